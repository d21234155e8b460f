//! Eye-dome lighting: a depth step darkens its far side only, across the seam and over the
//! poles as inside the image, and the pass gives the same image from both renderers.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::shading::{linear_to_srgb, srgb_to_linear};
use omnicloud::render::{ColorMode, Edl, Look, RenderSettings};
use omnicloud::{Frame, Rendered, raytrace};

const GREY: [u8; 4] = [200, 200, 200, 255];

/// A 128 x 64 frame, all covered in grey, depth `depth(i, j)`.
fn frame(depth: impl Fn(u32, u32) -> f32) -> Frame {
    let mut f = Frame::new(128, 64);
    for j in 0..64 {
        for i in 0..128 {
            let k = f.index(i, j);
            f.color[k] = GREY;
            f.depth[k] = depth(i, j);
        }
    }
    f
}

fn shaded(mut f: Frame) -> Frame {
    let edl = Edl::default();
    let angle = edl.angle(f.height);
    edl.apply(&mut f, angle);
    f
}

fn grey_at(f: &Frame, i: u32, j: u32) -> u8 {
    f.color[f.index(i, j)][0]
}

#[test]
fn a_depth_step_darkens_its_far_side_and_wraps_at_the_seam() {
    // Near (10 m) in columns 0..64, far (20 m) in 64..128: one step at column 64 and one
    // across the seam between column 127 and column 0.
    let f = shaded(frame(|i, _| if i < 64 { 10.0 } else { 20.0 }));
    for j in [20, 32, 40] {
        // The far side of each step darkens: one of the eight neighbours is a whole stop
        // (log2 = 1) nearer, exp(-300/8) ~ 0.
        assert!(grey_at(&f, 64, j) < 5, "row {j}: {}", grey_at(&f, 64, j));
        // The step across the seam darkens column 127 exactly as the inner one darkens 64.
        assert_eq!(grey_at(&f, 127, j), grey_at(&f, 64, j), "row {j}");
        // The near side and flat depth keep their colour.
        for i in [0, 32, 63, 96, 100] {
            assert_eq!(grey_at(&f, i, j), 200, "({i}, {j})");
        }
    }
    // Depth and coverage are untouched.
    assert_eq!(f.depth[f.index(64, 32)], 20.0);
    assert_eq!(f.coverage_count(), 128 * 64);
}

#[test]
fn a_gentle_slope_darkens_by_the_formula_and_strength_zero_not_at_all() {
    // 1% more distance per column eastward: the west neighbour (1.4 columns west) and the
    // north-west and south-west ones (1.4 cos 45° columns) are nearer by their column offset
    // times log2(1.01) (interpolated between columns).
    let base = frame(|i, _| 10.0 * 1.01f32.powi(i as i32 % 64));
    let f = shaded(base.clone());
    let columns = 1.4 * (1.0 + 2.0 * std::f32::consts::FRAC_1_SQRT_2);
    let shade = (-300.0 * columns * 1.01f32.log2() / 8.0).exp();
    let expected = linear_to_srgb(srgb_to_linear(200) * shade);
    assert_eq!(expected, 86);
    for j in [31, 32] {
        let g = grey_at(&f, 30, j);
        assert!(g.abs_diff(expected) <= 1, "row {j}: {g}");
    }
    // At 32° latitude the same angle spans more columns (1/cos): west neighbours two
    // columns away are nearer still, so the same slope per column darkens more.
    assert!(
        grey_at(&f, 30, 20) < expected - 10,
        "{}",
        grey_at(&f, 30, 20)
    );
    let mut zero = base.clone();
    Edl {
        strength: 0.0,
        ..Edl::default()
    }
    .apply(&mut zero, 0.1);
    assert_eq!(zero, base);
}

#[test]
fn neighbours_past_a_pole_lie_on_the_opposite_meridian() {
    // Far (20 m) everywhere but a near (10 m) patch in the top rows around column 32.
    let f = shaded(frame(|i, j| {
        if j < 2 && (16..48).contains(&i) {
            10.0
        } else {
            20.0
        }
    }));
    // Column 96 is 180° from column 32: its neighbours north of the top row cross the pole
    // into the near patch, so it darkens though no near pixel is in its own columns.
    assert!(grey_at(&f, 96, 0) < 100, "{}", grey_at(&f, 96, 0));
    // Far enough from the pole, nothing crosses it.
    assert_eq!(grey_at(&f, 96, 4), 200);
    // The same at the south pole, mirrored.
    let f = shaded(frame(|i, j| {
        if j > 61 && (16..48).contains(&i) {
            10.0
        } else {
            20.0
        }
    }));
    assert!(grey_at(&f, 96, 63) < 100, "{}", grey_at(&f, 96, 63));
    assert_eq!(grey_at(&f, 96, 59), 200);
}

#[test]
fn background_neighbours_do_not_darken_and_background_stays_transparent() {
    let mut f = frame(|i, _| if i < 64 { 10.0 } else { 20.0 });
    for j in 0..64 {
        for i in 60..64 {
            let k = f.index(i, j);
            f.color[k] = [0, 0, 0, 0];
            f.depth[k] = f32::INFINITY;
        }
    }
    let out = shaded(f.clone());
    // Column 64's only nearer neighbours were the near columns, now background.
    assert_eq!(grey_at(&out, 64, 32), 200);
    assert_eq!(out.color[out.index(62, 32)], [0, 0, 0, 0]);
}

/// Pixels whose colour differs by more than one level in any channel, and the pixels that
/// differ in coverage.
fn differences(a: &Rendered, b: &Rendered) -> (usize, usize) {
    let (a, b) = (a.top_bottom(), b.top_bottom());
    let coverage = a
        .color
        .iter()
        .zip(&b.color)
        .filter(|(x, y)| (x[3] == 0) != (y[3] == 0))
        .count();
    let color = a
        .color
        .iter()
        .zip(&b.color)
        .filter(|(x, y)| (0..3).any(|c| x[c].abs_diff(y[c]) > 1))
        .count();
    (color, coverage)
}

#[test]
fn both_renderers_give_the_same_edl_image() {
    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let look = Look {
        edl: Some(Edl::default()),
        ..Look::default()
    };
    let scene = raster_common::autzen_at_centre();
    for stereo in [
        Stereo::Mono,
        Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging {
                north: PoleMerge::COMFORTABLE,
                south: PoleMerge::COMFORTABLE,
            },
            offset: OdsOffset::Exact,
        },
    ] {
        let mut settings = RenderSettings::new(256, Camera::new(DVec3::ZERO, 0.0));
        settings.stereo = stereo;
        settings.color = ColorMode::Flat;
        let pb = ProgressBar::hidden();
        let (gpu, _) = raster.render(&scene, &settings, &pb).expect("raster");
        let cpu = raytrace::render(&scene, &settings, &pb).expect("ray trace");
        let (_, plain_coverage) = differences(&gpu, &cpu);
        let (gpu, cpu_edl) = (look.finish(gpu), look.finish(cpu.clone()));
        let (color, coverage) = differences(&gpu, &cpu_edl);
        let (edl_changed, _) = differences(&cpu, &cpu_edl);
        eprintln!(
            "{stereo:?}: EDL changed {edl_changed} px; raster and ray tracer differ in coverage \
             on {coverage} px, in EDL colour on {color} px"
        );
        assert!(edl_changed > 2000, "EDL changed only {edl_changed} px");
        assert_eq!(coverage, plain_coverage, "EDL changed coverage");
        // Only the few pixels whose coverage differs, and their neighbours, may differ.
        assert!(color <= 9 * coverage, "{color} px differ");
    }
}
