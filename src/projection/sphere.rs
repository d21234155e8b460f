//! Exact ray–sphere intersection in f64, robust for grazing rays, far spheres and origins
//! inside or on a sphere.

use glam::DVec3;

/// Roots closer to the ray origin than this fraction of `|origin - centre| + radius` are
/// treated as the origin itself (a ray starting on a surface), not as hits: rounding puts
/// such roots a few ulps either side of zero, and a sign decided by rounding is no hit.
pub const SELF_HIT_RELATIVE: f64 = 1e-12;

/// Distance along a unit-length ray `origin + t * dir` to the nearest hit with the sphere
/// (`center`, `radius`) at `t > 0`, or `None`.
///
/// A ray starting inside the sphere returns the far (inside-surface) hit; hits behind the
/// origin are ignored. `dir` must have unit length: the formulas rely on `a = |dir|² = 1`.
///
/// The discriminant is computed from the perpendicular offset of the centre from the ray
/// (`r² − |oc − b·d|²`), not as `b² − c`, so far spheres with tiny radii keep their
/// precision; the two roots come from the stable form `q = −(b + sign(b)·√disc)`,
/// `t ∈ {q, c/q}`, so neither root loses digits to cancellation.
#[inline]
pub fn intersect(origin: DVec3, dir: DVec3, center: DVec3, radius: f64) -> Option<f64> {
    let oc = origin - center;
    let b = dir.dot(oc);
    let perp = oc - b * dir;
    let disc = radius * radius - perp.length_squared();
    if disc < 0.0 || disc.is_nan() {
        return None;
    }
    let len = oc.length();
    let c = (len - radius) * (len + radius);
    let sqrt_disc = disc.sqrt();
    let q = if b >= 0.0 {
        -(b + sqrt_disc)
    } else {
        -(b - sqrt_disc)
    };
    if q == 0.0 {
        // Tangent exactly at the origin.
        return None;
    }
    let (r0, r1) = (q, c / q);
    let (near, far) = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
    let t_min = SELF_HIT_RELATIVE * (len + radius);
    if near > t_min {
        Some(near)
    } else if far > t_min {
        Some(far)
    } else {
        None
    }
}

/// Unit surface normal at the hit `origin + t * dir` of the sphere at `center`, turned to
/// face the viewer (against `dir`), so inside-surface hits are lit from inside.
#[inline]
pub fn facing_normal(origin: DVec3, dir: DVec3, t: f64, center: DVec3) -> DVec3 {
    // Relative to the centre first: keeps the small offset exact when the sphere is far.
    let offset = (origin - center) + t * dir;
    let n = offset.normalize_or_zero();
    if n.dot(dir) > 0.0 { -n } else { n }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    #[test]
    fn head_on_hit_is_the_near_surface() {
        let t = intersect(DVec3::ZERO, DVec3::Y, DVec3::new(0.0, 5.0, 0.0), 0.5).unwrap();
        assert_eq!(t, 4.5);
        let n = facing_normal(DVec3::ZERO, DVec3::Y, t, DVec3::new(0.0, 5.0, 0.0));
        assert!((n + DVec3::Y).length() < 1e-15);
    }

    #[test]
    fn offset_hit_matches_the_chord_formula() {
        let c = DVec3::new(0.3, 7.0, -0.2);
        let r = 0.5;
        let t = intersect(DVec3::ZERO, DVec3::Y, c, r).unwrap();
        let p2: f64 = 0.3 * 0.3 + 0.2 * 0.2;
        assert!(close(t, 7.0 - (r * r - p2).sqrt(), 1e-15));
    }

    #[test]
    fn no_hit_behind_the_origin_or_beside_the_sphere() {
        assert!(intersect(DVec3::ZERO, DVec3::Y, DVec3::new(0.0, -5.0, 0.0), 1.0).is_none());
        assert!(intersect(DVec3::ZERO, DVec3::Y, DVec3::new(1.0001, 5.0, 0.0), 1.0).is_none());
        assert!(intersect(DVec3::ZERO, DVec3::Y, DVec3::new(1e-9, 5.0, 0.0), 0.0).is_none());
    }

    #[test]
    fn grazing_rays_hit_just_inside_and_miss_just_outside() {
        let r = 1.0;
        let c = DVec3::new(0.0, 10.0, 0.0);
        for &(x, hits) in &[(1.0 - 1e-9, true), (1.0 + 1e-9, false)] {
            let o = DVec3::new(x, 0.0, 0.0);
            let got = intersect(o, DVec3::Y, c, r);
            assert_eq!(got.is_some(), hits, "offset {x}");
            if let Some(t) = got {
                let expect = 10.0 - (r * r - x * x).sqrt();
                assert!((t - expect).abs() < 1e-7, "t {t} expect {expect}");
            }
        }
        // Exactly tangent: one touching point at t = 10.
        let t = intersect(DVec3::new(1.0, 0.0, 0.0), DVec3::Y, c, r).unwrap();
        assert!((t - 10.0).abs() < 1e-12);
    }

    #[test]
    fn origin_inside_returns_the_far_hit_with_an_inward_normal() {
        let c = DVec3::new(0.1, 0.2, 0.0);
        let r = 2.0;
        let d = DVec3::new(1.0, 0.0, 0.0);
        let t = intersect(DVec3::ZERO, d, c, r).unwrap();
        let expect = 0.1 + (r * r - 0.2f64 * 0.2).sqrt();
        assert!(close(t, expect, 1e-15));
        let n = facing_normal(DVec3::ZERO, d, t, c);
        assert!(n.dot(d) < 0.0);
        assert!((n.length() - 1.0).abs() < 1e-15);
        // The centre itself: the hit is exactly one radius away in any direction.
        let t = intersect(c, DVec3::new(0.0, 0.6, 0.8), c, r).unwrap();
        assert_eq!(t, r);
    }

    #[test]
    fn origin_on_the_surface_sees_the_far_side_inward_and_nothing_outward() {
        let c = DVec3::ZERO;
        let o = DVec3::new(0.0, 0.0, 1.0);
        assert_eq!(intersect(o, -DVec3::Z, c, 1.0), Some(2.0));
        assert_eq!(intersect(o, DVec3::Z, c, 1.0), None);
        // A surface point that is not exactly representable: still no self-hit.
        let dir = DVec3::new(1.0, 2.0, 3.0).normalize();
        let o = 0.7 * dir;
        assert_eq!(intersect(o, dir, c, 0.7), None);
        let t = intersect(o, -dir, c, 0.7).unwrap();
        assert!(close(t, 1.4, 1e-15));
    }

    #[test]
    fn far_tiny_sphere_keeps_its_depth_to_the_micrometre() {
        let d = DVec3::new(0.3, 0.9, 0.1).normalize();
        let dist = 1e4;
        let r = 1e-3;
        let c = dist * d + DVec3::new(0.0, 0.0, 5e-4);
        // Perpendicular offset of the centre from the ray line.
        let p = (c - c.dot(d) * d).length();
        let t = intersect(DVec3::ZERO, d, c, r).unwrap();
        let expect = c.dot(d) - (r * r - p * p).sqrt();
        assert!((t - expect).abs() < 1e-8, "t {t} expect {expect}");
        // Perpendicular miss by a micrometre at 10 km.
        let c_miss = dist * d + DVec3::new(0.0, 0.0, 1.0).cross(d).normalize() * (r + 1e-6);
        assert!(intersect(DVec3::ZERO, d, c_miss, r).is_none());
        let c_hit = dist * d + DVec3::new(0.0, 0.0, 1.0).cross(d).normalize() * (r - 1e-6);
        assert!(intersect(DVec3::ZERO, d, c_hit, r).is_some());
    }

    #[test]
    fn nan_input_is_no_hit() {
        assert!(intersect(DVec3::NAN, DVec3::Y, DVec3::ZERO, 1.0).is_none());
        assert!(intersect(DVec3::ZERO, DVec3::Y, DVec3::ZERO, f64::NAN).is_none());
    }
}
