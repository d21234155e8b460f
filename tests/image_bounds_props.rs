//! Property tests for `projection::image_bounds`: its pixel rectangles hold the centre of
//! every pixel whose ray (`View::image_ray`) hits the sphere, found by the ray tracer's exact
//! intersection on small images of every projection. Spheres anywhere, near the poles,
//! behind the camera and next to the eye; mono and both eyes with per-pole merge profiles;
//! any yaw, pitch and roll.

mod projection_strategies;

use glam::DVec3;
use omnicloud::projection::sphere;
use omnicloud::projection::{Camera, Image, Margins, Projection, View, image_bounds};
use projection_strategies::{
    CENTRE, anywhere, between_longitudes, eye, eye_view, near_a_pole, near_the_eye, profile,
};
use proptest::prelude::*;

/// Slack for pixel centres on a rectangle's edge: the rectangles and the rays are both f64,
/// so anything beyond rounding is a real miss.
const EDGE: Margins = Margins {
    angle: 1e-9,
    pixel: 1e-6,
};

/// Every projection at a small width (96 px: thousands of whole-image scans per second).
fn image() -> impl Strategy<Value = Image> {
    prop_oneof![
        Just("equirect"),
        Just("equirect:200,100"),
        Just("equirect:350,60"),
        Just("hammer"),
        Just("cylindrical:100"),
        Just("cylindrical:160"),
        Just("fisheye:200"),
        Just("fisheye:360"),
        Just("fisheye:90"),
        Just("cubemap"),
    ]
    .prop_map(|p| Image::new(p.parse().expect("projection"), 96).expect("image"))
}

/// Mono, or either eye with independent north and south profiles and an ipd from 3 cm to
/// 30 cm; any heading, pitch and roll.
fn view() -> impl Strategy<Value = View> {
    let tilt = prop_oneof![
        Just((0.0, 0.0)),
        (-90.0..90.0f64, -180.0..180.0f64),
        Just((90.0, 0.0)),
    ];
    (
        eye(),
        profile(),
        profile(),
        0.03..0.3f64,
        -360.0..360.0f64,
        tilt,
    )
        .prop_map(|(eye, north, south, ipd, yaw, (pitch, roll))| {
            let camera = Camera::new(CENTRE, yaw).with_orientation(pitch, roll);
            eye_view(camera, eye, north, south, ipd)
        })
}

fn behind() -> impl Strategy<Value = (DVec3, f64)> {
    between_longitudes(150.0, 210.0)
}

/// Hit pixels, or the first hit pixel outside every rectangle.
fn check(image: &Image, v: &View, s: DVec3, r: f64) -> Result<usize, String> {
    let rects = image_bounds(image, v, s, r, EDGE);
    let centre = v.camera.center + s;
    let mut hits = 0;
    for j in 0..image.height {
        for i in 0..image.width {
            let Some((o, d)) = v.image_ray(image, i, j) else {
                continue;
            };
            if sphere::intersect(o, d, centre, r).is_none() {
                continue;
            }
            hits += 1;
            if !rects.iter().any(|q| q.contains_pixel(i, j)) {
                return Err(format!(
                    "{}: pixel ({i}, {j}) hits the sphere but lies outside {rects:?}",
                    image.projection
                ));
            }
        }
    }
    Ok(hits)
}

fn run(image: &Image, v: &View, sphere: (DVec3, f64)) -> Result<(), TestCaseError> {
    let hits = check(image, v, sphere.0, sphere.1).map_err(TestCaseError::fail)?;
    if hits == 0 {
        return Err(TestCaseError::reject("no pixel hits the sphere"));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn rects_hold_every_hit_pixel_anywhere(img in image(), v in view(), s in anywhere()) {
        run(&img, &v, s)?;
    }

    #[test]
    fn rects_hold_every_hit_pixel_near_the_poles(img in image(), v in view(), s in near_a_pole()) {
        run(&img, &v, s)?;
    }

    #[test]
    fn rects_hold_every_hit_pixel_behind(img in image(), v in view(), s in behind()) {
        run(&img, &v, s)?;
    }

    #[test]
    fn rects_hold_every_hit_pixel_near_the_eye(img in image(), v in view(), s in near_the_eye()) {
        run(&img, &v, s)?;
    }

    /// The map: spheres anywhere over a 40 m frame, the camera anywhere.
    #[test]
    fn map_rects_hold_every_hit_pixel(
        x in -20.0..20.0f64, y in -20.0..20.0f64, z in -5.0..5.0f64, r in 0.05..3.0f64,
        cam in (-10.0..10.0f64, -10.0..10.0f64),
    ) {
        let img = Image::map(DVec3::new(-20.0, -15.0, -5.0), DVec3::new(20.0, 15.0, 8.0), 96)
            .expect("map");
        prop_assert!(matches!(img.projection, Projection::Map(Some(_))));
        let v = View::mono(Camera::new(DVec3::new(cam.0, cam.1, 0.5), 0.0));
        let s = DVec3::new(x, y, z) - v.camera.center;
        run(&img, &v, (s, r))?;
    }
}
