//! The equidistant fisheye, centred on the forward axis (DESIGN §8), `H = W`.
//!
//! Directions are in rig components `(d.R, d.F, d.U)`.

use glam::DVec3;

/// Rig-frame direction `(d.R, d.F, d.U)` seen at continuous image position `(u, v)` in
/// `[0, 1]^2` of a fisheye with field of view `fov` (radians), or `None` outside the circle.
#[inline]
pub fn direction(u: f64, v: f64, fov: f64) -> Option<DVec3> {
    let x = 2.0 * u - 1.0;
    let y = 1.0 - 2.0 * v;
    let s = x.hypot(y);
    if s > 1.0 {
        return None;
    }
    if s == 0.0 {
        return Some(DVec3::Y);
    }
    let (st, ct) = (s * 0.5 * fov).sin_cos();
    Some(DVec3::new(st * x / s, ct, st * y / s))
}

/// Image position `(u, v)` of rig-frame direction `d` (any length), or `None` when it lies
/// outside the field of view.
#[inline]
pub fn position(d: DVec3, fov: f64) -> Option<(f64, f64)> {
    let side = d.x.hypot(d.z);
    let theta = side.atan2(d.y);
    if theta > 0.5 * fov {
        return None;
    }
    let s = theta / (0.5 * fov);
    let (x, y) = if side == 0.0 {
        (0.0, 0.0)
    } else {
        (s * d.x / side, s * d.z / side)
    };
    Some(((x + 1.0) / 2.0, (1.0 - y) / 2.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rim_of_a_180_degree_fisheye_looks_sideways() {
        let fov = 180f64.to_radians();
        let d = direction(1.0, 0.5, fov).unwrap();
        assert!((d - DVec3::X).length() < 1e-12);
        let d = direction(0.5, 0.0, fov).unwrap();
        assert!((d - DVec3::Z).length() < 1e-12);
        assert!(direction(0.95, 0.95, fov).is_none());
        assert_eq!(direction(0.5, 0.5, fov), Some(DVec3::Y));
    }

    #[test]
    fn position_inverts_direction() {
        let fov = 220f64.to_radians();
        for &(u, v) in &[(0.3, 0.4), (0.5, 0.9), (0.12, 0.5), (0.6, 0.55)] {
            let d = direction(u, v, fov).unwrap();
            let (u2, v2) = position(d, fov).unwrap();
            assert!((u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12, "{u},{v}");
        }
    }
}
