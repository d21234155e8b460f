//! Faults during long runs, at a small scale:
//!
//! - `kill -9` at seeded random moments of a tour, resumed each time: every frame on disk
//!   after each kill is whole, and the finished folder is byte for byte an uninterrupted run's;
//! - a full disk (`ulimit -f`, with `SIGXFSZ` ignored so that `write` fails with `EFBIG`)
//!   while writing a render, an index, a tour frame and a video: exit status non-zero, an
//!   error naming the file, no partial or temporary file, earlier frames intact.
//!
//! The ray tracer renders (deterministic and without a GPU). `tools/kill_resume.sh` is the
//! long version of the first check.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use omnicloud::rng::SplitMix64;

const SCAN: &str = "data/autzen_trim.laz";
const WALK: &str = "data/tours/autzen_walk.csv";

fn omnicloud() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    c.env_remove("OMNICLOUD_PROGRESS");
    for v in [
        "SLURM_ARRAY_TASK_ID",
        "JOB_COMPLETION_INDEX",
        "PARALLEL_SEQ",
    ] {
        c.env_remove(v);
    }
    c
}

/// `omnicloud tour` of the walk into `dir`: `frames` ODS frames `width` wide, ray traced.
fn tour_args(dir: &Path, frames: usize, width: u32) -> Vec<String> {
    [
        "tour",
        SCAN,
        "--path",
        WALK,
        "-o",
        dir.to_str().unwrap(),
        "--stereo",
        "ods",
        "--renderer",
        "raytrace",
        "-q",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([
        "--frames".into(),
        frames.to_string(),
        "--width".into(),
        width.to_string(),
    ])
    .collect()
}

/// Every file of `dir` but `tour.log`, by name. `tour.log` differs between an interrupted and
/// an uninterrupted run by right: it has one line per frame rendered, with its render time,
/// so its lines are split across the runs and its times are the clock's.
fn folder(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap() != "tour.log")
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

fn frame_count(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| {
        d.flatten()
            .filter(|e| {
                let n = e.file_name();
                let n = n.to_string_lossy();
                n.starts_with("frame_") && n.ends_with(".png")
            })
            .count()
    })
}

/// Each frame file in `dir` decodes whole at the tour's size (ODS: the eyes one above the
/// other, square).
fn assert_frames_whole(dir: &Path, width: u32) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with("frame_") {
            let img = image::open(entry.path())
                .unwrap_or_else(|e| panic!("{name} is not a whole PNG: {e}"));
            assert_eq!((img.width(), img.height()), (width, width), "{name}");
        }
    }
}

#[test]
fn kill_9_at_random_moments_then_resuming_gives_the_uninterrupted_folder() {
    const FRAMES: usize = 24;
    // About a tenth of a second a frame on a loaded CI machine: room to land inside one.
    const WIDTH: u32 = 256;
    const KILLS: usize = 3;
    // Both runs write into the same folder name (`tour.json` holds it in every frame's
    // command): the uninterrupted one first, then moved aside.
    let base = tempfile::tempdir().unwrap();
    let (dir, reference) = (base.path().join("tour"), base.path().join("reference"));
    let out = omnicloud()
        .args(tour_args(&dir, FRAMES, WIDTH))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::rename(&dir, &reference).unwrap();

    let mut rng = SplitMix64::new(0x6b69_6c6c_2d39);
    let mut killed = 0;
    while killed < KILLS {
        let before = frame_count(&dir);
        // Kill once a few more frames are done, at a random moment within the next frame.
        let target = (before + 1 + (rng.next_u64() % 5) as usize).min(FRAMES - 1);
        let delay = Duration::from_millis(rng.next_u64() % 60);
        let mut child = omnicloud()
            .args(tour_args(&dir, FRAMES, WIDTH))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let deadline = Instant::now() + Duration::from_secs(300);
        while frame_count(&dir) < target && Instant::now() < deadline {
            if child.try_wait().unwrap().is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        std::thread::sleep(delay);
        let finished = child.try_wait().unwrap().is_some();
        child.kill().unwrap_or(());
        child.wait().unwrap();
        assert!(!finished, "the tour finished before kill {}", killed + 1);
        killed += 1;
        let after = frame_count(&dir);
        eprintln!("kill -9 #{killed}: {before} -> {after} frames (target {target}, +{delay:?})");
        assert_frames_whole(&dir, WIDTH);
    }
    let out = omnicloud()
        .args(tour_args(&dir, FRAMES, WIDTH))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (got, want) = (folder(&dir), folder(&reference));
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        want.keys().collect::<Vec<_>>(),
        "the resumed folder holds other files"
    );
    for (name, bytes) in &want {
        assert!(
            &got[name] == bytes,
            "{name} differs from the uninterrupted run's"
        );
    }
    assert_eq!(got.len(), FRAMES + 1, "{:?}", got.keys());
}

/// Runs omnicloud with `args` under `ulimit -f BLOCKS` (512-byte blocks in `sh`), `SIGXFSZ`
/// ignored so that writes past the limit fail with `EFBIG` instead of killing the process.
fn with_file_limit(blocks: u32, args: &[String]) -> Output {
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(format!(
            "ulimit -f {blocks} && trap '' XFSZ && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env_remove("OMNICLOUD_PROGRESS");
    c.output().unwrap()
}

/// Names in `dir` that are temporary files (`.NAME.XXXXXX.tmp`) or scratch folders.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// The run failed, saying so about `file`, and left neither it nor a temporary file.
fn assert_refused_cleanly(out: &Output, file: &Path) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{}: {stderr}", file.display());
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains(&file.display().to_string()),
        "the error does not name {}: {stderr}",
        file.display()
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!file.exists(), "{} was left behind", file.display());
    let dir = file.parent().unwrap();
    assert!(temporaries(dir).is_empty(), "left: {:?}", temporaries(dir));
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

#[test]
fn a_full_disk_while_writing_a_render_or_an_index_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("pano.png");
    let out = with_file_limit(
        16,
        &strings(&[
            "render",
            SCAN,
            "-o",
            png.to_str().unwrap(),
            "--width",
            "512",
            "--renderer",
            "raytrace",
        ]),
    );
    assert_refused_cleanly(&out, &png);

    let copc = dir.path().join("autzen.copc.laz");
    let out = with_file_limit(
        16,
        &strings(&["index", SCAN, "-o", copc.to_str().unwrap(), "--quiet"]),
    );
    assert_refused_cleanly(&out, &copc);
}

#[test]
fn a_full_disk_during_a_tour_keeps_the_earlier_frames_and_a_video_leaves_no_file() {
    const WIDTH: u32 = 256;
    let dir = tempfile::tempdir().unwrap();
    let args = tour_args(dir.path(), 4, WIDTH);
    let out = omnicloud().args(&args).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let whole = folder(dir.path());
    let frame = |i: usize| dir.path().join(format!("frame_{i:06}.png"));
    let manifest_len = whole["tour.json"].len() as u64;
    let frame_len = whole["frame_000002.png"].len() as u64;
    // Room for the manifest, not for a frame.
    let blocks = (manifest_len / 512 + 2) as u32;
    assert!(
        u64::from(blocks) * 512 < frame_len,
        "frames too small for the test"
    );
    std::fs::remove_file(frame(2)).unwrap();
    std::fs::remove_file(frame(3)).unwrap();

    let out = with_file_limit(blocks, &args);
    assert_refused_cleanly(&out, &frame(2));
    assert!(!frame(3).exists());
    for i in 0..2 {
        let name = format!("frame_{i:06}.png");
        assert!(
            std::fs::read(frame(i)).unwrap() == whole[&name],
            "{name} changed"
        );
    }

    // The video of the finished frames.
    let out = omnicloud().args(&args).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mp4 = dir.path().join("walk.mp4");
    let out = with_file_limit(
        4,
        &strings(&[
            "video",
            dir.path().to_str().unwrap(),
            "-o",
            mp4.to_str().unwrap(),
        ]),
    );
    assert_refused_cleanly(&out, &mp4);
}
