//! Property tests for `projection::sphere_bounds` (docs/SPHERE_BOUNDS.md): the box contains
//! the centre angles of every pixel whose ray hits the sphere, found by the ray tracer's exact
//! intersection on a small image. Spheres anywhere, near the poles, straddling the seam and
//! next to the eye; mono and both eyes, with per-pole merge profiles.

mod projection_strategies;

use std::f64::consts::{FRAC_PI_2, PI};

use glam::{DVec2, DVec3};
use omnicloud::projection::sphere;
use omnicloud::projection::{
    Camera, Equirect, Eye, OdsOffset, PoleMerging, Rect, Stereo, View, sphere_bounds,
};
use projection_strategies::{
    CENTRE, anywhere, between_longitudes, eye, eye_view, near_a_pole, near_the_eye, profile,
};
use proptest::prelude::*;

/// 192 x 96: 1.9° per pixel, small enough for thousands of whole-image scans per second.
const WIDTH: u32 = 192;

/// Slack (radians) for pixel centres on the box's edge: the box and the rays are both f64,
/// so anything beyond rounding is a real miss.
const EDGE: f64 = 1e-9;

/// Mono, or either eye with independent north and south profiles and an ipd from 3 cm to
/// 30 cm (wide rigs make the offset term large at this resolution). Spheres are drawn in the
/// yaw-0 camera frame; `sphere_in` turns them with the view.
fn view() -> impl Strategy<Value = View> {
    (eye(), profile(), profile(), 0.03..0.3f64, -360.0..360.0f64).prop_map(
        |(eye, north, south, ipd, yaw)| eye_view(Camera::new(CENTRE, yaw), eye, north, south, ipd),
    )
}

fn across_the_seam() -> impl Strategy<Value = (DVec3, f64)> {
    between_longitudes(175.0, 185.0)
}

/// The sphere (`s` in the yaw-0 camera frame, radius) in the view's frame, relative to C.
fn sphere_in(v: &View, (s, r): (DVec3, f64)) -> (DVec3, f64) {
    let b = v.basis();
    (s.x * b.right + s.y * b.forward + s.z * b.up, r)
}

/// Pixels the ray tracer sees the sphere in, and how many lie outside the box: the first
/// such pixel's angles with it.
fn check(v: &View, s: DVec3, r: f64) -> Result<usize, String> {
    let image = Equirect::from_width(WIDTH);
    let bounds = sphere_bounds(v, s, r);
    // The splat wraps a box's pixel columns into the image once: its longitudes must lie
    // within one turn of 0.
    let turn = 2.0 * PI + EDGE;
    if bounds.rect.lo.x < -turn || bounds.rect.hi.x > turn {
        return Err(format!("{bounds:?} reaches beyond one turn of longitude"));
    }
    let grown = Rect {
        lo: bounds.rect.lo - DVec2::splat(EDGE),
        hi: bounds.rect.hi + DVec2::splat(EDGE),
    };
    let centre = v.camera.center + s;
    let mut hits = 0;
    for j in 0..image.height {
        for i in 0..image.width {
            let (o, d) = v.pixel_ray(&image, i, j);
            if sphere::intersect(o, d, centre, r).is_none() {
                continue;
            }
            hits += 1;
            let (lam, phi) = image.pixel_angles(i, j);
            if !grown.contains(lam, phi) {
                return Err(format!(
                    "pixel ({i}, {j}) at ({lam:.5}, {phi:.5}) hits the sphere but lies outside {:?}",
                    bounds
                ));
            }
        }
    }
    Ok(hits)
}

fn run(v: &View, sphere: (DVec3, f64)) -> Result<(), TestCaseError> {
    let (s, r) = sphere_in(v, sphere);
    let hits = check(v, s, r).map_err(TestCaseError::fail)?;
    // A sphere no pixel centre sees proves nothing: draw another.
    if hits == 0 {
        return Err(TestCaseError::reject("no pixel hits the sphere"));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn box_holds_every_hit_pixel_anywhere(v in view(), s in anywhere()) {
        run(&v, s)?;
    }

    #[test]
    fn box_holds_every_hit_pixel_near_the_poles(v in view(), s in near_a_pole()) {
        run(&v, s)?;
    }

    #[test]
    fn box_holds_every_hit_pixel_across_the_seam(v in view(), s in across_the_seam()) {
        run(&v, s)?;
    }

    #[test]
    fn box_holds_every_hit_pixel_near_the_eye(v in view(), s in near_the_eye()) {
        run(&v, s)?;
    }
}

/// The box is not loose where it need not be: a sphere 2 m ahead (right eye, no merging)
/// reaches within a pixel of each of its box's edges.
#[test]
fn box_of_a_sphere_ahead_is_tight_to_a_pixel() {
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let stereo = Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::OFF,
        offset: OdsOffset::Exact,
    };
    let v = View::eye(camera, &stereo, Eye::Right);
    let image = Equirect::from_width(WIDTH);
    let (s, r) = (DVec3::new(0.1, 2.0, 0.2), 0.5);
    let b = sphere_bounds(&v, s, r);
    assert!(!b.special);
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for j in 0..image.height {
        for i in 0..image.width {
            let (o, d) = v.pixel_ray(&image, i, j);
            if sphere::intersect(o, d, s, r).is_some() {
                let (lam, phi) = image.pixel_angles(i, j);
                lo = lo.min(DVec2::new(lam, phi));
                hi = hi.max(DVec2::new(lam, phi));
            }
        }
    }
    let pixel = PI / image.height as f64;
    for (edge, got) in [
        (b.rect.lo.x, lo.x),
        (b.rect.lo.y, lo.y),
        (b.rect.hi.x, hi.x),
        (b.rect.hi.y, hi.y),
    ] {
        assert!(
            (edge - got).abs() <= pixel,
            "box edge {edge} vs outermost hit pixel centre {got}"
        );
    }
    assert!(b.rect.hi.y < FRAC_PI_2);
}
