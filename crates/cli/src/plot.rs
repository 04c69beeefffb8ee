//! What every plot shares: the file type from the extension.

/// Calls `draw(root, args...)` with a drawing area of `size` pixels on the file at `path`: a
/// PNG when the extension is `png`, an SVG otherwise. (A macro because the drawing function
/// is generic over the backend.)
macro_rules! render {
    ($path:expr, $size:expr, $draw:ident($($arg:expr),* $(,)?)) => {{
        let path: &std::path::Path = $path.as_ref();
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
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
