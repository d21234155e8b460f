//! Ctrl-C during a render leaves no output and no temporary file, and exits non-zero with one
//! line; staged (written, not yet renamed) files are removed by the interrupt path.

mod data_common;
mod interrupt_common;

use std::path::Path;
use std::process::Command;

use interrupt_common::{assert_interrupted, interrupt_at_progress, is_progress};

fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn sigint_mid_render_leaves_nothing_behind() {
    let input = data_common::lion();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pano.exr");
    // 341,989 points ray-traced at 4096 x 2048, ODS: interrupted at its first progress line.
    let mut command = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    command
        .args([
            "render",
            "--renderer",
            "raytrace",
            "--stereo",
            "ods",
            "--width",
            "4096",
        ])
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .arg("--depth")
        .arg(dir.path().join("depth.exr"));
    let run = interrupt_at_progress(command, "ray tracing");
    assert_interrupted(&run);
    assert!(
        leftovers(dir.path()).is_empty(),
        "left behind: {:?}",
        leftovers(dir.path())
    );
}

#[test]
fn progress_lines_are_told_from_messages() {
    let bar = format!("  rasterizing [{:<40}] 3/110000 (2s)", "=>");
    assert!(is_progress(&bar, "rasterizing"));
    assert!(is_progress(&bar, ""));
    assert!(!is_progress(&bar, "surveying"));
    assert!(!is_progress("a.las: 3 points, camera at (1, 2, 3)", ""));
    assert!(!is_progress(
        "omnicloud: interrupted; no partial output left (0 unfinished file(s) removed)",
        ""
    ));
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
