//! PNG: 8-bit sRGB RGBA. Alpha carries coverage (255 hit, 0 background), so a PNG keeps the
//! silhouette; viewers show the background as transparent. Depth is not stored.

use std::io::Write;
use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::OutputError;
use crate::frame::Frame;

/// Encodes `frame` as an RGBA PNG into `out`; `path` names the file in errors.
pub fn encode_png(frame: &Frame, out: impl Write, path: &Path) -> Result<(), OutputError> {
    let bytes: &[u8] = bytemuck::cast_slice(&frame.color);
    PngEncoder::new(out)
        .write_image(
            bytes,
            frame.width,
            frame.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|source| OutputError::Png {
            path: path.to_path_buf(),
            source,
        })
}

/// Reads a PNG into a frame: colour and coverage from RGBA (an opaque PNG counts as all hit),
/// depth unknown (`+inf` everywhere).
pub fn read_png(path: &Path) -> Result<Frame, OutputError> {
    let png_err = |source| OutputError::Png {
        path: path.to_path_buf(),
        source,
    };
    let reader = image::ImageReader::open(path).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        action: "opening",
        source,
    })?;
    let rgba = reader
        .with_guessed_format()
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            action: "reading",
            source,
        })?
        .decode()
        .map_err(png_err)?
        .into_rgba8();
    let (width, height) = rgba.dimensions();
    let color: Vec<[u8; 4]> = rgba.pixels().map(|p| p.0).collect();
    Ok(Frame {
        width,
        height,
        depth: vec![f32::INFINITY; color.len()],
        color,
    })
}

/// Writes an 8-bit RGB or RGBA buffer (an anaglyph, a heatmap) as a PNG, atomically.
pub fn write_png_buffer<P>(
    path: &Path,
    img: &image::ImageBuffer<P, Vec<u8>>,
) -> Result<(), OutputError>
where
    P: image::Pixel<Subpixel = u8> + image::PixelWithColorType,
{
    super::atomic::write_atomically(path, |w| {
        PngEncoder::new(w)
            .write_image(img.as_raw(), img.width(), img.height(), P::COLOR_TYPE)
            .map_err(|source| OutputError::Png {
                path: path.to_path_buf(),
                source,
            })
    })
}
