//! The Hammer–Aitoff projection of the whole sphere (DESIGN §8), `H = W / 2`.

use std::f64::consts::SQRT_2;

/// Longitude and latitude seen at continuous image position `(u, v)` in `[0, 1]^2`, or `None`
/// outside the ellipse `x^2/8 + y^2/2 <= 1`.
#[inline]
pub fn angles(u: f64, v: f64) -> Option<(f64, f64)> {
    let x = (2.0 * u - 1.0) * 2.0 * SQRT_2;
    let y = (1.0 - 2.0 * v) * SQRT_2;
    // 2 z^2 - 1 with z = sqrt(1 - x^2/16 - y^2/4), from x and y rather than from the
    // rounded z (the f32 twin in shaders/projection.wgsl needs it).
    let w = 1.0 - x * x / 8.0 - y * y / 2.0;
    if w < 0.0 {
        return None;
    }
    let z = (0.5 * (1.0 + w)).sqrt();
    let lam = 2.0 * (z * x).atan2(2.0 * w);
    let phi = (z * y).clamp(-1.0, 1.0).asin();
    Some((lam, phi))
}

/// Image position `(u, v)` in `[0, 1]^2` of longitude `lam` in `[-pi, pi]`, latitude `phi`.
#[inline]
pub fn position(lam: f64, phi: f64) -> (f64, f64) {
    let (sp, cp) = phi.sin_cos();
    let (sh, ch) = (0.5 * lam).sin_cos();
    // cos(lam/2) >= 0 on [-pi, pi]: k >= 1.
    let k = (1.0 + cp * ch).sqrt();
    let (x, y) = (2.0 * SQRT_2 * cp * sh / k, SQRT_2 * sp / k);
    ((x / (2.0 * SQRT_2) + 1.0) / 2.0, (1.0 - y / SQRT_2) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn centre_is_forward_and_the_ellipse_tips_are_behind() {
        let (lam, phi) = angles(0.5, 0.5).unwrap();
        assert!(lam.abs() < 1e-15 && phi.abs() < 1e-15);
        let (lam, _) = angles(0.0005, 0.5).unwrap();
        assert!((lam.abs() - PI).abs() < 0.01);
        let (_, phi) = angles(0.5, 0.0001).unwrap();
        assert!((phi - FRAC_PI_2).abs() < 0.03);
    }

    #[test]
    fn corners_lie_outside_the_ellipse() {
        assert!(angles(0.01, 0.01).is_none());
        assert!(angles(0.99, 0.99).is_none());
    }

    #[test]
    fn position_inverts_angles() {
        for &(u, v) in &[
            (0.3, 0.4),
            (0.1, 0.5),
            (0.7, 0.85),
            (0.5, 0.02),
            (0.93, 0.45),
        ] {
            let (lam, phi) = angles(u, v).unwrap();
            let (u2, v2) = position(lam, phi);
            assert!((u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12, "{u},{v}");
        }
    }
}
