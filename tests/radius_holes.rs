//! Hole share (background enclosed by coverage, `omnicloud::compare::holes`) of the default
//! render against the old default (camera at the centre, half the median spacing) on the lion,
//! Autzen and a generated terrain; and `--radius adaptive` against `auto` from the same camera.
//! Ray tracer, 512 wide. `cargo test --test radius_holes -- --nocapture` prints the table
//! docs/PICTURES.md quotes.

mod data_common;

use std::path::{Path, PathBuf};

use indicatif::ProgressBar;
use omnicloud::compare::holes::{default_reach, holes};
use omnicloud::prepare::{CameraChoice, PrepareOptions, RadiusChoice, prepare};
use omnicloud::projection::Camera;
use omnicloud::raytrace::render;
use omnicloud::render::RenderSettings;
use omnicloud::{Frame, Rendered};

const WIDTH: u32 = 512;

fn autzen() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz")
}

/// A 2 km generated terrain of 40,000 points (10 m spacing), written once per test run.
fn terrain() -> PathBuf {
    let path = std::env::temp_dir().join(format!("omnicloud-holes-{}.las", std::process::id()));
    if !path.exists() {
        omnicloud::synthetic::write_ground_las(&path, 40_000, &ProgressBar::hidden()).unwrap();
    }
    path
}

fn frame(path: &Path, camera: CameraChoice, radius: Option<RadiusChoice>) -> Frame {
    let options = PrepareOptions {
        camera,
        radius,
        ..PrepareOptions::default()
    };
    let prepared = prepare(path, &options, &ProgressBar::hidden()).unwrap();
    let settings = RenderSettings::new(WIDTH, Camera::new(glam::DVec3::ZERO, 0.0));
    match render(&prepared.scene, &settings, &ProgressBar::hidden()).unwrap() {
        Rendered::Mono(f) => f,
        Rendered::Stereo { .. } => unreachable!("mono settings"),
    }
}

/// Hole share and coverage (%) of a render.
fn measure(name: &str, path: &Path, camera: CameraChoice, radius: Option<RadiusChoice>) -> f64 {
    let f = frame(path, camera, radius);
    let s = holes(&f, default_reach(WIDTH));
    println!(
        "{name:<8} camera {camera:<8} radius {:<11} holes {:>6.2} %  coverage {:>5.1} %",
        radius.map_or("default".to_string(), |r| r.to_string()),
        100.0 * s.hole_share(),
        100.0 * s.coverage(),
        camera = format!("{camera:?}").to_lowercase(),
    );
    100.0 * s.hole_share()
}

#[test]
fn default_render_has_fewer_holes_than_the_old_default() {
    let old = Some(RadiusChoice::Auto);
    for (name, path) in [("autzen", autzen()), ("lion", data_common::lion())] {
        let before = measure(name, &path, CameraChoice::Center, old);
        let now = measure(name, &path, CameraChoice::Auto, None);
        assert!(now < before, "{name}: {now} % holes, {before} % before");
        // Measured at 512 wide: Autzen 1.06 % before, 1.01 % now (the camera 27 m up sees the
        // gaps between scan lines that car-sized bubbles at 1.7 m hid); the lion 20.4 % before,
        // 1.42 % now.
        let (was, is) = match name {
            "autzen" => (1.04, 1.03),
            _ => (15.0, 2.0),
        };
        assert!(
            before > was && now < is,
            "{name}: {now} % holes, {before} % before"
        );
    }
}

#[test]
fn adaptive_radius_against_auto() {
    let adaptive = Some(RadiusChoice::Adaptive { k: 8 });
    let terrain = terrain();
    let cases = [
        ("autzen", autzen()),
        ("terrain", terrain.clone()),
        ("lion", data_common::lion()),
    ];
    for (name, path) in cases {
        let auto = measure(name, &path, CameraChoice::Auto, Some(RadiusChoice::Auto));
        let adapt = measure(name, &path, CameraChoice::Auto, adaptive);
        println!("{name}: adaptive {adapt:.2} %, auto {auto:.2} %");
    }
    std::fs::remove_file(terrain).ok();
}
