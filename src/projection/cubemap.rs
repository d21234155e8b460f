//! Six 90° faces in one strip, `H = W / 6` (DESIGN §8): front, right, back, left, up, down.
//!
//! Directions are in rig components `(d.R, d.F, d.U)`.

use glam::DVec3;

/// Face axes (forward A, right B, up C) in rig components, in strip order.
pub const FACES: [[DVec3; 3]; 6] = {
    const R: DVec3 = DVec3::X;
    const F: DVec3 = DVec3::Y;
    const U: DVec3 = DVec3::Z;
    const NR: DVec3 = DVec3::NEG_X;
    const NF: DVec3 = DVec3::NEG_Y;
    const NU: DVec3 = DVec3::NEG_Z;
    [
        [F, R, U],
        [R, NF, U],
        [NF, NR, U],
        [NR, F, U],
        [U, R, NF],
        [NU, R, F],
    ]
};

/// Rig-frame unit direction seen at continuous image position `(u, v)` in `[0, 1]^2`.
#[inline]
pub fn direction(u: f64, v: f64) -> DVec3 {
    let k = ((6.0 * u).floor() as usize).min(5);
    let a = 2.0 * (6.0 * u - k as f64) - 1.0;
    let b = 1.0 - 2.0 * v;
    let [fa, fb, fc] = FACES[k];
    (fa + a * fb + b * fc).normalize()
}

/// Face and face coordinates `(a, b)` in `[-1, 1]^2` of rig-frame direction `d` (any length):
/// the face whose forward axis is nearest `d`.
#[inline]
pub fn face_coordinates(d: DVec3) -> (usize, f64, f64) {
    let mut best = 0;
    let mut best_dot = f64::NEG_INFINITY;
    for (k, [fa, _, _]) in FACES.iter().enumerate() {
        let dot = d.dot(*fa);
        if dot > best_dot {
            best = k;
            best_dot = dot;
        }
    }
    let [_, fb, fc] = FACES[best];
    (best, d.dot(fb) / best_dot, d.dot(fc) / best_dot)
}

/// Image position `(u, v)` of rig-frame direction `d`.
#[inline]
pub fn position(d: DVec3) -> (f64, f64) {
    let (k, a, b) = face_coordinates(d);
    ((k as f64 + (a + 1.0) / 2.0) / 6.0, (1.0 - b) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_centres_look_along_their_axes() {
        for (k, [fa, _, _]) in FACES.iter().enumerate() {
            let d = direction((k as f64 + 0.5) / 6.0, 0.5);
            assert!((d - *fa).length() < 1e-12, "face {k}");
        }
    }

    #[test]
    fn faces_are_right_handed_like_the_rig() {
        for [fa, fb, fc] in FACES {
            assert!((fa.cross(fc) - fb).length() < 1e-12);
        }
    }

    #[test]
    fn position_inverts_direction() {
        for &(u, v) in &[
            (0.03, 0.2),
            (0.4, 0.7),
            (0.7, 0.1),
            (0.95, 0.6),
            (0.55, 0.5),
        ] {
            let (u2, v2) = position(direction(u, v));
            assert!((u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12, "{u},{v}");
        }
    }
}
