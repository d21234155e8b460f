//! Runs the speed/accuracy benchmark until the CLI's `omnicloud bench` exists:
//!
//! `cargo run --release --example bench_run -- --suite data/scenes --out DIR [--frames N]`
//! `cargo run --release --example bench_run -- --replot DIR/bench.json --out DIR` (redraw)
//! `cargo run --release --example bench_run -- FILE --out DIR [--width W] [--stereo mono|ods]
//!  [--frames N] [--warmup N]` (camera at the centre of the bounds, radius auto unless the
//! file has per-point radii, colour rgb when present, unlit).

use std::path::PathBuf;
use std::process::ExitCode;

use indicatif::{ProgressBar, ProgressStyle};
use omnicloud::bench::{self, BenchConfig};
use omnicloud::io::{LoadOptions, load_scene};
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{ColorMode, RenderSettings};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let out = PathBuf::from(value("--out").unwrap_or_else(|| "bench_out".into()));
    let mut config = BenchConfig::default();
    if let Some(n) = value("--frames") {
        config.timed_frames = n.parse()?;
    }
    if let Some(n) = value("--warmup") {
        config.warmup_frames = n.parse()?;
    }
    config.width = value("--width").map(|w| w.parse()).transpose()?;
    config.stereo = match value("--stereo").as_deref() {
        None => None,
        Some("mono") => Some(Stereo::Mono),
        Some("ods") => Some(Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging::both(PoleMerge::COMFORTABLE),
            offset: OdsOffset::Exact,
        }),
        Some(s) => return Err(format!("--stereo {s}: expected mono or ods").into()),
    };
    let pb = ProgressBar::new(0).with_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} {elapsed} {msg}",
    )?);
    if let Some(json) = value("--replot") {
        // Redraws the outputs of an earlier run from its bench.json or suite.json.
        let text = std::fs::read_to_string(&json)?;
        if let Ok(report) = serde_json::from_str::<bench::BenchReport>(&text) {
            bench::write_outputs(&report, &out)?;
        } else {
            let report: bench::SuiteReport = serde_json::from_str(&text)?;
            bench::write_suite_outputs(&report, &out)?;
        }
        return Ok(());
    }
    if let Some(dir) = value("--suite") {
        let report = bench::run_suite(&PathBuf::from(dir), &config, &pb)?;
        pb.finish_and_clear();
        let files = bench::write_suite_outputs(&report, &out)?;
        println!("{}", bench::suite_markdown(&report));
        println!("wrote {}", files.json.parent().unwrap_or(&out).display());
        return Ok(());
    }
    let file = PathBuf::from(args.first().ok_or("give a scene file or --suite DIR")?);
    let (mut scene, _) = load_scene(&file, &LoadOptions::default())?;
    if matches!(scene.radii, omnicloud::Radii::Uniform(_)) {
        scene.radii = omnicloud::Radii::Uniform(omnicloud::radius::auto_radius(&scene));
    }
    let mut base = RenderSettings::new(
        config.width.unwrap_or(2048),
        Camera::new(glam::DVec3::ZERO, 0.0),
    );
    if scene.attributes.rgb.is_some() {
        base.color = ColorMode::Rgb;
    }
    let name = file
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let report = bench::run_bench(&name, &scene, &base, &config, &pb)?;
    pb.finish_and_clear();
    let files = bench::write_outputs(&report, &out)?;
    println!("{}", omnicloud::bench::report::markdown(&report));
    println!("wrote {}", files.json.parent().unwrap_or(&out).display());
    Ok(())
}
