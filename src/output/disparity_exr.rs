//! OpenEXR disparity images: 32-bit float channels `disparity.h` and `disparity.v`
//! (arcminutes, NaN where a pixel has no disparity), with the unit and sign convention as
//! string attributes. Written atomically like every output.

use std::io::{Seek, Write};
use std::path::Path;

use exr::meta::attribute::AttributeValue;
use exr::prelude::{
    Encoding, Image, Layer, LayerAttributes, SpecificChannels, Text, WritableImage,
};

use super::{OutputError, write_atomically};
use crate::projection::disparity_image::DisparityImage;

/// Horizontal disparity channel.
pub const CHANNEL_H: &str = "disparity.h";
/// Vertical disparity channel.
pub const CHANNEL_V: &str = "disparity.v";
/// Attribute naming the channels' unit.
pub const UNIT_ATTRIBUTE: &str = "disparityUnit";
/// The unit written.
pub const UNIT: &str = "arcminutes";
/// Attribute stating the sign convention.
pub const CONVENTION_ATTRIBUTE: &str = "disparityConvention";
/// The convention written (DESIGN §9).
pub const CONVENTION: &str = "h = wrap(lamL - lamR), v = phiL - phiR of the left-eye pixel's surface point; \
     h > 0 nearer than infinity; NaN = no disparity";

fn exr_error(path: &Path) -> impl FnOnce(exr::error::Error) -> OutputError + '_ {
    move |source| OutputError::Exr {
        path: path.to_path_buf(),
        source,
    }
}

/// Encodes `img` as a single-layer EXR into `out`; `path` names the file in errors.
pub fn encode_disparity_exr(
    img: &DisparityImage,
    out: impl Write + Seek,
    path: &Path,
) -> Result<(), OutputError> {
    let n = img.width as usize * img.height as usize;
    if n == 0 || img.dh.len() != n || img.dv.len() != n {
        return Err(OutputError::BadSize {
            path: path.to_path_buf(),
            width: img.width,
            height: img.height,
        });
    }
    let mut attrs = LayerAttributes::default();
    for (name, value) in [(UNIT_ATTRIBUTE, UNIT), (CONVENTION_ATTRIBUTE, CONVENTION)] {
        attrs
            .other
            .insert(Text::from(name), AttributeValue::Text(Text::from(value)));
    }
    let width = img.width as usize;
    let channels = SpecificChannels::build()
        .with_channel(CHANNEL_H)
        .with_channel(CHANNEL_V)
        .with_pixel_fn(|p| {
            let k = p.x() + p.y() * width;
            (img.dh[k], img.dv[k])
        });
    let size = (width, img.height as usize);
    Image::from_layer(Layer::new(size, attrs, Encoding::SMALL_LOSSLESS, channels))
        .write()
        .to_buffered(out)
        .map_err(exr_error(path))
}

/// Writes `img` to `path` (see the module docs).
pub fn write_disparity_exr(path: &Path, img: &DisparityImage) -> Result<(), OutputError> {
    write_atomically(path, |w| encode_disparity_exr(img, w, path))
}

/// Reads a disparity EXR written by [`write_disparity_exr`].
///
/// # Errors
/// The file is unreadable, lacks `disparity.h` or `disparity.v`, or names a unit other
/// than arcminutes.
pub fn read_disparity_exr(path: &Path) -> Result<DisparityImage, OutputError> {
    let image = exr::prelude::read_first_flat_layer_from_file(path).map_err(exr_error(path))?;
    let layer = &image.layer_data;
    let not_disparity = |what: String| OutputError::NotDisparity {
        path: path.to_path_buf(),
        what,
    };
    if let Some(unit) = layer.attributes.other.get(&Text::from(UNIT_ATTRIBUTE)) {
        match unit {
            AttributeValue::Text(t) if t.eq(UNIT) => {}
            other => return Err(not_disparity(format!("unit {other:?}, expected `{UNIT}`"))),
        }
    }
    let channel = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(name))
            .map(|c| c.sample_data.values_as_f32().collect::<Vec<f32>>())
            .ok_or_else(|| not_disparity(format!("no `{name}` channel")))
    };
    Ok(DisparityImage {
        width: layer.size.width() as u32,
        height: layer.size.height() as u32,
        dh: channel(CHANNEL_H)?,
        dv: channel(CHANNEL_V)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_values_and_nan() {
        let (w, h) = (16u32, 8u32);
        let n = (w * h) as usize;
        let dh: Vec<f32> = (0..n)
            .map(|k| {
                if k % 5 == 0 {
                    f32::NAN
                } else {
                    110.0126 - k as f32 * 0.37
                }
            })
            .collect();
        let dv: Vec<f32> = (0..n)
            .map(|k| {
                if k % 5 == 0 {
                    f32::NAN
                } else {
                    (k as f32 * 0.01).sin()
                }
            })
            .collect();
        let img = DisparityImage {
            width: w,
            height: h,
            dh,
            dv,
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("disparity.exr");
        write_disparity_exr(&path, &img).unwrap();
        let back = read_disparity_exr(&path).unwrap();
        assert_eq!((back.width, back.height), (w, h));
        for k in 0..n {
            for (a, b) in [(img.dh[k], back.dh[k]), (img.dv[k], back.dv[k])] {
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "{k}: {a} {b}"
                );
            }
        }
        assert_eq!(back.dh.iter().filter(|d| d.is_nan()).count(), n.div_ceil(5));
        // Only the file itself is left in the folder (the temporary one was renamed).
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
        let unit = &meta.headers[0].own_attributes.other[&Text::from(UNIT_ATTRIBUTE)];
        assert_eq!(unit, &AttributeValue::Text(Text::from(UNIT)));
    }

    #[test]
    fn bad_sizes_and_other_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.exr");
        let img = DisparityImage {
            width: 4,
            height: 2,
            dh: vec![0.0; 7],
            dv: vec![0.0; 8],
        };
        let e = write_disparity_exr(&path, &img).unwrap_err();
        assert!(matches!(e, OutputError::BadSize { .. }), "{e}");
        assert!(!path.exists());
        // A depth-only EXR has no disparity channels.
        let frame = crate::frame::Frame::new(4, 2);
        let depth = dir.path().join("z.exr");
        crate::output::write_atomically(&depth, |w| {
            crate::output::exr::encode_exr(
                crate::output::ExrViews::Mono(&frame),
                crate::output::ExrContent::DepthOnly,
                w,
                &depth,
            )
        })
        .unwrap();
        let e = read_disparity_exr(&depth).unwrap_err().to_string();
        assert!(
            e.contains("not a disparity EXR: no `disparity.h` channel"),
            "{e}"
        );
    }
}
