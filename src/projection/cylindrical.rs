//! The cylindrical (central) projection: full longitude, latitude through `tan` (DESIGN §8).

use std::f64::consts::{PI, TAU};

/// Image height for `width` and vertical field of view `vfov` (radians):
/// `round(W tan(VFOV/2) / pi)`.
pub fn height(width: u32, vfov: f64) -> u32 {
    (f64::from(width) * (0.5 * vfov).tan() / PI).round() as u32
}

/// Longitude and latitude seen at continuous image position `(u, v)` in `[0, 1]^2`.
#[inline]
pub fn angles(u: f64, v: f64, vfov: f64) -> (f64, f64) {
    (
        (u - 0.5) * TAU,
        ((1.0 - 2.0 * v) * (0.5 * vfov).tan()).atan(),
    )
}

/// Image position `(u, v)` of longitude `lam` in `[-pi, pi)`, latitude `phi` (|phi| < pi/2).
#[inline]
pub fn position(lam: f64, phi: f64, vfov: f64) -> (f64, f64) {
    (
        lam / TAU + 0.5,
        (1.0 - phi.tan() / (0.5 * vfov).tan()) / 2.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_edge_is_half_the_field_of_view() {
        let vfov = 90f64.to_radians();
        assert_eq!(height(3600, vfov), 1146);
        let (lam, phi) = angles(0.5, 0.0, vfov);
        assert!(lam.abs() < 1e-15 && (phi - vfov / 2.0).abs() < 1e-12);
        let (u, v) = position(1.0, 0.3, vfov);
        let (lam, phi) = angles(u, v, vfov);
        assert!((lam - 1.0).abs() < 1e-12 && (phi - 0.3).abs() < 1e-12);
    }
}
