//! `tour` takes the picture options (`--edl`, `--supersample`, `--background`), and each
//! frame's recorded `omnicloud render` command writes the same file.

use std::process::Command;

use serde_json::Value;

fn omnicloud(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env_remove("OMNICLOUD_PROGRESS")
        .output()
        .unwrap()
}

#[test]
fn tour_frames_with_the_picture_options_are_what_render_writes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let o = omnicloud(&[
        "tour",
        "data/autzen_trim.laz",
        "--path",
        "data/tours/autzen_walk.csv",
        "-o",
        out.to_str().unwrap(),
        "--frames",
        "3",
        "--width",
        "128",
        "--renderer",
        "raytrace",
        "--edl",
        "--supersample",
        "2",
        "--background",
        "#204060",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("tour.json")).unwrap()).unwrap();
    assert_eq!(m["width"], 128);
    let frame = &m["frames"][1];
    let command = frame["command"].as_str().unwrap();
    for needle in [
        "--edl=1",
        "--edl-radius=1.4",
        "--supersample=2",
        "'--background=#204060'",
        "--units=metres",
    ] {
        assert!(command.contains(needle), "{command}");
    }
    // The recorded command, its output redirected (no quoted word holds a space here).
    let mut words: Vec<String> = command
        .split(' ')
        .map(|w| w.trim_matches('\'').to_string())
        .collect();
    let o_at = words.iter().position(|w| w == "-o").unwrap();
    let again = dir.path().join("again.png");
    words[o_at + 1] = again.display().to_string();
    let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let r = omnicloud(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let written = std::fs::read(out.join(frame["file"].as_str().unwrap())).unwrap();
    assert!(std::fs::read(&again).unwrap() == written, "frame 1 differs");
    let img = image::load_from_memory(&written).unwrap().into_rgba8();
    assert_eq!(img.dimensions(), (128, 64));
    // Opaque with the background colour in the sky.
    assert!(img.pixels().all(|p| p[3] == 255));
    assert_eq!(img.get_pixel(64, 0).0, [0x20, 0x40, 0x60, 255]);

    let o = omnicloud(&[
        "tour",
        "data/autzen_trim.laz",
        "--path",
        "data/tours/autzen_walk.csv",
        "-o",
        out.to_str().unwrap(),
        "--format",
        "jpg",
        "--background",
        "transparent",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no alpha"));
}
