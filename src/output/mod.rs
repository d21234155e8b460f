//! Writing frames: PNG, OpenEXR, ODS layouts and anaglyph previews; reading EXR back.
//!
//! - PNG: 8-bit sRGB **RGBA**; alpha is coverage (background stays transparent), no depth.
//! - EXR: float `R`,`G`,`B` (linear, premultiplied), `A` (coverage), `Z` (metres along the
//!   ray, `+inf` background); `--depth` files hold `Z` only.
//! - Stereo: one top-bottom file (left eye on top), or `NAME_left.ext` + `NAME_right.ext`.
//! - Every file is written to a hidden temporary name in its directory and renamed into
//!   place, so an interrupted render leaves no half-written output.

pub mod anaglyph;
pub mod atomic;
mod error;
pub mod exr;
pub mod format;
pub mod layout;
pub mod linear_image;
pub mod png;

pub use anaglyph::{AnaglyphMethod, anaglyph, write_anaglyph};
pub use atomic::{StagedFile, remove_staged_files, write_atomically};
pub use error::OutputError;
pub use exr::{ExrContent, read_exr};
pub use format::ImageFormat;
pub use layout::{Layout, eye_path, write_depth, write_image};
pub use linear_image::LinearImage;
pub use png::{read_png, write_png_buffer};

use std::path::Path;

/// Reads an image for comparison by extension: EXR (colour, coverage, depth) or PNG (colour
/// and coverage from alpha, depth unknown = `+inf`).
pub fn read_image(path: &Path) -> Result<LinearImage, OutputError> {
    match ImageFormat::from_path(path)? {
        ImageFormat::Exr => read_exr(path),
        ImageFormat::Png => Ok(LinearImage::from_frame(&read_png(path)?)),
    }
}
