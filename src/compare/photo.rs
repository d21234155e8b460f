//! A scanner's own panorama as the reference of a comparison: an E57 image resampled into
//! the equirectangular frame of a render from its station (`render --camera station:N`),
//! transparent where the image does not reach.

use std::path::Path;

use image::RgbaImage;

use super::CompareError;
use crate::projection::Camera;
use crate::projection::equirect::{self, Equirect};

/// E57 image `index` of `path` as a mono equirectangular image `width` wide (height half
/// of it), seen from the image's position with its station's heading (DESIGN §12).
///
/// # Errors
/// The file's errors, or an image without projection.
pub fn station_reference(path: &Path, index: usize, width: u32) -> Result<RgbaImage, CompareError> {
    let (photo, yaw) = crate::io::e57::read_photo(path, index)?;
    let size = Equirect::from_width(width);
    let basis = Camera::new(photo.pose.translation, yaw).basis();
    Ok(RgbaImage::from_fn(size.width, size.height, |i, j| {
        let (lam, phi) = size.pixel_angles(i, j);
        let d = equirect::direction(&basis, lam, phi);
        match photo.colour(photo.pose.translation + d) {
            Some([r, g, b]) => image::Rgba([r, g, b, 255]),
            None => image::Rgba([0, 0, 0, 0]),
        }
    }))
}
