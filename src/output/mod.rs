//! Writing frames: PNG, JPEG, VR photo, OpenEXR, ODS layouts and anaglyph previews, with
//! the metadata 360° players read; reading images back for comparison.
//!
//! - PNG: 8-bit sRGB **RGBA**; alpha is coverage (background stays transparent), no depth.
//! - JPEG: 8-bit sRGB, background black, no depth.
//! - `.vr.jpg`: Google's VR Photo, the right eye inside the left eye's XMP.
//! - EXR: float `R`,`G`,`B` (linear, premultiplied), `A` (coverage), `Z` (metres along the
//!   ray, `+inf` background); `--depth` files hold `Z` only.
//! - Stereo: one top-bottom PNG/JPEG (left eye on top), one multi-view EXR, or
//!   `NAME_left.ext` + `NAME_right.ext`.
//! - Metadata: Photo Sphere XMP on full panoramas ([`xmp`]), EXIF in JPEG, `envmap` in EXR;
//!   every PNG, JPEG and EXR render names its projection and eyes ([`description`]).
//! - Every file is written to a hidden temporary name in its directory and renamed into
//!   place, so an interrupted render leaves no half-written output.

pub mod anaglyph;
pub mod atomic;
pub mod description;
pub mod disparity_exr;
mod error;
pub mod exif;
pub mod exr;
pub mod format;
pub mod jpeg;
pub mod layout;
pub mod linear_image;
pub mod png;
pub mod xmp;

pub use anaglyph::{AnaglyphMethod, anaglyph, write_anaglyph};
pub use atomic::{ScratchDir, StagedFile, remove_staged_files, write_atomically};
pub use description::{ImageDescription, StereoLayout, StoredEyes, read_description};
pub use error::OutputError;
pub use exr::{ExrContent, ExrViews, read_exr};
pub use format::ImageFormat;
pub use jpeg::read_vr_jpeg;
pub use layout::{
    Layout, OutputOptions, eye_path, write_depth, write_depth_with, write_image, write_image_with,
};
pub use linear_image::LinearImage;
pub use png::{read_png, write_png_buffer};

use std::path::Path;

/// Reads an image for comparison by extension: EXR (colour, coverage, depth; a multi-view
/// pair top-bottom), PNG (colour and coverage from alpha, depth unknown = `+inf`), JPEG (all
/// covered) or a VR photo (both eyes, top-bottom).
pub fn read_image(path: &Path) -> Result<LinearImage, OutputError> {
    match ImageFormat::from_path(path)? {
        ImageFormat::Exr => read_exr(path),
        ImageFormat::Png => Ok(LinearImage::from_frame(&read_png(path)?)),
        // The decoder is chosen by content; only the error should name the right format.
        ImageFormat::Jpeg => match read_png(path) {
            Ok(frame) => Ok(LinearImage::from_frame(&frame)),
            Err(OutputError::Png { path, source }) => Err(OutputError::Jpeg { path, source }),
            Err(e) => Err(e),
        },
        ImageFormat::VrJpeg => Ok(LinearImage::from_frame(&read_vr_jpeg(path)?.top_bottom())),
    }
}
