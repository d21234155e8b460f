//! E57 scans through the renderers: the same points as PLY in file coordinates give the same
//! picture, `--camera station:N` stands at the scan's station with its heading, and
//! `--camera station:all` writes one panorama per station as a tour folder.

mod e57_common;

use e57_common::*;
use omnicloud::io;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

fn omnicloud(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{args:?}: {text}");
    text
}

/// The points of `e57` as an ascii PLY of doubles (exact round trip) with their colour.
fn as_ply(e57: &Path, ply: &Path) {
    let mut rows = Vec::new();
    for chunk in io::open(e57).unwrap().chunks(4096) {
        let c = chunk.unwrap();
        for (p, rgb) in c.positions.iter().zip(c.rgb.unwrap()) {
            rows.push(format!(
                "{:?} {:?} {:?} {} {} {}",
                p.x, p.y, p.z, rgb[0], rgb[1], rgb[2]
            ));
        }
    }
    let mut f = std::fs::File::create(ply).unwrap();
    write!(
        f,
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
         property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
         end_header\n{}\n",
        rows.len(),
        rows.join("\n")
    )
    .unwrap();
}

fn render(file: &Path, out: &Path, extra: &[&str]) -> Vec<u8> {
    let mut args = vec![
        "render",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "128",
        "--radius",
        "0.2",
        "--quiet",
    ];
    args.extend(extra);
    omnicloud(&args);
    std::fs::read(out).unwrap()
}

fn decoded(png: &[u8]) -> image::RgbaImage {
    image::load_from_memory(png).unwrap().to_rgba8()
}

#[test]
fn an_e57_scan_renders_like_its_points_as_ply() {
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    write_site(&site);
    let ply = dir.path().join("site.ply");
    as_ply(&site, &ply);
    let camera = ["--camera", "10.5,19.0,1.6"];
    for renderer in ["raytrace", "raster"] {
        let mut extra = camera.to_vec();
        extra.extend(["--renderer", renderer]);
        let a = render(
            &site,
            &dir.path().join(format!("e57-{renderer}.png")),
            &extra,
        );
        let b = render(
            &ply,
            &dir.path().join(format!("ply-{renderer}.png")),
            &extra,
        );
        let (a, b) = (decoded(&a), decoded(&b));
        assert_eq!(a.dimensions(), (128, 64));
        let covered = a.pixels().filter(|p| p[3] > 0).count();
        assert!(
            covered > 128 * 64 / 2,
            "{renderer}: {covered} pixels covered"
        );
        assert!(a == b, "{renderer}: the E57 and PLY renders differ");
    }
}

#[test]
fn station_camera_stands_at_the_scan_translation_with_its_heading() {
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    write_site(&site);
    let stations = omnicloud::tour::stations::read_stations(&site).unwrap();
    assert_eq!(stations.len(), 2);
    let s1 = &stations[1];
    let t = glam::DVec3::from_array(POSE1_T);
    assert!((s1.position - t).length() < 1e-3, "{:?}", s1.position);
    // Scan 1 turns -60° about a nearly vertical axis: +Y heads 60° clockwise, yaw ≈ +60.
    assert!((s1.yaw - 60.0).abs() < 1.0, "{}", s1.yaw);
    let by_station = render(
        &site,
        &dir.path().join("station.png"),
        &["--camera", "station:1", "--renderer", "raytrace"],
    );
    let at = format!("{:?},{:?},{:?}", t.x, t.y, t.z);
    let yaw = format!("{:?}", s1.yaw);
    let by_hand = render(
        &site,
        &dir.path().join("hand.png"),
        &["--camera", &at, "--yaw", &yaw, "--renderer", "raytrace"],
    );
    assert!(decoded(&by_station) == decoded(&by_hand));
    let off = render(
        &site,
        &dir.path().join("off.png"),
        &["--camera", &at, "--renderer", "raytrace"],
    );
    assert!(decoded(&off) != decoded(&by_hand), "the heading matters");
}

#[test]
fn station_all_writes_a_resumable_tour_folder() {
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    write_site(&site);
    let out: PathBuf = dir.path().join("stations");
    let args = [
        "render",
        site.to_str().unwrap(),
        "--camera",
        "station:all",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "128",
        "--radius",
        "0.2",
        "--renderer",
        "raytrace",
    ];
    omnicloud(&args);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("tour.json")).unwrap()).unwrap();
    let frames = manifest["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 2);
    assert_eq!(manifest["path"], "stations");
    let p1: Vec<f64> = frames[1]["position"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        p1.iter().zip(POSE1_T).all(|(a, b)| (a - b).abs() < 1e-3),
        "{p1:?}"
    );
    // The stations the viewer lists: each scan's name, position and frame.
    let stations = manifest["stations"].as_array().unwrap();
    let names: Vec<&str> = stations
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["North", "South"]);
    assert_eq!(stations[1]["frame"], 1);
    assert_eq!(stations[1]["scan"], 1);
    assert_eq!(stations[1]["position"], serde_json::json!(POSE1_T));
    assert!(out.join("frame_000000.png").exists() && out.join("frame_000001.png").exists());
    // A second run finds both frames and renders nothing.
    let again = omnicloud(&args);
    assert!(again.contains("skipping 2 frame(s)"), "{again}");
    // The station frame is the panorama `--camera station:1` renders.
    let single = render(
        &site,
        &dir.path().join("one.png"),
        &["--camera", "station:1", "--renderer", "raytrace"],
    );
    assert!(decoded(&single) == decoded(&std::fs::read(out.join("frame_000001.png")).unwrap()));
}

#[test]
fn color_image_renders_the_photos_colours() {
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    write_site(&site);
    let common = [
        "--scan",
        "0",
        "--camera",
        "10,20,1.5",
        "--renderer",
        "raytrace",
    ];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = common.to_vec();
        v.extend(extra);
        v
    };
    let image = render(
        &site,
        &dir.path().join("image.png"),
        &with(&["--color", "image"]),
    );
    let stored = render(
        &site,
        &dir.path().join("rgb.png"),
        &with(&["--color", "rgb"]),
    );
    let picked = PathBuf::from(format!("{}#color:image", site.display()));
    let named = render(
        &picked,
        &dir.path().join("named.png"),
        &with(&["--color", "rgb"]),
    );
    assert!(
        decoded(&image) == decoded(&named),
        "--color image reads FILE#color:image"
    );
    assert!(decoded(&image) != decoded(&stored));
    // Heading 0 looks along world +Y, which the scan's quarter turn makes its +X: at the
    // photo, red above the horizon, blue below.
    let img = decoded(&image);
    let (w, h) = img.dimensions();
    let above = img.get_pixel(w / 2, h / 2 - 8);
    let below = img.get_pixel(w / 2, h / 2 + 8);
    assert_eq!((above[0], above[2]), (255, 0), "{above:?}");
    assert_eq!((below[0], below[2]), (0, 255), "{below:?}");
}

#[test]
fn a_station_render_compares_with_the_scanners_panorama() {
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    write_site(&site);
    let out = dir.path().join("station1.png");
    render(
        &site,
        &out,
        &[
            "--camera",
            "station:1",
            "--color",
            "image",
            "--renderer",
            "raytrace",
        ],
    );
    let reference = format!("{}#image:0", site.display());
    let json = dir.path().join("report.json");
    // Share of the render's pixels whose colour differs from the photo's, and the share of
    // pixels the render covers.
    let compare = |test: &Path| {
        omnicloud(&[
            "compare",
            &reference,
            test.to_str().unwrap(),
            "--report",
            json.to_str().unwrap(),
        ]);
        let report: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        let all = &report["eyes"][0]["all"];
        assert_eq!(
            all["ref_hits"],
            128 * 64,
            "the full-sphere photo covers every pixel"
        );
        let test_hits = all["test_hits"].as_f64().unwrap();
        (
            all["color_differs"].as_f64().unwrap() / test_hits,
            test_hits / (128.0 * 64.0),
        )
    };
    let (differs, covered) = compare(&out);
    // Measured: 278 of 2,926 covered pixels differ (spheres straddling the photo's 8-pixel
    // blocks), 35.7 % covered.
    assert!(differs < 0.15, "{differs}");
    assert!((0.30..0.42).contains(&covered), "{covered}");
    // Turned a quarter off the station's heading, the render no longer matches its photo.
    let turned = dir.path().join("turned.png");
    render(
        &site,
        &turned,
        &[
            "--camera",
            "station:1",
            "--yaw",
            "90",
            "--color",
            "image",
            "--renderer",
            "raytrace",
        ],
    );
    let (turned_differs, _) = compare(&turned);
    assert!(
        turned_differs > 3.0 * differs,
        "{turned_differs} vs {differs}"
    );
}
