//! OpenEXR: 32-bit float channels `R`, `G`, `B` (linear light, premultiplied by coverage),
//! `A` (coverage) and `Z` (distance along the ray in metres, `+inf` for background); or `Z`
//! alone for depth-only files. A full equirect panorama is marked as a latitude-longitude
//! environment map (`envmap`); every file carries its description (`omnicloud`) and the
//! software; an ODS pair is one multi-view file (left, right).

use std::io::{Seek, Write};
use std::path::Path;

use exr::meta::attribute::{AttributeValue, EnvironmentMap};
use exr::prelude::{
    AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SpecificChannels, Text,
    WritableImage,
};

use super::description::{self, ImageDescription, StoredEyes};
use super::linear_image::linear_pixel;
use super::xmp::software;
use super::{LinearImage, OutputError};
use crate::frame::Frame;
use crate::projection::Projection;

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

/// The views of an EXR file: one panorama, or an ODS pair stored as a multi-view file.
#[derive(Debug, Clone, Copy)]
pub enum ExrViews<'a> {
    /// One equirectangular panorama.
    Mono(&'a Frame),
    /// Left and right eye: OpenEXR multi-view (`multiView` = left, right), the left eye's
    /// channels unprefixed (`R`, …, `Z`, what single-view readers show), the right eye's as
    /// `right.R`, …, `right.Z`.
    Stereo {
        /// Left eye (the default view).
        left: &'a Frame,
        /// Right eye.
        right: &'a Frame,
    },
}

/// The name of the second view of a stereo file.
pub const RIGHT_VIEW: &str = "right";

/// Layer attributes: the file's [`ImageDescription`] and the software; a full panorama is a
/// latitude-longitude environment map; a stereo file also names its views.
fn attributes(stereo: bool, description: &ImageDescription) -> LayerAttributes {
    let mut a = LayerAttributes {
        environment_map: description
            .is_panorama()
            .then_some(EnvironmentMap::LatitudeLongitude),
        software_name: Some(Text::from(software().as_str())),
        ..LayerAttributes::default()
    };
    a.other.insert(
        Text::from(description::KEY),
        AttributeValue::Text(Text::from(description.to_string().as_str())),
    );
    if stereo {
        a.multi_view_names = Some(vec![Text::from("left"), Text::from(RIGHT_VIEW)]);
    }
    a
}

/// Encodes `views` (full equirectangular panoramas) as a single-part EXR into `out`; `path`
/// names the file in errors.
pub fn encode_exr(
    views: ExrViews<'_>,
    content: ExrContent,
    out: impl Write + Seek,
    path: &Path,
) -> Result<(), OutputError> {
    let eyes = match views {
        ExrViews::Mono(_) => StoredEyes::Mono,
        ExrViews::Stereo { .. } => StoredEyes::TopBottom,
    };
    let description = ImageDescription {
        projection: Projection::EQUIRECT,
        eyes,
        metres_per_unit: None,
    };
    encode_exr_with(views, content, &description, out, path)
}

/// [`encode_exr`] for any projection, described by `description` (whose eyes must match
/// `views`): only a full 360° x 180° equirect is marked a latitude-longitude environment map.
pub fn encode_exr_with(
    views: ExrViews<'_>,
    content: ExrContent,
    description: &ImageDescription,
    out: impl Write + Seek,
    path: &Path,
) -> Result<(), OutputError> {
    let (left, right) = match views {
        ExrViews::Mono(f) => (f, None),
        ExrViews::Stereo { left, right } => (left, Some(right)),
    };
    if left.width == 0 || left.height == 0 {
        return Err(OutputError::BadSize {
            path: path.to_path_buf(),
            width: left.width,
            height: left.height,
        });
    }
    if let Some(r) = right
        && (r.width, r.height) != (left.width, left.height)
    {
        return Err(OutputError::EyeSizeMismatch {
            path: path.to_path_buf(),
            left: (left.width, left.height),
            right: (r.width, r.height),
        });
    }
    let size = (left.width as usize, left.height as usize);
    let at = move |p: exr::math::Vec2<usize>| p.x() + p.y() * left.width as usize;
    let color = |f: &Frame, k: usize| {
        let (rgb, a) = linear_pixel(f.color[k]);
        (a, rgb[2], rgb[1], rgb[0], f.depth[k])
    };
    // ZIP keeps float data lossless and compresses the large constant background well.
    // Samples are computed per block as the encoder asks, so no full-size float copy of the
    // frame is ever held (20 bytes a pixel at five channels).
    let encoding = Encoding::SMALL_LOSSLESS;
    let attrs = attributes(right.is_some(), description);
    let write = |layer_result: Result<(), exr::error::Error>| layer_result.map_err(exr_error(path));
    // Channels are listed in the sorted order OpenEXR stores them in.
    match (content, right) {
        (ExrContent::ColorAndDepth, None) => {
            let channels = SpecificChannels::build()
                .with_channel("A")
                .with_channel("B")
                .with_channel("G")
                .with_channel("R")
                .with_channel("Z")
                .with_pixel_fn(|p| color(left, at(p)));
            write(
                Image::from_layer(Layer::new(size, attrs, encoding, channels))
                    .write()
                    .to_buffered(out),
            )
        }
        (ExrContent::ColorAndDepth, Some(right)) => {
            let channels = SpecificChannels::build()
                .with_channel("A")
                .with_channel("B")
                .with_channel("G")
                .with_channel("R")
                .with_channel("Z")
                .with_channel("right.A")
                .with_channel("right.B")
                .with_channel("right.G")
                .with_channel("right.R")
                .with_channel("right.Z")
                .with_pixel_fn(|p| {
                    let k = at(p);
                    let (a, b, g, r, z) = color(left, k);
                    let (ra, rb, rg, rr, rz) = color(right, k);
                    (a, b, g, r, z, ra, rb, rg, rr, rz)
                });
            write(
                Image::from_layer(Layer::new(size, attrs, encoding, channels))
                    .write()
                    .to_buffered(out),
            )
        }
        (ExrContent::DepthOnly, None) => {
            let channels = SpecificChannels::build()
                .with_channel("Z")
                .with_pixel_fn(|p| (left.depth[at(p)],));
            write(
                Image::from_layer(Layer::new(size, attrs, encoding, channels))
                    .write()
                    .to_buffered(out),
            )
        }
        (ExrContent::DepthOnly, Some(right)) => {
            let channels = SpecificChannels::build()
                .with_channel("Z")
                .with_channel("right.Z")
                .with_pixel_fn(|p| {
                    let k = at(p);
                    (left.depth[k], right.depth[k])
                });
            write(
                Image::from_layer(Layer::new(size, attrs, encoding, channels))
                    .write()
                    .to_buffered(out),
            )
        }
    }
}

/// Reads the first layer of an EXR file. Missing `R`/`G`/`B` read as 0; a missing `Z` as
/// `+inf`; a missing `A` is derived from `Z` (finite = hit). A file with neither `A` nor `Z`
/// is an error. A multi-view file's first two views come back stacked top-bottom (first view
/// on top), the layout of a top-bottom ODS pair.
pub fn read_exr(path: &Path) -> Result<LinearImage, OutputError> {
    check_exr_size(path)?;
    let image = exr::prelude::read_first_flat_layer_from_file(path).map_err(exr_error(path))?;
    let layer = &image.layer_data;
    let views = layer.attributes.multi_view_names.as_deref().unwrap_or(&[]);
    if views.len() < 2 {
        return read_view(layer, "", path);
    }
    // The first (default) view's channels may be unprefixed; the others carry `view.`.
    let first = format!("{}.", views[0]);
    let has_prefixed_first = layer
        .channel_data
        .list
        .iter()
        .any(|c| c.name.to_string().starts_with(&first));
    let mut top = read_view(layer, if has_prefixed_first { &first } else { "" }, path)?;
    let bottom = read_view(layer, &format!("{}.", views[1]), path)?;
    top.height += bottom.height;
    top.color.extend(bottom.color);
    top.coverage.extend(bottom.coverage);
    top.depth.extend(bottom.depth);
    Ok(top)
}

/// Most pixels a part of an EXR file read here may declare: 16384 x 16384, the largest image
/// omnicloud writes (a top-bottom pair at the widest `--width`). The decoder allocates a
/// block's declared size before inflating it (found by fuzzing: a 1 kB frame whose header
/// declared a 2^29-pixel-wide image asked for 110 GB).
const MAX_EXR_PIXELS: u64 = 1 << 28;

/// Most raw bytes a part may declare per byte of the file: above what any EXR compression
/// reaches (run-length then deflate on a constant image). A 1.3 kB frame declaring 6,094,864
/// x 8 pixels (found by fuzzing) otherwise took 1.75 GB and seconds to decode.
const MAX_EXR_EXPANSION: u64 = 1 << 16;

/// Refuses a file whose header declares more than [`MAX_EXR_PIXELS`] in a part, or more raw
/// bytes than [`MAX_EXR_EXPANSION`] times the file's size, before any pixel is decoded.
fn check_exr_size(path: &Path) -> Result<(), OutputError> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(exr_error(path))?;
    let file_len = std::fs::metadata(path)
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            action: "reading",
            source,
        })?
        .len();
    for header in &meta.headers {
        let size = header.layer_size;
        let pixels = (size.width() as u64).saturating_mul(size.height() as u64);
        let raw = pixels.saturating_mul(header.channels.bytes_per_pixel as u64);
        let reason = if pixels > MAX_EXR_PIXELS {
            format!("more than the {MAX_EXR_PIXELS} read here")
        } else if raw > file_len.saturating_mul(MAX_EXR_EXPANSION) {
            format!("{raw} bytes, more than a {file_len}-byte file can hold")
        } else {
            continue;
        };
        return Err(OutputError::Exr {
            path: path.to_path_buf(),
            source: exr::error::Error::Invalid(
                format!(
                    "the header declares {} x {} pixels, {reason}",
                    size.width(),
                    size.height()
                )
                .into(),
            ),
        });
    }
    Ok(())
}

/// A layer as the reader gives it: any channels, flat samples.
type FlatLayer = Layer<AnyChannels<FlatSamples>>;

/// The channels `{prefix}R`, `{prefix}G`, … of a flat layer as one image.
fn read_view(layer: &FlatLayer, prefix: &str, path: &Path) -> Result<LinearImage, OutputError> {
    let (w, h) = (layer.size.width(), layer.size.height());
    let n = w * h;
    let channel = |name: &str| -> Option<Vec<f32>> {
        let full = format!("{prefix}{name}");
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(full.as_str()))
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
