//! `omnicloud render` on the streamed raster path, as a user runs it: what it prints, what it
//! refuses before starting, and what an interrupt leaves behind.

#[path = "raster_common/gpu.rs"]
mod gpu;
mod interrupt_common;

use std::process::{Command, Output};

fn omnicloud(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .output()
        .unwrap()
}

/// True when the render failed for want of a GPU adapter, after [`gpu::require_or_skip`]
/// (which fails the test when a GPU is required).
fn no_adapter(success: bool, stderr: &str) -> bool {
    let missing = !success && stderr.contains("no GPU adapter");
    if missing {
        gpu::require_or_skip(&format!(
            "omnicloud render found no adapter: {}",
            stderr.trim()
        ));
    }
    missing
}

/// `omnicloud render` of the bundled sample to `png` with `extra` options; its stderr.
fn render_sample(png: &std::path::Path, extra: &[&str]) -> (Output, String) {
    let mut args = vec![
        "render",
        "data/autzen_trim.laz",
        "-o",
        png.to_str().unwrap(),
    ];
    args.extend(extra);
    let out = omnicloud(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out, stderr)
}

#[test]
fn the_sample_streams_through_the_rasterizer_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("autzen.png");
    let (out, stderr) = render_sample(&png, &["--width", "512"]);
    if no_adapter(out.status.success(), &stderr) {
        return;
    }
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("110000 points"), "{stderr}");
    assert!(stderr.contains("planned from every point"), "{stderr}");
    assert!(stderr.contains("streamed 110000 points"), "{stderr}");
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (512, 256));
}

/// `omnicloud render` of the sample at 64 wide with its pipeline cache in `cache`.
fn render_with_cache(cache: &std::path::Path, png: &std::path::Path) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", "data/autzen_trim.laz", "--width", "64", "-o"])
        .arg(png)
        .env("OMNICLOUD_CACHE_DIR", cache)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_second_process_loads_the_pipeline_cache_and_a_garbage_one_is_rebuilt() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let png = dir.path().join("pano.png");
    let (ok, stderr) = render_with_cache(&cache, &png);
    if no_adapter(ok, &stderr) {
        return;
    }
    assert!(ok, "{stderr}");
    assert!(stderr.contains("pipeline cache created"), "{stderr}");
    let files: Vec<_> = std::fs::read_dir(&cache).unwrap().flatten().collect();
    assert_eq!(files.len(), 1, "one cache file per adapter");
    let file = files[0].path();
    let first = std::fs::read(&file).unwrap();

    let (ok, stderr) = render_with_cache(&cache, &png);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("pipeline cache loaded"), "{stderr}");
    assert_eq!(
        std::fs::read(&file).unwrap(),
        first,
        "a hit leaves the file as it was"
    );

    for garbage in [&b"not a cache at all"[..], &first[..first.len() - 3]] {
        std::fs::write(&file, garbage).unwrap();
        let (ok, stderr) = render_with_cache(&cache, &png);
        assert!(ok, "a bad cache must not fail the render: {stderr}");
        assert!(
            stderr.contains("warning: ignored the pipeline cache"),
            "{stderr}"
        );
        let (ok, stderr) = render_with_cache(&cache, &png);
        assert!(
            ok && stderr.contains("pipeline cache loaded"),
            "rewritten: {stderr}"
        );
    }
}

#[test]
fn subsampling_while_streaming_reports_what_it_kept() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("thin.png");
    let (out, stderr) = render_sample(&png, &["--width", "512", "--subsample", "4"]);
    if no_adapter(out.status.success(), &stderr) {
        return;
    }
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("kept 27500 of 110000 points (25.0%)"),
        "{stderr}"
    );
}

#[test]
fn a_frame_over_the_memory_cap_is_refused_before_anything_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("big.png");
    let (out, stderr) = render_sample(
        &png,
        &["--width", "3840", "--stereo", "ods", "--max-memory", "200M"],
    );
    assert!(!out.status.success());
    for needle in [
        "autzen_trim.laz",
        "3840",
        "stereo",
        "200.0 MiB",
        "--width",
        "--max-memory",
    ] {
        assert!(stderr.contains(needle), "{needle}: {stderr}");
    }
    assert!(!stderr.contains("streamed"), "{stderr}");
    assert!(!png.exists());
}

#[test]
fn sigint_mid_stream_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let las = dir.path().join("ground.las");
    omnicloud::synthetic::write_ground_las(&las, 3_000_000, &indicatif::ProgressBar::hidden())
        .unwrap();
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let png = out_dir.join("pano.png");
    let mut command = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    command
        .args(["render", "--width", "2048", "--stereo", "ods"])
        .arg(&las)
        .arg("-o")
        .arg(&png);
    let run = interrupt_common::interrupt_at_progress(command, "rasterizing");
    if run.cue.is_none() && no_adapter(run.status.success(), &run.stderr()) {
        return;
    }
    interrupt_common::assert_interrupted(&run);
    let left: Vec<_> = std::fs::read_dir(&out_dir).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
