//! Red/cyan anaglyph previews of a stereo render.
//!
//! Both methods mix in linear light (the eyes' sRGB bytes are decoded, mixed, re-encoded) and
//! give an opaque RGB image whose background is black.

use std::path::{Path, PathBuf};

use image::RgbImage;

use super::OutputError;
use super::format::ImageFormat;
use super::png::write_png_buffer;
use crate::frame::{Frame, Rendered};
use crate::render::shading::{linear_to_srgb, srgb_to_linear};

/// How the two eyes are mixed into red and cyan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AnaglyphMethod {
    /// Half-colour: red = Rec. 709 luminance of the left eye, green and blue = the right eye's
    /// own green and blue. Keeps most colour, and using luminance for red avoids the retinal
    /// rivalry a saturated red object causes in a full-colour anaglyph. Each output channel
    /// depends on one eye only.
    #[default]
    HalfColor,
    /// Dubois' least-squares red/cyan matrices (Dubois 2001, as published on his site):
    /// better colour and less ghosting on typical red/cyan glasses; channels mix both eyes
    /// slightly (with negative weights), white stays white.
    Dubois,
}

/// Rec. 709 luminance weights of linear RGB.
const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// Dubois red/cyan matrix applied to the left eye (rows: output R, G, B).
const DUBOIS_LEFT: [[f32; 3]; 3] = [
    [0.437, 0.449, 0.164],
    [-0.062, -0.062, -0.024],
    [-0.048, -0.050, -0.017],
];

/// Dubois red/cyan matrix applied to the right eye.
const DUBOIS_RIGHT: [[f32; 3]; 3] = [
    [-0.011, -0.032, -0.007],
    [0.377, 0.761, 0.009],
    [-0.026, -0.093, 1.234],
];

fn linear(c: [u8; 4]) -> [f32; 3] {
    // Background pixels may carry any colour with alpha 0: they show as black; partly
    // covered (supersampled) pixels are laid over black.
    let a = c[3] as f32 / 255.0;
    if c[3] == 0 {
        return [0.0; 3];
    }
    [
        srgb_to_linear(c[0]) * a,
        srgb_to_linear(c[1]) * a,
        srgb_to_linear(c[2]) * a,
    ]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Mixes one pixel of each eye into an sRGB anaglyph pixel.
pub fn anaglyph_pixel(left: [u8; 4], right: [u8; 4], method: AnaglyphMethod) -> [u8; 3] {
    let (l, r) = (linear(left), linear(right));
    let out = match method {
        AnaglyphMethod::HalfColor => [dot(LUMA, l), r[1], r[2]],
        AnaglyphMethod::Dubois => {
            std::array::from_fn(|k| dot(DUBOIS_LEFT[k], l) + dot(DUBOIS_RIGHT[k], r))
        }
    };
    out.map(linear_to_srgb)
}

/// The anaglyph of two equally sized eye frames.
pub fn anaglyph(
    left: &Frame,
    right: &Frame,
    method: AnaglyphMethod,
    path: &Path,
) -> Result<RgbImage, OutputError> {
    if (left.width, left.height) != (right.width, right.height) {
        return Err(OutputError::EyeSizeMismatch {
            path: path.to_path_buf(),
            left: (left.width, left.height),
            right: (right.width, right.height),
        });
    }
    let bytes = left
        .color
        .iter()
        .zip(&right.color)
        .flat_map(|(&l, &r)| anaglyph_pixel(l, r, method))
        .collect();
    RgbImage::from_raw(left.width, left.height, bytes).ok_or(OutputError::BadSize {
        path: path.to_path_buf(),
        width: left.width,
        height: left.height,
    })
}

/// Writes the anaglyph preview of a stereo render as a `.png`, atomically.
pub fn write_anaglyph(
    path: &Path,
    rendered: &Rendered,
    method: AnaglyphMethod,
) -> Result<PathBuf, OutputError> {
    ImageFormat::require(path, ImageFormat::Png)?;
    let Rendered::Stereo { left, right } = rendered else {
        return Err(OutputError::NotStereo {
            what: "an anaglyph",
            path: path.to_path_buf(),
        });
    };
    let img = anaglyph(left, right, method, path)?;
    write_png_buffer(path, &img)?;
    Ok(path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dubois_keeps_white_and_black() {
        let w = anaglyph_pixel([255; 4], [255; 4], AnaglyphMethod::Dubois);
        for c in w {
            assert!(c >= 254, "{w:?}");
        }
        let b = anaglyph_pixel([0, 0, 0, 255], [0, 0, 0, 255], AnaglyphMethod::Dubois);
        assert_eq!(b, [0, 0, 0]);
    }

    #[test]
    fn half_color_grey_stays_grey() {
        let g = anaglyph_pixel(
            [90, 90, 90, 255],
            [90, 90, 90, 255],
            AnaglyphMethod::HalfColor,
        );
        assert_eq!(g, [90, 90, 90]);
    }
}
