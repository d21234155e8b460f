//! The rasterizer (`bounds` + `raycast`) against the CPU ray tracer, through `compare`, on the
//! real sample and on the stress scene, mono and ODS with pole merging: at most
//! [`COVERAGE_MAX_PX`] pixels differ in coverage per eye (lavapipe: at most 1), depth relative
//! error p99 <= [`DEPTH_P99_MAX`] (lavapipe: up to 7.4e-7), and unlit colour identical where
//! both hit.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::compare::{CompareReport, compare};
use omnicloud::output::LinearImage;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings};
use omnicloud::{Rendered, Scene, raytrace};

/// Coverage mismatches allowed per eye (measured: at most 1).
const COVERAGE_MAX_PX: u64 = 2;
/// Depth relative error p99 allowed (measured: at most 4.4e-7).
const DEPTH_P99_MAX: f64 = 6e-7;

fn settings(width: u32, stereo: Stereo, color: ColorMode) -> RenderSettings {
    let mut s = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
    s.stereo = stereo;
    s.color = color;
    s.proxy = Proxy::Bounds;
    s.imposter = Imposter::Raycast;
    s
}

fn ods(north: PoleMerge, south: PoleMerge) -> Stereo {
    Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging { north, south },
        offset: OdsOffset::Exact,
    }
}

fn as_image(r: &Rendered) -> LinearImage {
    LinearImage::from_frame(&r.top_bottom())
}

/// Renders with both renderers and checks the thresholds on every eye.
fn agree(scene: &Scene, settings: &RenderSettings, label: &str) -> Option<CompareReport> {
    let raster = raster_common::rasterizer()?;
    let (test, _) = raster
        .render(scene, settings, &ProgressBar::hidden())
        .expect("raster render");
    let reference = raytrace::render(scene, settings, &ProgressBar::hidden()).expect("ray trace");
    let report = compare(&as_image(&reference), &as_image(&test)).expect("same size");
    for eye in &report.eyes {
        let all = &eye.all;
        eprintln!(
            "{label} {}: mismatch {} px ({:.4}%), depth p99 {:?}, colour rmse {:?}",
            eye.eye,
            all.mismatch,
            all.mismatch_percent,
            all.depth_relative.as_ref().map(|d| d.p99),
            all.color_rmse
        );
        assert!(all.ref_hits > 1000, "{label}: too few hits to judge");
        assert!(
            all.mismatch <= COVERAGE_MAX_PX,
            "{label} {}: coverage differs on {} px",
            eye.eye,
            all.mismatch
        );
        let depth = all.depth_relative.as_ref().expect("both hit somewhere");
        assert!(
            depth.p99 <= DEPTH_P99_MAX,
            "{label} {}: depth p99 {}",
            eye.eye,
            depth.p99
        );
        assert_eq!(all.color_rmse, Some(0.0), "{label} {}: colour", eye.eye);
    }
    Some(report)
}

#[test]
fn real_sample_mono() {
    agree(
        &raster_common::autzen_at_centre(),
        &settings(1024, Stereo::Mono, ColorMode::Rgb),
        "autzen mono",
    );
}

#[test]
fn real_sample_ods_with_pole_merging() {
    let stereo = ods(PoleMerge::COMFORTABLE, PoleMerge::CYCLES_DEFAULT);
    agree(
        &raster_common::autzen_at_centre(),
        &settings(1024, stereo, ColorMode::Rgb),
        "autzen ods",
    );
}

#[test]
fn stress_scene_ods_with_pole_merging() {
    let scene = raster_common::stress_scene(1500);
    for (label, stereo) in [
        ("stress mono", Stereo::Mono),
        (
            "stress ods comfortable",
            ods(PoleMerge::COMFORTABLE, PoleMerge::COMFORTABLE),
        ),
        (
            "stress ods cycles/off",
            ods(PoleMerge::CYCLES_DEFAULT, PoleMerge::Off),
        ),
    ] {
        agree(&scene, &settings(768, stereo, ColorMode::Rgb), label);
    }
}
