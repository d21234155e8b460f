//! Out-of-core rasterizing: a file streamed through the GPU in chunks into one frame renders
//! what the in-core path renders, pixel for pixel, and the ray tracer's reference image.
//! (The 20 M-point memory test is in `stream_raster_big.rs`, alone in its process.)

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::io::{LoadOptions, load_scene};
use omnicloud::output::LinearImage;
use omnicloud::prepare::PrepareOptions;
use omnicloud::prepare::radius::RadiusChoice;
use omnicloud::projection::Camera;
use omnicloud::render::{ColorMode, RenderSettings};
use omnicloud::stream::{PlanOptions, plan, stream_file};
use omnicloud::{Rendered, raytrace};
use raster_common::rasterizer;
use std::path::Path;

fn mono(rendered: &Rendered) -> &omnicloud::Frame {
    match rendered {
        Rendered::Mono(f) => f,
        Rendered::Stereo { .. } => panic!("expected a mono frame"),
    }
}

fn settings(width: u32, color: ColorMode) -> RenderSettings {
    let mut s = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
    s.color = color;
    s
}

#[test]
fn a_streamed_real_scan_matches_the_ray_traced_reference() {
    let Some(raster) = rasterizer() else { return };
    let file = Path::new("data/autzen_trim.laz");
    let plan = plan(file, &PlanOptions::default(), &ProgressBar::hidden()).unwrap();
    let whole = plan.whole.clone().expect("a small file is read whole");
    let s = settings(512, ColorMode::Auto);
    // Chunks far smaller than the file: 110,000 points in 7 GPU uploads.
    let mut frame = raster.begin_chunked(&s, plan.color, 16_384).unwrap();
    let report = stream_file(&plan, 16_384, &mut frame, &ProgressBar::hidden()).unwrap();
    assert_eq!(report.read, 110_000);
    assert_eq!(frame.points(), whole.len() as u64);
    let (streamed, stats, _) = frame.finish().unwrap();
    assert!(stats.batches >= 7, "{stats}");

    let reference = raytrace::render(&whole, &s, &ProgressBar::hidden()).unwrap();
    let r = omnicloud::compare::compare(
        &LinearImage::from_frame(mono(&reference)),
        &LinearImage::from_frame(mono(&streamed)),
    )
    .unwrap();
    let all = &r.eyes[0].all;
    eprintln!(
        "streamed vs ray traced: {} px mismatch of {} hits, IoU {}",
        all.mismatch, all.ref_hits, all.iou
    );
    assert!(all.ref_hits > 50_000, "{}", all.ref_hits);
    assert!(all.mismatch <= 2, "{} px mismatch", all.mismatch);
    // Colour from the file's RGB, exactly as the reference colours it.
    let (a, b) = (mono(&reference), mono(&streamed));
    let same = (0..a.color.len())
        .filter(|&k| a.color[k][3] == 255 && a.color[k] == b.color[k])
        .count();
    assert!(
        same as f64 > 0.999 * all.ref_hits as f64,
        "{same} of {}",
        all.ref_hits
    );
}

/// A file larger than the survey, drawn chunk by chunk, gives exactly the in-core render.
#[test]
fn a_file_larger_than_the_survey_streams_exactly_like_the_in_core_render() {
    let Some(raster) = rasterizer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("ground.las");
    let points = 250_000;
    omnicloud::synthetic::write_ground_las(&file, points, &ProgressBar::hidden()).unwrap();
    let camera = omnicloud::synthetic::GROUND_CORNER + DVec3::new(1000.0, 1000.0, 1.7);
    let radius = omnicloud::synthetic::ground_radius(points);
    let options = PlanOptions {
        prepare: PrepareOptions {
            camera: omnicloud::prepare::CameraChoice::At(camera),
            radius: Some(RadiusChoice::Fixed(radius)),
            ..PrepareOptions::default()
        },
        color: ColorMode::Rgb,
        survey_points: 20_000,
    };
    let plan = plan(&file, &options, &ProgressBar::hidden()).unwrap();
    assert!(plan.whole.is_none(), "the survey must sample, not read all");
    let s = settings(512, ColorMode::Rgb);
    let mut frame = raster.begin_chunked(&s, plan.color, 30_000).unwrap();
    let report = stream_file(&plan, 30_000, &mut frame, &ProgressBar::hidden()).unwrap();
    assert_eq!((report.read, report.drawn), (points, points));
    let (streamed, _, _) = frame.finish().unwrap();

    let (mut scene, _) = load_scene(
        &file,
        &LoadOptions {
            origin: Some(camera),
            ..LoadOptions::default()
        },
    )
    .unwrap();
    scene.radii = omnicloud::Radii::Uniform(radius);
    let (in_core, _) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
    let (a, b) = (mono(&in_core), mono(&streamed));
    let differ = raster_common::differing_pixels(a, b);
    assert_eq!(differ, 0, "{differ} pixels differ from the in-core render");
    // The lower hemisphere is ground; colours are the file's two tones, 16-bit scaled.
    let hits = a.color.iter().filter(|c| c[3] == 255).count();
    assert!(hits as f64 > 0.45 * a.color.len() as f64, "{hits}");
}
