//! `bounds` + `raycast` against a brute-force f64 reference (per pixel `View::pixel_ray`
//! against every sphere): coverage, depth and colour agree on the stress scene, mono and ODS
//! with pole merging, and with a sphere enclosing the eye.
//!
//! Thresholds, near what lavapipe measures (0 px coverage mismatch, depth p99 up to 5.9e-7,
//! max up to 5.3e-5, no colour difference): at most [`COVERAGE_MAX_PX`] pixels differ in
//! coverage per eye, depth relative error p99 <= [`DEPTH_P99_MAX`] and max <=
//! [`DEPTH_MAX`] (f32 depth), unlit colour identical where the nearest sphere is unambiguous.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::Rendered;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{
    ColorMode, ColorRule, Imposter, Proxy, RenderSettings, Shading, base_colors,
};
use raster_common::*;

const WIDTH: u32 = 512;
/// Coverage mismatches allowed per eye (of 131,072 pixels; measured: at most 1).
const COVERAGE_MAX_PX: u64 = 2;
/// Depth relative error p99 allowed (measured: at most 4.4e-7).
const DEPTH_P99_MAX: f64 = 6e-7;
/// Largest depth relative error allowed.
const DEPTH_MAX: f64 = 2e-4;

fn settings(stereo: Stereo) -> RenderSettings {
    let mut s = RenderSettings::new(WIDTH, Camera::new(DVec3::ZERO, 0.0));
    s.stereo = stereo;
    s.color = ColorMode::Rgb;
    s.proxy = Proxy::Bounds;
    s.imposter = Imposter::Raycast;
    s
}

fn ods(merging: PoleMerging) -> Stereo {
    Stereo::Ods {
        ipd: 0.064,
        merging,
        offset: OdsOffset::Exact,
    }
}

/// Renders and checks every view against the reference; returns the agreements.
fn check(scene: &omnicloud::Scene, settings: &RenderSettings, label: &str) {
    let Some(raster) = rasterizer() else { return };
    let (rendered, stats) = raster
        .render(scene, settings, &ProgressBar::hidden())
        .expect("render");
    eprintln!("{label}: {stats:?}");
    let frames = match &rendered {
        Rendered::Mono(f) => vec![f],
        Rendered::Stereo { left, right } => vec![left, right],
    };
    let colors = base_colors(scene, settings.color).unwrap();
    for (view, frame) in settings.views().iter().zip(frames) {
        let reference = reference(scene, settings, view);
        let a = compare(frame, &reference, &colors, settings);
        let all = a.all();
        eprintln!(
            "{label} eye {}: {} px both, coverage mismatch {} px ({:.4}%), depth p99 {:.2e} max {:.2e}, colour differs {} ({} unambiguous)",
            view.eye_sign,
            all.both_hits(),
            all.mismatch,
            100.0 * a.coverage_fraction(),
            a.depth_rel_p99(),
            all.depth_relative.as_ref().map_or(0.0, |d| d.max),
            all.color_differs,
            a.color_diff
        );
        assert!(
            all.both_hits() > 500,
            "{label}: too few hits to judge ({})",
            all.both_hits()
        );
        assert!(
            all.mismatch <= COVERAGE_MAX_PX,
            "{label}: coverage differs on {} px ({:.4}%)",
            all.mismatch,
            100.0 * a.coverage_fraction()
        );
        assert!(
            a.depth_rel_p99() <= DEPTH_P99_MAX,
            "{label}: depth p99 {}",
            a.depth_rel_p99()
        );
        let depth_max = all.depth_relative.as_ref().map_or(0.0, |d| d.max);
        assert!(depth_max <= DEPTH_MAX, "{label}: depth max {depth_max}");
        assert_eq!(
            a.color_diff, 0,
            "{label}: colour differs on unambiguous hits"
        );
    }
}

#[test]
fn one_sphere_ahead_matches_reference_mono() {
    let mut scene = omnicloud::Scene::new(DVec3::ZERO, vec![glam::Vec3::new(0.3, 2.0, 0.2)], 0.4);
    scene.attributes.rgb = Some(vec![[200, 100, 50]]);
    check(&scene, &settings(Stereo::Mono), "one sphere mono");
}

#[test]
fn stress_scene_mono() {
    check(&stress_scene(1500), &settings(Stereo::Mono), "stress mono");
}

#[test]
fn stress_scene_ods_without_merging() {
    check(
        &stress_scene(1500),
        &settings(ods(PoleMerging::OFF)),
        "stress ods",
    );
}

#[test]
fn stress_scene_ods_marrinan_merging() {
    check(
        &stress_scene(1500),
        &settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE))),
        "stress ods marrinan",
    );
}

#[test]
fn stress_scene_ods_cycles_merging_per_pole_and_yaw() {
    let mut s = settings(ods(PoleMerging {
        north: PoleMerge::CYCLES_DEFAULT,
        south: PoleMerge::Off,
    }));
    s.camera.yaw_deg = 37.0;
    check(&stress_scene(1500), &s, "stress ods cycles/off yaw 37");
}

#[test]
fn sphere_enclosing_the_eye_shows_its_inside() {
    check(
        &enclosing_scene(),
        &settings(Stereo::Mono),
        "enclosing mono",
    );
    check(
        &enclosing_scene(),
        &settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE))),
        "enclosing ods",
    );
}

#[test]
fn small_batches_through_one_depth_buffer_give_the_same_frames() {
    let Some(mut raster) = rasterizer() else {
        return;
    };
    let scene = stress_scene(1500);
    let s = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
    let (whole, one) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
    raster.set_batch_limit(Some(97));
    let (batched, many) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
    assert_eq!(one.batches, 2);
    assert_eq!(many.batches, 2 * scene.len().div_ceil(97) as u64);
    assert_eq!(one.drawn, many.drawn);
    assert!(whole == batched, "batched frames differ");
}

#[test]
fn pipelines_are_compiled_for_the_modes_drawn_only() {
    let Some(raster) = rasterizer() else {
        return;
    };
    assert_eq!(raster.compiled_pipelines(), 0, "nothing drawn yet");
    let scene = stress_scene(100);
    let mono = settings(Stereo::Mono);
    let stereo = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
    let pb = ProgressBar::hidden();
    let (first, _) = raster.render(&scene, &mono, &pb).unwrap();
    assert_eq!(raster.compiled_pipelines(), 1);
    raster.render(&scene, &stereo, &pb).unwrap();
    assert_eq!(raster.compiled_pipelines(), 2, "mono and ODS");
    let (again, _) = raster.render(&scene, &mono, &pb).unwrap();
    assert_eq!(
        raster.compiled_pipelines(),
        2,
        "mono's pipelines are reused"
    );
    assert!(first == again, "the reused pipelines draw the same frame");
}

#[test]
fn frames_drawn_into_reused_buffers_are_the_same() {
    let Some(raster) = rasterizer() else {
        return;
    };
    // From its second frame on a rasterizer keeps its images (keys or targets) and buffers
    // for the next frame of the same shape: nothing of one frame may reach the next.
    let scene = stress_scene(1500);
    let ahead = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
    let mut turned = ahead;
    turned.camera = Camera::new(DVec3::new(0.3, -0.2, 0.1), 90.0);
    let pb = ProgressBar::hidden();
    let (fresh, stats) = raster.render(&scene, &ahead, &pb).unwrap();
    assert!(
        stats.splatted > 1000,
        "the splat keys are exercised: {stats}"
    );
    let (other, _) = raster.render(&scene, &turned, &pb).unwrap();
    assert!(fresh != other, "the two views differ");
    for k in 0..2 {
        let (reused, _) = raster.render(&scene, &ahead, &pb).unwrap();
        assert!(fresh == reused, "frame {} in reused buffers differs", k + 3);
        // Handed back, the other view's frames are where the next one is read back into.
        let (turned_frames, _) = raster.render(&scene, &turned, &pb).unwrap();
        assert!(turned_frames == other);
        raster.recycle(turned_frames);
    }
    let (into_recycled, _) = raster.render(&scene, &ahead, &pb).unwrap();
    assert!(
        fresh == into_recycled,
        "a frame read into recycled memory differs"
    );
    // Another shape in between replaces the kept buffers; its mono frame, handed back, has
    // an eye's size and is read into by the next frame.
    raster.recycle(
        raster
            .render(&scene, &settings(Stereo::Mono), &pb)
            .unwrap()
            .0,
    );
    let (last, _) = raster.render(&scene, &ahead, &pb).unwrap();
    assert!(fresh == last, "the first shape again differs");
    // The drawn targets (billboards and sprites) read back into recycled frames too.
    let drawn = |mut s: RenderSettings| {
        s.proxy = Proxy::Quad;
        s.imposter = Imposter::Sprite;
        s
    };
    let (fresh_drawn, _) = raster.render(&scene, &drawn(ahead), &pb).unwrap();
    for _ in 0..2 {
        raster.recycle(raster.render(&scene, &drawn(turned), &pb).unwrap().0);
        let (reused, _) = raster.render(&scene, &drawn(ahead), &pb).unwrap();
        assert!(
            fresh_drawn == reused,
            "a drawn frame read into recycled memory differs"
        );
    }
}

#[test]
fn compute_splat_and_drawing_give_the_same_frames() {
    let Some(mut raster) = rasterizer() else {
        return;
    };
    if !raster.can_splat() {
        // Without the splat this would compare drawing with drawing and test nothing.
        gpu::require_or_skip(&format!(
            "the adapter {} has no 64-bit atomics, so the compute splat cannot run",
            raster.adapter_name()
        ));
        return;
    }
    let scene = stress_scene(1500);
    // Every shading: the keyed path shades each hit into its pixel's key, the drawn path each
    // fragment into the render targets.
    for shading in [Shading::Unlit, Shading::Phong, Shading::Normal] {
        let mut s = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
        s.shading = shading;
        raster.set_splat_limit(16);
        let (splatted, with) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
        raster.set_splat_limit(0);
        let (drawn, without) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
        eprintln!("{shading:?} splat: {with}\ndraw: {without}");
        assert_eq!(without.splatted, 0);
        assert!(with.splatted > 1000, "too few spheres splatted: {with}");
        // ODS pairs: spheres over 32 pixels go to the wide splat, which must agree too.
        assert!(
            (150..=185).contains(&with.wide),
            "spheres cast wide: {with}"
        );
        assert!(with.vertices < without.vertices);
        assert_eq!(with.drawn, without.drawn);
        let pairs = match (&splatted, &drawn) {
            (
                Rendered::Stereo { left, right },
                Rendered::Stereo {
                    left: l2,
                    right: r2,
                },
            ) => [(left, l2), (right, r2)],
            _ => panic!("ODS renders two eyes"),
        };
        for (a, b) in pairs {
            let differ = differing_pixels(a, b);
            assert_eq!(
                differ, 0,
                "{shading:?}: {differ} pixels differ between splat and draw"
            );
        }
    }
}

/// A screen of large spheres 3 m ahead, then a crowd of small ones: half 15-25 m away, half
/// from 2.2 m to 3.6 m, in front of the screen, poking through it and behind it.
fn screen_and_crowd(crowd: usize) -> (omnicloud::Scene, usize) {
    let mut positions = Vec::new();
    let mut radii = Vec::new();
    for i in 0..11 {
        for j in 0..11 {
            let (x, z) = (-1.5 + 0.3 * i as f32, -1.5 + 0.3 * j as f32);
            positions.push(glam::Vec3::new(x, 3.0, z));
            radii.push(0.4);
        }
    }
    let screen = positions.len();
    let mut rng = omnicloud::rng::SplitMix64::new(7);
    for k in 0..crowd {
        let (x, z) = (rng.range(-0.8, 0.8), rng.range(-0.8, 0.8));
        let y = if k % 2 == 0 {
            rng.range(15.0, 25.0)
        } else {
            rng.range(2.2, 3.6)
        };
        positions.push(glam::Vec3::new(x as f32, y as f32, z as f32));
        radii.push(0.05);
    }
    let scene = omnicloud::Scene {
        origin: DVec3::ZERO,
        positions,
        radii: omnicloud::Radii::PerPoint(radii),
        attributes: Default::default(),
    };
    (scene, screen)
}

/// Renders `scene` in one batch and in batches of `first` points (the occluders first), mono
/// and ODS, unlit and Phong, 1024 wide and 1002 wide heading away (so the last column of
/// tiles is 2 pixels wide and tiles straddle the seam): the frames must be the same, and at
/// least `hidden` spheres per eye skipped in batches, at most the `behind` that can be.
fn assert_hidden_spheres_skipped(
    raster: &mut omnicloud::raster::Rasterizer,
    scene: &omnicloud::Scene,
    first: usize,
    (hidden, behind): (u64, u64),
) {
    let ods = ods(PoleMerging::both(PoleMerge::COMFORTABLE));
    let cases = [
        (Stereo::Mono, Shading::Unlit, 1024, 0.0),
        (Stereo::Mono, Shading::Phong, 1024, 0.0),
        (ods, Shading::Unlit, 1024, 0.0),
        (ods, Shading::Phong, 1024, 0.0),
        (ods, Shading::Unlit, 1002, 180.0),
    ];
    for (stereo, shading, width, yaw) in cases {
        let mut s = settings(stereo);
        s.image = omnicloud::projection::Image::equirect(width);
        s.camera = Camera::new(DVec3::ZERO, yaw);
        s.color = ColorMode::Elevation;
        s.shading = shading;
        // In one batch the hidden spheres are splatted before anything is known to hide
        // them. With the occluders in a batch of their own, later batches find their tiles
        // filled.
        raster.set_batch_limit(None);
        let (whole, one) = raster.render(scene, &s, &ProgressBar::hidden()).unwrap();
        raster.set_batch_limit(Some(first as u32));
        let (culled, many) = raster.render(scene, &s, &ProgressBar::hidden()).unwrap();
        raster.set_batch_limit(None);
        eprintln!("{stereo:?} {shading:?} {width} {yaw}\none batch: {one}\nbatches: {many}");
        let eyes = s.views().len() as u64;
        assert_eq!(one.occluded, 0);
        assert_eq!(one.drawn, many.drawn);
        assert!(
            whole == culled,
            "culling the hidden spheres changed the frames"
        );
        assert!(
            many.occluded >= hidden * eyes && many.occluded <= behind * eyes,
            "{many}"
        );
    }
}

/// The adapter's rasterizer when it can cull (it has the keyed path), else `None` after
/// reporting the skip.
fn culling_rasterizer() -> Option<omnicloud::raster::Rasterizer> {
    let raster = rasterizer()?;
    if !raster.can_splat() {
        gpu::require_or_skip(&format!(
            "the adapter {} has no 64-bit atomics, so spheres are not culled",
            raster.adapter_name()
        ));
        return None;
    }
    Some(raster)
}

#[test]
fn spheres_hidden_whole_are_skipped_and_change_no_pixel() {
    let Some(mut raster) = culling_rasterizer() else {
        return;
    };
    let crowd = 2000;
    let (scene, screen) = screen_and_crowd(crowd);
    // Measured: 1,408 of the 2,000 hidden in mono, 2,772 to 2,815 of 4,000 in ODS.
    assert_hidden_spheres_skipped(&mut raster, &scene, screen, (1380, crowd as u64));
}

/// A wall of small spheres 3 m ahead, none large enough to hide a tile alone, then `crowd`
/// as large 5-10 m away, around it: some behind it, some seen past its edges.
fn small_wall_and_crowd(crowd: usize) -> (omnicloud::Scene, usize) {
    let mut positions = Vec::new();
    for i in 0..31 {
        for j in 0..31 {
            let (x, z) = (-0.6 + 0.04 * i as f32, -0.6 + 0.04 * j as f32);
            positions.push(glam::Vec3::new(x, 3.0, z));
        }
    }
    let wall = positions.len();
    let mut rng = omnicloud::rng::SplitMix64::new(11);
    for _ in 0..crowd {
        let (x, z) = (rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
        positions.push(glam::Vec3::new(
            x as f32,
            rng.range(5.0, 10.0) as f32,
            z as f32,
        ));
    }
    let scene = omnicloud::Scene {
        origin: DVec3::ZERO,
        positions,
        radii: omnicloud::Radii::Uniform(0.03),
        attributes: Default::default(),
    };
    (scene, wall)
}

#[test]
fn spheres_behind_many_small_ones_are_skipped_once_their_tiles_resolve() {
    let Some(mut raster) = culling_rasterizer() else {
        return;
    };
    let crowd = 1000;
    let (scene, wall) = small_wall_and_crowd(crowd);
    // Every sphere is splatted, and a splatted sphere records no tile: only the resolve of
    // the wall's keys between batches can hide the crowd. Measured: 829 of the 1,000 hidden in
    // mono, 1,655 of 2,000 in ODS, 1,458 heading away across the seam.
    assert_hidden_spheres_skipped(&mut raster, &scene, wall, (720, crowd as u64));
}

#[test]
fn pieces_drawn_into_one_chunked_frame_give_the_same_frames() {
    let Some(raster) = rasterizer() else {
        return;
    };
    let scene = stress_scene(1500);
    let s = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
    let (whole, one) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
    // Uneven pieces, each split again by a GPU chunk of 211 points.
    let rule = ColorRule::for_scene(&scene, s.color).unwrap();
    let mut frame = raster.begin_chunked(&s, rule, 211).unwrap();
    let mut start = 0;
    for len in [1, 500, 7, 211, 212, 1000] {
        let end = (start + len).min(scene.len());
        frame.draw(&scene.range(start..end)).unwrap();
        start = end;
    }
    assert_eq!(frame.points(), scene.len() as u64);
    let (pieces, many, _) = frame.finish().unwrap();
    assert_eq!(one.drawn, many.drawn);
    assert!(many.batches > one.batches, "{many}");
    assert!(whole == pieces, "frames drawn in pieces differ");
    // And they are not trivially equal: something was drawn.
    let Rendered::Stereo { left, .. } = &pieces else {
        panic!("ODS renders two eyes")
    };
    assert!(left.color.iter().filter(|c| c[3] == 255).count() > 10_000);
}

/// `scene` with every point repeated after the last: the copies keep positions and radii and
/// take `recolor` of the colour.
fn with_copies(scene: &omnicloud::Scene, recolor: impl Fn([u8; 3]) -> [u8; 3]) -> omnicloud::Scene {
    let mut doubled = scene.clone();
    doubled.positions.extend_from_within(..);
    if let omnicloud::Radii::PerPoint(r) = &mut doubled.radii {
        r.extend_from_within(..);
    }
    let rgb = doubled
        .attributes
        .rgb
        .as_mut()
        .expect("the stress scene has colours");
    let copies: Vec<[u8; 3]> = rgb.iter().map(|&c| recolor(c)).collect();
    rgb.extend(copies);
    doubled
}

#[test]
fn coincident_spheres_show_the_lowest_index_lit_and_one_colour_whatever_the_order_unlit() {
    let Some(raster) = rasterizer() else { return };
    let base = stress_scene(300);
    let invert = |[r, g, b]: [u8; 3]| [255 - r, 255 - g, 255 - b];
    // The same spheres twice, the originals first or the inverted copies first.
    let originals_first = with_copies(&base, invert);
    let mut inverted = base.clone();
    for c in inverted.attributes.rgb.as_mut().unwrap() {
        *c = invert(*c);
    }
    let inverted_first = with_copies(&inverted, invert);
    let pb = ProgressBar::hidden();
    let render = |scene: &omnicloud::Scene, shading| {
        let mut s = settings(ods(PoleMerging::both(PoleMerge::COMFORTABLE)));
        s.shading = shading;
        let (rendered, stats) = raster.render(scene, &s, &pb).unwrap();
        match rendered {
            Rendered::Stereo { left, right } => (vec![left, right], stats),
            Rendered::Mono(_) => panic!("ODS renders two eyes"),
        }
    };
    let same = |a: &[omnicloud::Frame], b: &[omnicloud::Frame]| {
        a.iter()
            .zip(b)
            .map(|(a, b)| differing_pixels(a, b))
            .sum::<usize>()
    };
    // Lit: every pixel shows the copy of the lower index, as the ray tracer's tie rule.
    for shading in [Shading::Phong, Shading::Normal] {
        let (doubled, stats) = render(&originals_first, shading);
        assert!(
            stats.splatted > 300 && stats.drawn > stats.splatted,
            "{stats}"
        );
        assert_eq!(same(&doubled, &render(&base, shading).0), 0, "{shading:?}");
        let (doubled, _) = render(&inverted_first, shading);
        assert_eq!(
            same(&doubled, &render(&inverted, shading).0),
            0,
            "{shading:?}"
        );
    }
    // Unlit: one colour of the two, the same whatever order the copies come in.
    let (a, _) = render(&originals_first, Shading::Unlit);
    let (b, _) = render(&inverted_first, Shading::Unlit);
    assert_eq!(same(&a, &b), 0);
    let (plain, _) = render(&base, Shading::Unlit);
    let (flipped, _) = render(&inverted, Shading::Unlit);
    for ((a, p), f) in a.iter().zip(&plain).zip(&flipped) {
        let changed = (0..a.color.len())
            .filter(|&k| a.color[k] != p.color[k] && a.color[k] != f.color[k])
            .count();
        assert_eq!(changed, 0, "pixels that show neither copy");
    }
}
