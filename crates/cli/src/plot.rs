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
