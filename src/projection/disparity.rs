//! Angular disparity of a stereo pair and what it implies (DESIGN §9).
//!
//! A surface point `P` is projected into both eyes with the views' own inverse; the
//! horizontal disparity `dh = wrap(lamL - lamR)` is positive for points nearer than infinity,
//! the vertical one is `dv = phiL - phiR`. For plain ODS `dh = 2 asin(r/rho)` and `dv = 0`.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::equirect::wrap_longitude;
use super::ods::View;

/// Arcminutes in one radian.
pub const ARCMIN_PER_RADIAN: f64 = 60.0 * 180.0 / PI;

/// `(dh, dv)` in radians of world point `p` seen by `left` and `right`, or `None` when
/// either eye has no projection of `p`.
pub fn angular_disparity(left: &View, right: &View, p: DVec3) -> Option<(f64, f64)> {
    let (lam_l, phi_l) = left.project(p)?;
    let (lam_r, phi_r) = right.project(p)?;
    Some((wrap_longitude(lam_l - lam_r), phi_l - phi_r))
}

/// Distance (metres) at which a point straight ahead of two eyes `2 * half_ipd` apart shows
/// horizontal disparity `dh` (radians): `half_ipd / sin(dh/2)`; `+inf` for `dh <= 0`
/// (at or beyond infinity), NaN for NaN.
pub fn perceived_distance(half_ipd: f64, dh: f64) -> f64 {
    if dh.is_nan() {
        f64::NAN
    } else if dh <= 0.0 {
        f64::INFINITY
    } else {
        half_ipd / (0.5 * dh).sin()
    }
}

/// Disparity gradient between horizontally adjacent pixels of an image `width` pixels wide
/// over 360°: `|dh_a - dh_b| / (2 pi / width)` (disparities in radians). Above 1 the two
/// cannot be fused together (Burt & Julesz).
pub fn disparity_gradient(dh_a: f64, dh_b: f64, width: u32) -> f64 {
    (dh_a - dh_b).abs() / (TAU / width as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{Camera, Eye, OdsOffset, PoleMerge, PoleMerging, Stereo};

    const R: f64 = 0.032;

    fn pair(camera: Camera, merging: PoleMerging, offset: OdsOffset) -> (View, View) {
        let stereo = Stereo::Ods {
            ipd: 2.0 * R,
            merging,
            offset,
        };
        (
            View::eye(camera, &stereo, Eye::Left),
            View::eye(camera, &stereo, Eye::Right),
        )
    }

    /// Point at horizontal distance `rho`, longitude `lam` and height `z` from the camera.
    fn at(camera: Camera, lam: f64, rho: f64, z: f64) -> DVec3 {
        let b = camera.basis();
        camera.center + rho * (lam.sin() * b.right + lam.cos() * b.forward) + z * b.up
    }

    #[test]
    fn plain_ods_disparity_is_two_asin_r_over_rho() {
        let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 37.0);
        let (l, r) = pair(camera, PoleMerging::OFF, OdsOffset::Exact);
        let mut worst = 0.0f64;
        for rho in [0.05, 0.1, 0.5, 1.0, 3.0, 30.0, 1000.0] {
            for lam in [0.0, 1.0, -2.0, 3.1] {
                for z in [0.0, 0.7, -4.0] {
                    let (dh, dv) = angular_disparity(&l, &r, at(camera, lam, rho, z)).unwrap();
                    worst = worst.max((dh - 2.0 * (R / rho).asin()).abs());
                    assert!(dv.abs() < 1e-12, "dv {dv} at rho {rho} lam {lam} z {z}");
                }
            }
        }
        assert!(worst < 1e-12, "worst {worst:e}");
        // Straight ahead at 2 m: 2 asin(0.016) = 110.0126 arcmin.
        let (dh, _) = angular_disparity(&l, &r, at(camera, 0.0, 2.0, 0.0)).unwrap();
        assert!(
            (dh * ARCMIN_PER_RADIAN - 110.012_591).abs() < 1e-6,
            "{}",
            dh * ARCMIN_PER_RADIAN
        );
    }

    #[test]
    fn no_disparity_inside_the_viewing_circle() {
        let camera = Camera::new(DVec3::ZERO, 0.0);
        let (l, r) = pair(camera, PoleMerging::OFF, OdsOffset::Exact);
        assert!(angular_disparity(&l, &r, at(camera, 0.3, 0.02, 0.0)).is_none());
    }

    #[test]
    fn pole_merging_keeps_dv_zero_and_shrinks_dh_by_the_merge_factor() {
        let camera = Camera::new(DVec3::new(1.0, 2.0, 0.0), -80.0);
        let merging = PoleMerging::both(PoleMerge::COMFORTABLE);
        let (l, r) = pair(camera, merging, OdsOffset::Exact);
        for rho in [0.2, 1.0, 10.0] {
            let (dh, dv) = angular_disparity(&l, &r, at(camera, 0.4, rho, 0.0)).unwrap();
            assert_eq!(dv, 0.0, "horizon, rho {rho}");
            assert!((dh - 2.0 * (R / rho).asin()).abs() < 1e-12);
            // Off the horizon (72°, inside the merge band) both eyes share the latitude and
            // dh uses r(phi).
            let p = at(camera, 0.4, rho, 3.0 * rho);
            let (dh, dv) = angular_disparity(&l, &r, p).unwrap();
            assert!(dv.abs() < 1e-15, "dv {dv}");
            let (_, phi) = l.project(p).unwrap();
            let rp = l.circle_radius(phi);
            assert!(rp < R);
            assert!((dh - 2.0 * (rp / rho).asin()).abs() < 1e-12);
        }
    }

    #[test]
    fn paper_offset_disparity_is_two_atan_r_over_rho() {
        let camera = Camera::new(DVec3::ZERO, 10.0);
        let (l, r) = pair(camera, PoleMerging::OFF, OdsOffset::Paper);
        for rho in [0.05, 0.5, 5.0] {
            let (dh, dv) = angular_disparity(&l, &r, at(camera, -1.2, rho, 0.0)).unwrap();
            assert!((dh - 2.0 * (R / rho).atan()).abs() < 1e-12);
            assert_eq!(dv, 0.0);
        }
    }

    #[test]
    fn perceived_distance_inverts_plain_ods_disparity() {
        for rho in [0.1, 1.0, 7.5, 300.0] {
            let dh = 2.0 * (R / rho).asin();
            assert!((perceived_distance(R, dh) - rho).abs() < 1e-12 * rho);
        }
        assert_eq!(perceived_distance(R, 0.0), f64::INFINITY);
        assert_eq!(perceived_distance(R, -1e-3), f64::INFINITY);
        assert!(perceived_distance(R, f64::NAN).is_nan());
    }

    #[test]
    fn gradient_is_disparity_step_over_pixel_pitch() {
        let pitch = TAU / 4096.0;
        assert_eq!(disparity_gradient(2.0 * pitch, 0.5 * pitch, 4096), 1.5);
        assert_eq!(disparity_gradient(0.0, pitch, 4096), 1.0);
        assert_eq!(disparity_gradient(0.3, 0.3, 64), 0.0);
    }
}
