//! Colour from the scanner's photos: an E57 image decoded with its projection, and where a
//! point of the file's frame falls in it.
//!
//! Image frames (their pose maps them to the file's frame, as a scan's does):
//! - spherical: columns run with azimuth (about +Z, from +X towards +Y), azimuth 0 at the
//!   middle column; rows run from +elevation at the top down, elevation 0 at the middle row;
//!   `pixelWidth`/`pixelHeight` are radians (DESIGN §12);
//! - cylindrical: columns as spherical; a row is a height on the cylinder of `radius` about
//!   +Z, row `principalY` at height 0, heights up towards the top, `pixelHeight` metres;
//! - pinhole: the camera looks along +Z, columns run with +X and rows with +Y from the
//!   principal point; a pixel is `pixelWidth` x `pixelHeight` metres on the image plane at
//!   `focalLength` metres.

use super::pose::Pose;
use glam::DVec3;

/// How an image maps directions of its frame to pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lens {
    /// Equirectangular: radians per pixel across and down.
    Spherical { pixel_width: f64, pixel_height: f64 },
    /// A cylinder about +Z: radians per pixel across, metres per pixel down.
    Cylindrical {
        radius: f64,
        principal_y: f64,
        pixel_width: f64,
        pixel_height: f64,
    },
    /// A pinhole camera looking along +Z.
    Pinhole {
        focal_length: f64,
        pixel_width: f64,
        pixel_height: f64,
        principal_x: f64,
        principal_y: f64,
    },
}

/// A decoded image with its lens and pose.
#[derive(Debug, Clone)]
pub struct Photo {
    /// The image's pose (camera frame to file frame).
    pub pose: Pose,
    /// Its projection.
    pub lens: Lens,
    /// Its pixels.
    pub pixels: image::RgbImage,
}

impl Photo {
    /// The pixel (column, row) where the point `world` (file frame) appears, `None` when it
    /// falls outside the image or behind a pinhole camera.
    pub fn pixel(&self, world: DVec3) -> Option<(u32, u32)> {
        let p = self.pose.inverse_apply(world);
        let (w, h) = (
            f64::from(self.pixels.width()),
            f64::from(self.pixels.height()),
        );
        let (column, row) = match self.lens {
            Lens::Spherical {
                pixel_width,
                pixel_height,
            } => {
                let azimuth = p.y.atan2(p.x);
                let elevation = p.z.atan2(p.x.hypot(p.y));
                (
                    w / 2.0 + azimuth / pixel_width,
                    h / 2.0 - elevation / pixel_height,
                )
            }
            Lens::Cylindrical {
                radius,
                principal_y,
                pixel_width,
                pixel_height,
            } => {
                let rho = p.x.hypot(p.y);
                if rho <= 0.0 {
                    return None;
                }
                (
                    w / 2.0 + p.y.atan2(p.x) / pixel_width,
                    principal_y - p.z * radius / rho / pixel_height,
                )
            }
            Lens::Pinhole {
                focal_length,
                pixel_width,
                pixel_height,
                principal_x,
                principal_y,
            } => {
                if p.z <= 0.0 {
                    return None;
                }
                (
                    principal_x + p.x / p.z * focal_length / pixel_width,
                    principal_y + p.y / p.z * focal_length / pixel_height,
                )
            }
        };
        let inside = column.is_finite()
            && row.is_finite()
            && (0.0..w).contains(&column)
            && (0.0..h).contains(&row);
        inside.then_some((column as u32, row as u32))
    }

    /// The colour at `world`, `None` where the image does not see it.
    pub fn colour(&self, world: DVec3) -> Option<[u8; 3]> {
        self.pixel(world)
            .map(|(c, r)| self.pixels.get_pixel(c, r).0)
    }
}

/// The colour of `world` from the nearest of `photos` (by distance to the camera) that sees
/// it.
pub fn colour_from(photos: &[Photo], world: DVec3) -> Option<[u8; 3]> {
    photos
        .iter()
        .filter_map(|p| {
            p.colour(world)
                .map(|c| (p.pose.translation.distance_squared(world), c))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

/// The lens of an E57 image's projection, with the blob holding its pixels.
pub fn lens(projection: &e57::Projection) -> (Lens, &e57::ImageBlob) {
    match projection {
        e57::Projection::Spherical(s) => (
            Lens::Spherical {
                pixel_width: s.properties.pixel_width,
                pixel_height: s.properties.pixel_height,
            },
            &s.blob,
        ),
        e57::Projection::Cylindrical(c) => (
            Lens::Cylindrical {
                radius: c.properties.radius,
                principal_y: c.properties.principal_y,
                pixel_width: c.properties.pixel_width,
                pixel_height: c.properties.pixel_height,
            },
            &c.blob,
        ),
        e57::Projection::Pinhole(p) => (
            Lens::Pinhole {
                focal_length: p.properties.focal_length,
                pixel_width: p.properties.pixel_width,
                pixel_height: p.properties.pixel_height,
                principal_x: p.properties.principal_x,
                principal_y: p.properties.principal_y,
            },
            &p.blob,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn photo(lens: Lens, w: u32, h: u32) -> Photo {
        Photo {
            pose: Pose::default(),
            lens,
            pixels: image::RgbImage::from_fn(w, h, |x, y| image::Rgb([x as u8, y as u8, 0])),
        }
    }

    #[test]
    fn spherical_centre_and_corners() {
        let pi = std::f64::consts::PI;
        let p = photo(
            Lens::Spherical {
                pixel_width: 2.0 * pi / 64.0,
                pixel_height: pi / 32.0,
            },
            64,
            32,
        );
        // +X is azimuth 0, elevation 0: the middle.
        assert_eq!(p.pixel(DVec3::X), Some((32, 16)));
        // +Y is a quarter turn to the right of the middle; slightly up is the row above.
        assert_eq!(p.pixel(DVec3::new(0.0, 1.0, 0.05)), Some((48, 15)));
        assert_eq!(
            p.pixel(DVec3::new(-1.0, -1e-9, -0.999)).map(|c| c.0),
            Some(0)
        );
    }

    #[test]
    fn pinhole_sees_forward_only() {
        let p = photo(
            Lens::Pinhole {
                focal_length: 0.01,
                pixel_width: 0.0005,
                pixel_height: 0.0005,
                principal_x: 20.0,
                principal_y: 15.0,
            },
            40,
            30,
        );
        assert_eq!(p.pixel(DVec3::Z), Some((20, 15)));
        // 0.5 m right at 10 m: 0.05 × 20 px per unit = 1 px right.
        assert_eq!(p.pixel(DVec3::new(0.5, 0.0, 10.0)), Some((21, 15)));
        assert_eq!(p.pixel(-DVec3::Z), None);
        assert_eq!(
            p.pixel(DVec3::new(10.0, 0.0, 1.0)),
            None,
            "outside the frame"
        );
    }
}
