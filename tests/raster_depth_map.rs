//! `--depth-map` (DESIGN §9): every sphere is drawn with its own ODS radius.
//!
//! On a scene of spheres 0.3 to 30 m away: under `0.5=1.5` no sphere centre shows more
//! disparity than a point 1.5 m away (through each sphere's own views); identity pairs
//! render plain ODS bit for bit in both renderers; and the rasterizer (`bounds` + `raycast`)
//! equals the ray tracer under a map (pixels differing in coverage or colour <=
//! [`COVERAGE_MAX_FRACTION`] per eye, depth relative error p99 <= [`DEPTH_P99_MAX`]).

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::compare::compare;
use omnicloud::output::LinearImage;
use omnicloud::projection::depth_map::DepthMap;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo, equirect};
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings};
use omnicloud::rng::SplitMix64;
use omnicloud::{Attributes, Radii, Rendered, Scene, raytrace};

/// Coverage-mismatched fraction of an eye's pixels allowed (0.01 %).
const COVERAGE_MAX_FRACTION: f64 = 1e-4;
/// Depth relative error p99 allowed.
const DEPTH_P99_MAX: f64 = 1e-6;
const IPD: f64 = 0.064;

/// Spheres all around a camera at the origin, centres 0.3 to 30 m away (log-uniform),
/// radius 1 to 6 % of the distance, each with its own colour; a few near each pole.
fn near_and_far(n: usize) -> Scene {
    let mut rng = SplitMix64::new(31);
    let mut centres = Vec::new();
    let mut radii = Vec::new();
    for k in 0..n {
        let lam = rng.range(-180.0f64, 180.0).to_radians();
        let z = if k % 50 == 0 {
            rng.range(0.97, 1.0) * if k % 100 == 0 { 1.0 } else { -1.0 }
        } else {
            rng.range(-1.0, 1.0)
        };
        let h = (1.0 - z * z).sqrt();
        let d = 0.3 * 100f64.powf(rng.range(0.0, 1.0));
        centres.push((d * DVec3::new(h * lam.sin(), h * lam.cos(), z)).as_vec3());
        radii.push((d * rng.range(0.01, 0.06)) as f32);
    }
    let colors = (0..n)
        .map(|k| [(k % 200 + 20) as u8, (k / 200 * 20 + 10) as u8, 77])
        .collect();
    Scene {
        origin: DVec3::ZERO,
        positions: centres,
        radii: Radii::PerPoint(radii),
        attributes: Attributes {
            rgb: Some(colors),
            ..Attributes::default()
        },
    }
}

fn settings(width: u32, camera: Camera, merge: PoleMerge, map: &str) -> RenderSettings {
    let mut s = RenderSettings::new(width, camera);
    s.stereo = Stereo::Ods {
        ipd: IPD,
        merging: PoleMerging::both(merge),
        offset: OdsOffset::Exact,
    };
    s.depth_map = Some(map.parse().expect("a depth map"));
    s.color = ColorMode::Rgb;
    s.proxy = Proxy::Bounds;
    s.imposter = Imposter::Raycast;
    s
}

/// `lamL - lamR` of each sphere centre, each seen in its own views, radians; `None` for a
/// centre without a projection (inside the viewing circle).
fn centre_disparities(scene: &Scene, s: &RenderSettings) -> Vec<Option<f64>> {
    let views = s.views();
    scene
        .positions
        .iter()
        .map(|p| {
            let c = s.camera.center + p.as_dvec3();
            let lam = |k: usize| Some(views[k].for_sphere(c).project(c)?.0);
            Some(equirect::wrap_longitude(lam(0)? - lam(1)?))
        })
        .collect()
}

#[test]
fn no_sphere_centre_looks_nearer_than_the_map_allows() {
    let scene = near_and_far(3000);
    let bound = 2.0 * (0.5 * IPD / 1.5).asin();
    for merge in [PoleMerge::Off, PoleMerge::COMFORTABLE] {
        let camera = Camera::new(DVec3::ZERO, 20.0).with_orientation(15.0, -10.0);
        let mapped = settings(64, camera, merge, "0.5=1.5");
        let plain = RenderSettings {
            depth_map: None,
            ..mapped
        };
        // Under the map every centre projects (r_s < rho_c).
        let dh: Vec<f64> = centre_disparities(&scene, &mapped)
            .into_iter()
            .map(|d| d.expect("a centre projects"))
            .collect();
        let worst = dh.iter().copied().fold(0.0, f64::max);
        let plain_worst = centre_disparities(&scene, &plain)
            .into_iter()
            .flatten()
            .fold(0.0, f64::max);
        eprintln!(
            "{merge:?}: largest centre disparity {:.3}' (1.5 m: {:.3}'), plain ODS {:.3}'",
            worst.to_degrees() * 60.0,
            bound.to_degrees() * 60.0,
            plain_worst.to_degrees() * 60.0
        );
        assert!(worst <= bound * (1.0 + 1e-12), "{worst} > {bound}");
        // Without the map the near spheres do look nearer.
        assert!(plain_worst > 2.0 * bound, "plain ODS {plain_worst}");
        if merge == PoleMerge::Off {
            // Every centre within 0.5 m horizontally is pushed back to 1.5 m exactly.
            let views = mapped.views();
            let b = views[0].basis();
            let near = scene.positions.iter().zip(&dh).filter(|(p, _)| {
                let p = p.as_dvec3();
                p.dot(b.right).hypot(p.dot(b.forward)) <= 0.5
            });
            let mut count = 0;
            for (_, &d) in near {
                assert!((d - bound).abs() <= 1e-12, "{d} vs {bound}");
                count += 1;
            }
            assert!(count > 100, "{count} spheres within 0.5 m");
        }
    }
}

#[test]
fn identity_maps_render_plain_ods_bit_for_bit() {
    let scene = near_and_far(800);
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let identity = settings(256, camera, PoleMerge::COMFORTABLE, "0.01=0.01,1000=1000");
    assert!(
        identity
            .depth_map
            .is_some_and(|m: DepthMap| m.is_identity())
    );
    let plain = RenderSettings {
        depth_map: None,
        ..identity
    };
    let trace = |s: &RenderSettings| raytrace::render(&scene, s, &ProgressBar::hidden()).unwrap();
    assert_eq!(trace(&identity), trace(&plain), "ray tracer");
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let draw = |s: &RenderSettings| raster.render(&scene, s, &ProgressBar::hidden()).unwrap().0;
    assert_eq!(draw(&identity), draw(&plain), "rasterizer");
}

fn as_image(r: &Rendered) -> LinearImage {
    LinearImage::from_frame(&r.top_bottom())
}

#[test]
fn raster_equals_the_ray_tracer_under_a_depth_map() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let scene = near_and_far(2000);
    let level = Camera::new(DVec3::ZERO, 0.0);
    let turned = Camera::new(DVec3::ZERO, -40.0).with_orientation(-20.0, 10.0);
    for (label, s) in [
        (
            "0.5=1.5",
            settings(512, level, PoleMerge::COMFORTABLE, "0.5=1.5"),
        ),
        (
            "four pairs, cycles, pitch/roll",
            settings(
                512,
                turned,
                PoleMerge::CYCLES_DEFAULT,
                "0.4=1,1=2,2.5=3,6=10",
            ),
        ),
    ] {
        let (test, _) = raster
            .render(&scene, &s, &ProgressBar::hidden())
            .expect("raster render");
        let reference = raytrace::render(&scene, &s, &ProgressBar::hidden()).expect("ray trace");
        let plain = RenderSettings {
            depth_map: None,
            ..s
        };
        let ods = raytrace::render(&scene, &plain, &ProgressBar::hidden()).expect("ray trace");
        let changed = compare(&as_image(&ods), &as_image(&reference)).expect("same size");
        let report = compare(&as_image(&reference), &as_image(&test)).expect("same size");
        for (eye, moved) in report.eyes.iter().zip(&changed.eyes) {
            let all = &eye.all;
            let depth = all.depth_relative.as_ref().expect("both hit somewhere");
            eprintln!(
                "{label} {}: mismatch {} px ({:.4}%), depth p99 {:.2e}, colour rmse {:?}; \
                 the map moves {} px",
                eye.eye,
                all.mismatch,
                all.mismatch_percent,
                depth.p99,
                all.color_rmse,
                moved.all.mismatch
            );
            assert!(all.ref_hits > 10_000, "{label}: too few hits to judge");
            // The map changes the picture: the comparison is not plain ODS against itself.
            assert!(moved.all.mismatch > 100, "{label}: the map changed little");
            assert!(
                all.mismatch as f64 <= COVERAGE_MAX_FRACTION * all.pixels as f64,
                "{label} {}: coverage differs on {} of {} px",
                eye.eye,
                all.mismatch,
                all.pixels
            );
            assert!(
                depth.p99 <= DEPTH_P99_MAX,
                "{label}: depth p99 {}",
                depth.p99
            );
        }
        // A silhouette pixel that one renderer hits and the other misses by f32 rounding
        // shows the sphere behind: it counts with the coverage mismatches.
        for (k, (t, r)) in test.frames().iter().zip(reference.frames()).enumerate() {
            let differ = t.color.iter().zip(&r.color).filter(|(a, b)| a != b).count();
            eprintln!("{label} eye {k}: {differ} px differ in coverage or colour");
            assert!(
                differ as f64 <= COVERAGE_MAX_FRACTION * t.color.len() as f64,
                "{label} eye {k}: {differ} px differ"
            );
        }
    }
}
