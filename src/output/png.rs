//! PNG: 8-bit sRGB RGBA. Alpha carries coverage (255 hit, 0 background, the covered fraction
//! when supersampled), so a PNG keeps the silhouette; viewers show the background as
//! transparent. Depth is not stored.

use std::io::Write;
use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::OutputError;
use super::description::{self, ImageDescription};
use super::xmp::{PhotoSphere, photo_sphere_packet, software};
use crate::frame::Frame;

/// The keyword of the iTXt chunk that holds an XMP packet.
pub const XMP_KEYWORD: &str = "XML:com.adobe.xmp";

/// Encodes `frame` as an RGBA PNG into `out`; `sphere` adds a Photo Sphere XMP packet (an
/// uncompressed iTXt chunk before the image data, where viewers look for it), `description`
/// a `tEXt` chunk holding it (with `Software`). `path` names the file in errors.
pub fn encode_png(
    frame: &Frame,
    sphere: Option<&PhotoSphere>,
    description: Option<&ImageDescription>,
    out: impl Write,
    path: &Path,
) -> Result<(), OutputError> {
    let err = |source| OutputError::PngEncode {
        path: path.to_path_buf(),
        source,
    };
    if frame.width == 0 || frame.height == 0 {
        return Err(OutputError::BadSize {
            path: path.to_path_buf(),
            width: frame.width,
            height: frame.height,
        });
    }
    let mut encoder = png::Encoder::new(out, frame.width, frame.height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    // Fast deflate, as the `image` crate's encoder uses: panoramas are large.
    encoder.set_compression(png::Compression::Fast);
    if let Some(s) = sphere {
        encoder
            .add_itxt_chunk(XMP_KEYWORD.to_owned(), photo_sphere_packet(s))
            .map_err(err)?;
    }
    if let Some(d) = description {
        encoder
            .add_text_chunk("Software".to_owned(), software())
            .map_err(err)?;
        encoder
            .add_text_chunk(description::KEY.to_owned(), d.to_string())
            .map_err(err)?;
    }
    let mut writer = encoder.write_header().map_err(err)?;
    writer
        .write_image_data(bytemuck::cast_slice(&frame.color))
        .map_err(err)?;
    writer.finish().map_err(err)
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
    Ok(Frame::from_rgba8(rgba))
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
