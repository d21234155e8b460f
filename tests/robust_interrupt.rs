//! Ctrl-C during a render leaves no output and no temporary file, and exits non-zero with one
//! line; staged (written, not yet renamed) files are removed by the interrupt path.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn sigint_mid_render_leaves_nothing_behind() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data/large/potree_lion_takanawa_merged.las");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pano.exr");
    // A render of several seconds: 341,989 points ray-traced at 4096 x 2048, ODS.
    let child = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args([
            "render",
            "--renderer",
            "raytrace",
            "--stereo",
            "ods",
            "--width",
            "4096",
            "-q",
        ])
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .arg("--depth")
        .arg(dir.path().join("depth.exr"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let started = Instant::now();
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "the render did not stop promptly"
    );
    assert_eq!(output.status.code(), Some(130), "stderr: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "stderr: {stderr}");
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert!(
        leftovers(dir.path()).is_empty(),
        "left behind: {:?}",
        leftovers(dir.path())
    );
}

#[test]
fn staged_files_are_removed_by_the_interrupt_path() {
    let dir = tempfile::tempdir().unwrap();
    let dest = dir.path().join("out.png");
    let staged = omnicloud::output::StagedFile::create(&dest, |w| {
        use std::io::Write;
        w.write_all(b"half an image").unwrap();
        Ok(())
    })
    .unwrap();
    assert_eq!(leftovers(dir.path()).len(), 1, "the temporary file exists");
    // What the Ctrl-C handler does before exiting. (It leaves the registry locked, so this
    // binary stages nothing after it: the other test runs the real binary.)
    assert_eq!(omnicloud::output::remove_staged_files(), 1);
    assert!(leftovers(dir.path()).is_empty());
    assert!(!dest.exists());
    std::mem::forget(staged);
}
