//! The rasterizer draws every projection of DESIGN §8 as the ray tracer does: the stress
//! scene and the real sample in `equirect:200,100`, `hammer`, `cylindrical:100`,
//! `fisheye:200`, `cubemap` (mono and ODS with pole merging, level and pitched/rolled) and
//! `map`, compared per eye through `compare`: coverage mismatch at most
//! [`COVERAGE_MAX_FRACTION`] of the pixels (lavapipe: none), depth relative error p99 at
//! most [`DEPTH_P99_MAX`] ([`MAP_DEPTH_P99_MAX`] for the map), unlit colour identical where
//! both hit. A sphere in a known direction
//! lands where the projection's formula puts it in both renderers; Hammer draws nothing
//! outside its ellipse; a partial equirect is the crop of the full panorama.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::compare::{RegionStats, compare_eyes};
use omnicloud::projection::{Camera, Image, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::raster::Rasterizer;
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings};
use omnicloud::{Attributes, Frame, Radii, Rendered, Scene, raytrace};

/// Coverage mismatches allowed, as a fraction of each eye's pixels (0.01 %).
const COVERAGE_MAX_FRACTION: f64 = 1e-4;
/// Depth relative error p99 allowed (lavapipe: up to 8.4e-7).
const DEPTH_P99_MAX: f64 = 1e-6;
/// The same for the map, whose ray origins are f32 coordinates up to a few hundred metres
/// from the camera (a 1.5e-5 m ulp at 250 m; lavapipe: up to 2.2e-6 on the sample).
const MAP_DEPTH_P99_MAX: f64 = 3e-6;

/// The projections other than the full panorama, mono and ODS (the map is mono only).
const PROJECTIONS: [&str; 5] = [
    "equirect:200,100",
    "hammer",
    "cylindrical:100",
    "fisheye:200",
    "cubemap",
];

fn ods() -> Stereo {
    Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging {
            north: PoleMerge::COMFORTABLE,
            south: PoleMerge::CYCLES_DEFAULT,
        },
        offset: OdsOffset::Exact,
    }
}

fn settings(image: Image, camera: Camera, stereo: Stereo) -> RenderSettings {
    let mut s = RenderSettings::new(image.width, camera);
    s.image = image;
    s.stereo = stereo;
    s.color = ColorMode::Rgb;
    s.proxy = Proxy::Bounds;
    s.imposter = Imposter::Raycast;
    s
}

fn image(projection: &str, width: u32) -> Image {
    Image::new(projection.parse().expect("projection"), width).expect("image")
}

/// The map over the scene's XY extent (spheres included).
fn map_image(scene: &Scene, width: u32) -> Image {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for i in 0..scene.len() {
        let (p, r) = (scene.positions[i].as_dvec3(), scene.radii.get(i) as f64);
        lo = lo.min(p - r);
        hi = hi.max(p + r);
    }
    Image::map(lo, hi, width).expect("map image")
}

fn frames(r: &Rendered) -> Vec<Frame> {
    r.frames().into_iter().cloned().collect()
}

/// Renders with both renderers and checks the thresholds on every eye; returns the worst
/// mismatch fraction and depth p99.
fn agree(raster: &Rasterizer, scene: &Scene, s: &RenderSettings, label: &str) -> (f64, f64) {
    let (test, _) = raster
        .render(scene, s, &ProgressBar::hidden())
        .unwrap_or_else(|e| panic!("{label}: raster render: {e}"));
    let reference = raytrace::render(scene, s, &ProgressBar::hidden()).expect("ray trace");
    let (mut worst_cov, mut worst_depth) = (0f64, 0f64);
    for (eye, (r, t)) in frames(&reference)
        .iter()
        .zip(frames(&test).iter())
        .enumerate()
    {
        let panorama = s.image.projection.is_full_equirect();
        let regions = compare_eyes(&[(r, t)], panorama).expect("same size");
        let all: &RegionStats = &regions.all;
        let fraction = all.mismatch as f64 / all.pixels as f64;
        let p99 = all.depth_relative.as_ref().map_or(0.0, |d| d.p99);
        eprintln!(
            "{label} eye {eye}: {} px hit, mismatch {} px ({:.5}%), depth p99 {p99:.2e}, \
             colour differs on {} px",
            all.ref_hits,
            all.mismatch,
            100.0 * fraction,
            all.color_differs
        );
        assert!(all.ref_hits > 500, "{label}: too few hits to judge");
        assert!(
            fraction <= COVERAGE_MAX_FRACTION,
            "{label} eye {eye}: coverage differs on {} of {} px",
            all.mismatch,
            all.pixels
        );
        let max = if s.image.projection.is_map() {
            MAP_DEPTH_P99_MAX
        } else {
            DEPTH_P99_MAX
        };
        assert!(p99 <= max, "{label} eye {eye}: depth p99 {p99}");
        assert_eq!(all.color_differs, 0, "{label} eye {eye}: colour");
        worst_cov = worst_cov.max(fraction);
        worst_depth = worst_depth.max(p99);
    }
    (worst_cov, worst_depth)
}

#[test]
fn stress_scene_in_every_projection_matches_the_ray_tracer() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let scene = raster_common::stress_scene(600);
    let level = Camera::new(DVec3::ZERO, 0.0);
    let tilted = Camera::new(DVec3::ZERO, 20.0).with_orientation(30.0, -20.0);
    for p in PROJECTIONS {
        for (cam_label, camera) in [("level", level), ("pitch 30 roll -20", tilted)] {
            for (stereo_label, stereo) in [("mono", Stereo::Mono), ("ods", ods())] {
                let s = settings(image(p, 288), camera, stereo);
                agree(
                    &raster,
                    &scene,
                    &s,
                    &format!("stress {p} {stereo_label} {cam_label}"),
                );
            }
        }
    }
    let s = settings(map_image(&scene, 288), level, Stereo::Mono);
    agree(&raster, &scene, &s, "stress map");
}

#[test]
fn real_sample_in_every_projection_matches_the_ray_tracer() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let scene = raster_common::autzen_at_centre();
    let camera = Camera::new(DVec3::ZERO, 0.0);
    for p in PROJECTIONS {
        for (stereo_label, stereo) in [("mono", Stereo::Mono), ("ods", ods())] {
            let s = settings(image(p, 240), camera, stereo);
            agree(&raster, &scene, &s, &format!("autzen {p} {stereo_label}"));
        }
    }
    let s = settings(map_image(&scene, 240), camera, Stereo::Mono);
    agree(&raster, &scene, &s, "autzen map");
}

/// One small sphere at `centre` (camera at the origin).
fn one_sphere(centre: DVec3, radius: f32) -> Scene {
    Scene {
        origin: DVec3::ZERO,
        positions: vec![centre.as_vec3()],
        radii: Radii::Uniform(radius),
        attributes: Attributes {
            rgb: Some(vec![[200, 100, 50]]),
            ..Attributes::default()
        },
    }
}

/// Mean pixel centre of a frame's covered pixels.
fn centroid(f: &Frame) -> Option<(f64, f64)> {
    let (mut n, mut x, mut y) = (0.0, 0.0, 0.0);
    for j in 0..f.height {
        for i in 0..f.width {
            if f.covered(i, j) {
                n += 1.0;
                x += f64::from(i) + 0.5;
                y += f64::from(j) + 0.5;
            }
        }
    }
    (n > 0.0).then(|| (x / n, y / n))
}

#[test]
fn a_sphere_in_a_known_direction_lands_where_the_formula_puts_it() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    // Rig-frame directions (d.R, d.F, d.U), and the orientations to look through.
    let dirs = [
        DVec3::new(0.3, 1.0, 0.2),
        DVec3::new(-1.0, 0.4, -0.3),
        DVec3::new(0.5, -0.2, 0.6),
        DVec3::new(0.2, 0.9, -0.7),
    ];
    let cameras = [
        Camera::new(DVec3::ZERO, 0.0),
        Camera::new(DVec3::ZERO, 35.0).with_orientation(30.0, -20.0),
        // Straight up: the forward pixel looks at the zenith.
        Camera::new(DVec3::ZERO, 0.0).with_orientation(90.0, 0.0),
    ];
    let mut worst = 0f64;
    for p in PROJECTIONS.iter().chain(&["equirect"]) {
        let img = image(p, 384);
        for camera in cameras {
            let b = camera.basis();
            let dirs: Vec<DVec3> = if camera.pitch_deg == 90.0 {
                vec![DVec3::Y]
            } else {
                dirs.iter().map(|d| d.normalize()).collect()
            };
            for d in dirs {
                let Some((u, v)) = img.projection.position_of_direction(d) else {
                    continue;
                };
                let world = d.x * b.right + d.y * b.forward + d.z * b.up;
                if camera.pitch_deg == 90.0 {
                    assert!((world - DVec3::Z).length() < 1e-12);
                }
                let scene = one_sphere(10.0 * world, 0.3);
                let s = settings(img, camera, Stereo::Mono);
                let want = (u * f64::from(img.width), v * f64::from(img.height));
                let (test, _) = raster
                    .render(&scene, &s, &ProgressBar::hidden())
                    .expect("raster");
                let reference =
                    raytrace::render(&scene, &s, &ProgressBar::hidden()).expect("ray trace");
                for (name, r) in [("raster", &test), ("raytrace", &reference)] {
                    let got = centroid(&frames(r)[0])
                        .unwrap_or_else(|| panic!("{p} {name}: sphere at {d} not drawn"));
                    let err = (got.0 - want.0).abs().max((got.1 - want.1).abs());
                    worst = worst.max(err);
                    assert!(
                        err <= 0.5,
                        "{p} {name} {camera:?}: sphere at {d} drawn at {got:?}, want {want:?}"
                    );
                }
            }
        }
    }
    eprintln!("worst centroid offset {worst:.3} px");
}

#[test]
fn hammer_draws_nothing_outside_its_ellipse() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    // The enclosing sphere covers every direction: the ellipse exactly.
    let scene = raster_common::enclosing_scene();
    let img = image("hammer", 256);
    for stereo in [Stereo::Mono, ods()] {
        let s = settings(img, Camera::new(DVec3::ZERO, 0.0), stereo);
        let (test, _) = raster
            .render(&scene, &s, &ProgressBar::hidden())
            .expect("raster");
        for f in frames(&test) {
            let mut inside = 0;
            for j in 0..img.height {
                for i in 0..img.width {
                    let (u, v) = img.pixel_uv(i, j);
                    let shows = img.projection.angles(u, v).is_some();
                    inside += usize::from(shows);
                    assert_eq!(f.covered(i, j), shows, "pixel ({i}, {j})");
                }
            }
            assert!(inside > 25_000);
        }
    }
}

#[test]
fn a_partial_equirect_is_the_crop_of_the_panorama() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let scene = raster_common::stress_scene(600);
    let camera = Camera::new(DVec3::ZERO, 0.0);
    for stereo in [Stereo::Mono, ods()] {
        let full = settings(Image::equirect(512), camera, stereo);
        let same = settings(image("equirect:360,180", 512), camera, stereo);
        let half = settings(image("equirect:180,90", 256), camera, stereo);
        let render = |s: &RenderSettings| {
            frames(
                &raster
                    .render(&scene, s, &ProgressBar::hidden())
                    .expect("raster")
                    .0,
            )
        };
        let (a, b, c) = (render(&full), render(&same), render(&half));
        assert_eq!(a, b, "equirect:360,180 is the panorama");
        // Pixel (i, j) of the 180 x 90 image at W/2 looks where pixel (i + W/4, j + W/8) of
        // the panorama at W does.
        let (mut coverage, mut depth) = (0, 0f64);
        for (full, crop) in a.iter().zip(&c) {
            for j in 0..crop.height {
                for i in 0..crop.width {
                    let k = crop.index(i, j);
                    let kf = full.index(i + 128, j + 64);
                    if crop.covered(i, j) != full.covered(i + 128, j + 64) {
                        coverage += 1;
                    } else if crop.covered(i, j) {
                        let (x, y) = (crop.depth[k], full.depth[kf]);
                        depth = depth.max(f64::from((x - y).abs() / y));
                        assert_eq!(crop.color[k], full.color[kf]);
                    }
                }
            }
        }
        eprintln!("crop {stereo:?}: {coverage} px coverage differ, depth max {depth:.2e}");
        // Both images take their rays from the same f64 angles, rounded once
        // (src/raster/pixel_trig.rs): nothing may differ.
        assert_eq!(coverage, 0, "{coverage} px differ in coverage");
        assert_eq!(depth, 0.0, "depth differs by {depth}");
    }
}

#[test]
fn an_enclosing_sphere_fills_every_projection() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let scene = raster_common::enclosing_scene();
    let camera = Camera::new(DVec3::ZERO, 0.0).with_orientation(30.0, -20.0);
    for p in PROJECTIONS {
        for (stereo_label, stereo) in [("mono", Stereo::Mono), ("ods", ods())] {
            let s = settings(image(p, 192), camera, stereo);
            agree(
                &raster,
                &scene,
                &s,
                &format!("enclosing {p} {stereo_label}"),
            );
        }
    }
}

#[test]
fn compute_splat_and_drawing_agree_in_every_projection() {
    let Some(mut raster) = raster_common::rasterizer() else {
        return;
    };
    if !raster.can_splat() {
        raster_common::gpu::require_or_skip(&format!(
            "the adapter {} has no 64-bit atomics, so the compute splat cannot run",
            raster.adapter_name()
        ));
        return;
    }
    let scene = raster_common::stress_scene(600);
    let camera = Camera::new(DVec3::ZERO, 20.0).with_orientation(30.0, -20.0);
    let mut runs = Vec::new();
    for limit in [16, 0] {
        raster.set_splat_limit(limit);
        let mut frames_and_counts = Vec::new();
        for p in PROJECTIONS {
            let s = settings(image(p, 288), camera, ods());
            let (r, stats) = raster
                .render(&scene, &s, &ProgressBar::hidden())
                .expect("raster");
            frames_and_counts.push((frames(&r), stats.splatted));
        }
        runs.push(frames_and_counts);
    }
    for (p, (splat, drawn)) in PROJECTIONS.iter().zip(runs[0].iter().zip(&runs[1])) {
        assert!(splat.1 > 300, "{p}: {} spheres splatted", splat.1);
        assert_eq!(drawn.1, 0);
        for (a, b) in splat.0.iter().zip(&drawn.0) {
            let differ = raster_common::differing_pixels(a, b);
            assert_eq!(
                differ, 0,
                "{p}: {differ} pixels differ between splat and draw"
            );
        }
    }
}
