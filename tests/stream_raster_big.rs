//! The out-of-core test, alone in its test binary so that the process's peak resident
//! memory (VmHWM) is this render's: 20,000,000 points streamed through the GPU rasterizer.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::Rendered;
use omnicloud::prepare::PrepareOptions;
use omnicloud::prepare::radius::RadiusChoice;
use omnicloud::projection::{Camera, Equirect};
use omnicloud::render::{ColorMode, RenderSettings};
use omnicloud::stream::{PlanOptions, plan, stream_file};
use raster_common::rasterizer;

/// The test: 20,000,000 points streamed through the GPU rasterizer with peak resident
/// memory (VmHWM) under the cap, which is less than loading the cloud would take.
#[test]
fn twenty_million_points_stream_through_the_gpu_under_the_memory_cap() {
    let Some(raster) = rasterizer() else { return };
    let points: u64 = std::env::var("OMNICLOUD_STREAM_POINTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000_000);
    let cap: u64 = 384 << 20;
    let width = 1024;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("big.las");
    omnicloud::synthetic::write_ground_las(&file, points, &ProgressBar::hidden()).unwrap();
    let chunk = omnicloud::memory::raster_chunk_points(&file, width, 1, cap, false).unwrap();

    let camera = omnicloud::synthetic::GROUND_CORNER + DVec3::new(1000.0, 1000.0, 1.7);
    let radius = omnicloud::synthetic::ground_radius(points);
    let options = PlanOptions {
        prepare: PrepareOptions {
            camera: omnicloud::prepare::CameraChoice::At(camera),
            radius: Some(RadiusChoice::Fixed(radius)),
            ..PrepareOptions::default()
        },
        color: ColorMode::Rgb,
        ..PlanOptions::default()
    };
    let plan = plan(&file, &options, &ProgressBar::hidden()).unwrap();
    let mut s = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
    s.color = ColorMode::Rgb;
    let mut frame = raster.begin_chunked(&s, plan.color, chunk as u32).unwrap();
    // Driver, pipelines and frame are in place: from here on only the stream can grow memory.
    let before = omnicloud::memory::peak_resident().expect("VmHWM");
    let report = stream_file(&plan, chunk, &mut frame, &ProgressBar::hidden()).unwrap();
    let (rendered, stats, _) = frame.finish().unwrap();
    let peak = omnicloud::memory::peak_resident().expect("VmHWM");
    eprintln!(
        "{points} points in chunks of {chunk}: {:.2} M points/s, {stats}, peak RSS {} MiB, {} MiB \
         before streaming (cap {} MiB; the loaded scene alone would be {} MiB)",
        report.points_per_second() / 1e6,
        peak >> 20,
        before >> 20,
        cap >> 20,
        (points * omnicloud::memory::LOADED_BYTES_PER_POINT) >> 20
    );
    assert_eq!(report.read, points);
    assert_eq!(stats.drawn, points);
    assert!(peak < cap, "peak RSS {} MiB over the cap", peak >> 20);
    // Streaming grew the peak by what the chunks need, far less than the points would take.
    let grown = peak.saturating_sub(before);
    assert!(
        grown < 160 << 20,
        "streaming grew the peak by {} MiB",
        grown >> 20
    );

    // What was drawn: ground everywhere below the horizon, at the distance the relief gives.
    let Rendered::Mono(f) = &rendered else {
        panic!("expected a mono frame")
    };
    let img = Equirect::from_width(width);
    let ground_z = omnicloud::synthetic::ground_height(1000.0, 1000.0);
    // The spheres' tops form a surface between the centres and a radius above them.
    let (eye_height, r) = (1.7 - ground_z, radius as f64);
    for j in [img.height - 1, img.height * 2 / 3] {
        let below = -img.pixel_angles(0, j).1.sin();
        let (near, far) = ((eye_height - r) / below, eye_height / below);
        let row = &f.depth[(j * img.width) as usize..((j + 1) * img.width) as usize];
        let hit = row.iter().filter(|d| d.is_finite()).count();
        assert_eq!(hit, img.width as usize, "row {j}: {hit} hits");
        let mean = row.iter().map(|&d| d as f64).sum::<f64>() / row.len() as f64;
        assert!(
            (near - 0.02..=far + 0.02).contains(&mean),
            "row {j}: mean distance {mean}, expected {near}..{far}"
        );
    }
    let tones = [[90, 110, 60, 255], [170, 150, 110, 255]];
    let nadir = &f.color[((img.height - 1) * img.width) as usize..];
    assert!(
        nadir.iter().all(|c| tones.contains(c)),
        "unexpected ground colour"
    );
}
