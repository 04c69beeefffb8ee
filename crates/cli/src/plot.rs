//! What every plot shares: the file type from the extension.

/// The file types the plots are written as: the extensions (any case) and what they are.
pub const PLOT_FORMATS: [(&str, &str); 2] = [("svg", "SVG"), ("png", "PNG")];

/// The format of a plot file by its extension (`svg` or `png`, any case); `None` for any
/// other extension or none.
pub fn format_of(path: &std::path::Path) -> Option<&'static str> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    PLOT_FORMATS
        .iter()
        .find(|(e, _)| *e == ext)
        .map(|(e, _)| *e)
}

/// Refuses a plot path (given with `flag`) whose extension is not one the plotter writes, so
/// that a `.bmp` or `.pdf` never holds SVG text: bad input naming the flag, the path and the
/// allowed extensions. Call it before any work.
pub fn check_path(flag: &str, path: &std::path::Path) -> anyhow::Result<()> {
    if format_of(path).is_some() {
        return Ok(());
    }
    let ext = path.extension().map_or_else(
        || "no extension".to_owned(),
        |e| format!("`.{}`", e.to_string_lossy()),
    );
    let allowed: Vec<String> = PLOT_FORMATS
        .iter()
        .map(|(e, what)| format!(".{e} ({what})"))
        .collect();
    Err(crate::error::input_error(format!(
        "{flag} `{}` has {ext}; the plotter writes {} only: give the file one of these extensions",
        path.display(),
        allowed.join(" or ")
    )))
}

/// Calls `draw(root, args...)` with a drawing area of `size` pixels on the file at `path`: a
/// PNG when the extension is `png`, an SVG when it is `svg` (any case); any other extension
/// is refused ([`check_path`]). (A macro because the drawing function is generic over the
/// backend.)
macro_rules! render {
    ($path:expr, $size:expr, $draw:ident($($arg:expr),* $(,)?)) => {{
        let path: &std::path::Path = $path.as_ref();
        let format = crate::plot::format_of(path);
        if format.is_none() {
            crate::plot::check_path("plot", path)
        } else if format == Some("png") {
            $draw(
                plotters::prelude::BitMapBackend::new(path, $size).into_drawing_area(),
                $($arg),*
            )
        } else {
            $draw(
                plotters::prelude::SVGBackend::new(path, $size).into_drawing_area(),
                $($arg),*
            )
        }
    }};
}

pub(crate) use render;

/// A drawing error as the CLI reports it.
pub fn draw_error<E: std::error::Error + Send + Sync>(
    x: plotters::drawing::DrawingAreaErrorKind<E>,
) -> anyhow::Error {
    anyhow::anyhow!("cannot draw the plot: {x}")
}

/// Fills `root` white and puts `title` at its top in a `font_px` sans-serif; returns the area
/// below the title.
pub fn titled_white<DB: plotters::prelude::DrawingBackend>(
    root: plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    font_px: u32,
) -> anyhow::Result<plotters::prelude::DrawingArea<DB, plotters::coord::Shift>>
where
    DB::ErrorType: 'static,
{
    root.fill(&plotters::prelude::WHITE).map_err(draw_error)?;
    root.titled(title, ("sans-serif", font_px))
        .map_err(draw_error)
}
