//! OpenEXR: 32-bit float channels `R`, `G`, `B` (linear light, premultiplied by coverage),
//! `A` (coverage) and `Z` (distance along the ray in metres, `+inf` for background); or `Z`
//! alone for depth-only files.

use std::io::{Seek, Write};
use std::path::Path;

use exr::prelude::{Encoding, Image, Layer, LayerAttributes, SpecificChannels, WritableImage};

use super::linear_image::linear_pixel;
use super::{LinearImage, OutputError};
use crate::frame::Frame;

/// Which channels an EXR file gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExrContent {
    /// `R`, `G`, `B`, `A`, `Z`.
    ColorAndDepth,
    /// `Z` only.
    DepthOnly,
}

fn exr_error(path: &Path) -> impl FnOnce(exr::error::Error) -> OutputError + '_ {
    move |source| OutputError::Exr {
        path: path.to_path_buf(),
        source,
    }
}

/// Encodes `frame` as a single-layer EXR into `out`; `path` names the file in errors.
pub fn encode_exr(
    frame: &Frame,
    content: ExrContent,
    out: impl Write + Seek,
    path: &Path,
) -> Result<(), OutputError> {
    if frame.width == 0 || frame.height == 0 {
        return Err(OutputError::BadSize {
            path: path.to_path_buf(),
            width: frame.width,
            height: frame.height,
        });
    }
    let size = (frame.width as usize, frame.height as usize);
    let at = move |p: exr::math::Vec2<usize>| p.x() + p.y() * frame.width as usize;
    // ZIP keeps float data lossless and compresses the large constant background well.
    // Samples are computed per block as the encoder asks, so no full-size float copy of the
    // frame is ever held (20 bytes a pixel at five channels).
    let encoding = Encoding::SMALL_LOSSLESS;
    match content {
        ExrContent::ColorAndDepth => {
            let channels = SpecificChannels::build()
                .with_channel("A")
                .with_channel("B")
                .with_channel("G")
                .with_channel("R")
                .with_channel("Z")
                .with_pixel_fn(|p| {
                    let k = at(p);
                    let (rgb, a) = linear_pixel(frame.color[k]);
                    (a, rgb[2], rgb[1], rgb[0], frame.depth[k])
                });
            Image::from_layer(Layer::new(
                size,
                LayerAttributes::default(),
                encoding,
                channels,
            ))
            .write()
            .to_buffered(out)
            .map_err(exr_error(path))
        }
        ExrContent::DepthOnly => {
            let channels = SpecificChannels::build()
                .with_channel("Z")
                .with_pixel_fn(|p| (frame.depth[at(p)],));
            Image::from_layer(Layer::new(
                size,
                LayerAttributes::default(),
                encoding,
                channels,
            ))
            .write()
            .to_buffered(out)
            .map_err(exr_error(path))
        }
    }
}

/// Reads the first layer of an EXR file. Missing `R`/`G`/`B` read as 0; a missing `Z` as
/// `+inf`; a missing `A` is derived from `Z` (finite = hit). A file with neither `A` nor `Z`
/// is an error.
pub fn read_exr(path: &Path) -> Result<LinearImage, OutputError> {
    let image = exr::prelude::read_first_flat_layer_from_file(path).map_err(exr_error(path))?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let n = w * h;
    let channel = |name: &str| -> Option<Vec<f32>> {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(name))
            .map(|c| c.sample_data.values_as_f32().collect())
    };
    let zeros = || vec![0.0f32; n];
    let (r, g, b) = (
        channel("R").unwrap_or_else(zeros),
        channel("G").unwrap_or_else(zeros),
        channel("B").unwrap_or_else(zeros),
    );
    let z = channel("Z");
    let coverage = match (channel("A"), &z) {
        (Some(a), _) => a,
        (None, Some(z)) => z.iter().map(|d| d.is_finite() as u8 as f32).collect(),
        (None, None) => {
            return Err(OutputError::NoCoverage {
                path: path.to_path_buf(),
            });
        }
    };
    let color = (0..n).map(|k| [r[k], g[k], b[k]]).collect();
    Ok(LinearImage {
        width: w as u32,
        height: h as u32,
        color,
        coverage,
        depth: z.unwrap_or_else(|| vec![f32::INFINITY; n]),
    })
}
