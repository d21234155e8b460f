//! Equirectangular pixels, angles and directions (DESIGN §2).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec3;

use super::camera::Basis;

/// An equirectangular image size; `width = 2 * height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Equirect {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Equirect {
    /// Narrowest image accepted, pixels.
    pub const MIN_WIDTH: u32 = 16;
    /// Widest image accepted, pixels.
    pub const MAX_WIDTH: u32 = 16384;

    /// `width` when it is even and within `MIN_WIDTH..=MAX_WIDTH` (the height is half of it).
    ///
    /// # Errors
    /// A message giving the rule.
    pub fn check_width(width: u32) -> Result<u32, String> {
        if (Self::MIN_WIDTH..=Self::MAX_WIDTH).contains(&width) && width.is_multiple_of(2) {
            Ok(width)
        } else {
            Err(format!(
                "the width must be even and within {}..={}, got {width}",
                Self::MIN_WIDTH,
                Self::MAX_WIDTH
            ))
        }
    }

    /// The image of width `width` and height `width / 2`.
    pub fn from_width(width: u32) -> Self {
        Equirect {
            width,
            height: width / 2,
        }
    }

    /// Longitude and latitude of continuous image position `(x, y)`; pixel `(i, j)` is
    /// sampled at `(i + 0.5, j + 0.5)`.
    #[inline]
    pub fn angles_of_position(&self, x: f64, y: f64) -> (f64, f64) {
        let u = x / self.width as f64;
        let v = y / self.height as f64;
        ((u - 0.5) * TAU, (0.5 - v) * PI)
    }

    /// Longitude and latitude of the centre of pixel `(i, j)`.
    #[inline]
    pub fn pixel_angles(&self, i: u32, j: u32) -> (f64, f64) {
        self.angles_of_position(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// Continuous image position of longitude `lam` (wrapped into [-pi, pi)) and latitude `phi`.
    #[inline]
    pub fn position_of_angles(&self, lam: f64, phi: f64) -> (f64, f64) {
        let lam = wrap_longitude(lam);
        let u = lam / TAU + 0.5;
        let v = 0.5 - phi / PI;
        (u * self.width as f64, v * self.height as f64)
    }
}

/// Wraps a longitude into [-pi, pi).
#[inline]
pub fn wrap_longitude(lam: f64) -> f64 {
    (lam + PI).rem_euclid(TAU) - PI
}

/// Unit direction of longitude `lam`, latitude `phi` in the camera frame `b`.
#[inline]
pub fn direction(b: &Basis, lam: f64, phi: f64) -> DVec3 {
    let (sl, cl) = lam.sin_cos();
    let (sp, cp) = phi.sin_cos();
    cp * (sl * b.right + cl * b.forward) + sp * b.up
}

/// Longitude of a (not necessarily unit) vector `v` in the camera frame `b`; 0 for vertical `v`.
#[inline]
pub fn longitude(b: &Basis, v: DVec3) -> f64 {
    v.dot(b.right).atan2(v.dot(b.forward))
}

/// Longitude and latitude of a non-zero vector `v` in the camera frame `b`.
#[inline]
pub fn angles(b: &Basis, v: DVec3) -> (f64, f64) {
    let x = v.dot(b.right);
    let y = v.dot(b.forward);
    let z = v.dot(b.up);
    (x.atan2(y), z.atan2(x.hypot(y)).clamp(-FRAC_PI_2, FRAC_PI_2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::Camera;

    #[test]
    fn centre_pixel_looks_forward_and_top_row_looks_up() {
        let e = Equirect::from_width(3840);
        let b = Camera::new(DVec3::ZERO, 30.0).basis();
        let (lam, phi) = e.angles_of_position(1920.0, 960.0);
        assert!((direction(&b, lam, phi) - b.forward).length() < 1e-12);
        let (_, phi) = e.pixel_angles(0, 0);
        assert!(phi > FRAC_PI_2 - PI / 1920.0);
        let (lam, _) = e.angles_of_position(2880.0, 960.0);
        assert!((direction(&b, lam, 0.0) - b.right).length() < 1e-12);
    }

    #[test]
    fn angles_invert_direction() {
        let b = Camera::new(DVec3::ZERO, -71.0).basis();
        for &(lam, phi) in &[(0.3, 0.2), (-3.1, -1.5), (3.1, 1.56), (-0.7, 0.0)] {
            let (l2, p2) = angles(&b, direction(&b, lam, phi));
            assert!((l2 - lam).abs() < 1e-12 && (p2 - phi).abs() < 1e-12);
        }
    }

    #[test]
    fn positions_wrap_across_the_seam() {
        let e = Equirect::from_width(100);
        let (x, _) = e.position_of_angles(PI + 0.01, 0.0);
        assert!(x < 1.0);
        assert!((wrap_longitude(-PI) + PI).abs() < 1e-15);
    }
}
