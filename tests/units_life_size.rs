//! Lengths a person types are metres whatever the file's unit: the bundled sample counts in
//! international feet, and its ODS pair, rendered with `--ipd 0.064 --radius 0.4`, has the
//! disparities of the same scene converted to metres and rendered from the same spot with the
//! same options. `--units file` keeps the old reading (lengths in feet), whose disparities are
//! 3.28 times smaller.

use std::path::{Path, PathBuf};
use std::process::Command;

use omnicloud::output::disparity_exr::read_disparity_exr;

const AUTZEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");
const FOOT: f64 = 0.3048;

fn omnicloud(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The sample with every coordinate in metres, in a LAS whose WKT says so.
fn autzen_in_metres(path: &Path) {
    let mut reader = las::Reader::from_path(AUTZEN).unwrap();
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(7).unwrap();
    builder.transforms = las::Vector {
        x: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        y: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        z: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
    };
    let mut header = builder.into_header().unwrap();
    header
        .set_wkt_crs(br#"PROJCS["metric copy",UNIT["metre",1]]"#.to_vec())
        .unwrap();
    let mut writer = las::Writer::from_path(path, header).unwrap();
    for p in reader.read_all().unwrap().points() {
        let p = p.unwrap();
        writer
            .write_point(las::Point {
                x: p.x * FOOT,
                y: p.y * FOOT,
                z: p.z * FOOT,
                gps_time: Some(p.gps_time.unwrap_or(0.0)),
                ..p
            })
            .unwrap();
    }
    writer.close().unwrap();
}

/// Renders `scan`'s ODS pair from `camera` (its file coordinates) and returns the left eye's
/// horizontal disparities (arcminutes, NaN where none) and the stderr.
fn disparities(
    scan: &Path,
    camera: [f64; 3],
    radius: &str,
    out: &Path,
    extra: &[&str],
) -> (Vec<f32>, String) {
    let exr = out.with_extension("exr");
    let camera = format!("--camera={},{},{}", camera[0], camera[1], camera[2]);
    let mut args = vec![
        "render",
        scan.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "256",
        "--stereo",
        "ods",
        "--ipd",
        "0.064",
        "--radius",
        radius,
        "--renderer",
        "raytrace",
        "--disparity",
        exr.to_str().unwrap(),
        &camera,
    ];
    args.extend(extra);
    let (ok, stderr) = omnicloud(&args);
    assert!(ok, "{stderr}");
    (read_disparity_exr(&exr).unwrap().dh, stderr)
}

/// Mean of `|a - k b|` over the pixels both cover, relative to the mean of `|a|`, and the
/// share of pixels covered in one only.
fn relative_difference(a: &[f32], b: &[f32], k: f64) -> (f64, f64) {
    let (mut diff, mut size, mut both, mut one) = (0.0, 0.0, 0usize, 0usize);
    for (&x, &y) in a.iter().zip(b) {
        match (x.is_finite(), y.is_finite()) {
            (true, true) => {
                diff += (f64::from(x) - k * f64::from(y)).abs();
                size += f64::from(x).abs();
                both += 1;
            }
            (false, false) => {}
            _ => one += 1,
        }
    }
    assert!(both > 1000, "{both} pixels covered in both");
    (diff / size, one as f64 / (both + one) as f64)
}

#[test]
fn the_sample_in_feet_has_the_disparities_of_the_same_scene_in_metres() {
    let dir = tempfile::tempdir().unwrap();
    let metric: PathBuf = dir.path().join("autzen_metres.las");
    autzen_in_metres(&metric);
    // A spot over the stadium's ground, 10 m up (file feet).
    let feet_camera = [636_690.0, 849_200.0, 440.0];
    let metre_camera = feet_camera.map(|c| c * FOOT);

    let (feet, stderr) = disparities(
        AUTZEN.as_ref(),
        feet_camera,
        "0.4",
        &dir.path().join("feet.png"),
        &[],
    );
    assert!(
        stderr.contains("lengths in metres (1 m = 3.2808 ft)")
            && stderr.contains("--ipd 0.064 m = 0.2100 ft")
            && stderr.contains("--radius 0.4 m = 1.3123 ft")
            && stderr.contains("life-size"),
        "{stderr}"
    );
    let (metres, stderr) =
        disparities(&metric, metre_camera, "0.4", &dir.path().join("m.png"), &[]);
    assert!(
        !stderr.contains("note: "),
        "a metric file needs no note: {stderr}"
    );
    let (rel, coverage) = relative_difference(&feet, &metres, 1.0);
    // Measured: 0.013 % apart, 0.006 % of the pixels covered in one only (f32 rounding of
    // coordinates three times larger).
    assert!(rel < 0.001, "disparities differ by {:.3}%", 100.0 * rel);
    assert!(
        coverage < 0.001,
        "coverage differs on {:.3}%",
        100.0 * coverage
    );

    // The old reading: every length in feet. With the same spheres (0.4 m given as 1.3123 ft),
    // only the baseline differs: 3.28 times smaller, and so is every disparity.
    let (file_units, stderr) = disparities(
        AUTZEN.as_ref(),
        feet_camera,
        "1.312336",
        &dir.path().join("file.png"),
        &["--units", "file"],
    );
    assert!(
        stderr.contains("with --units file every length") && stderr.contains("--ipd 0.064 ft"),
        "{stderr}"
    );
    let (rel_file, _) = relative_difference(&feet, &file_units, 1.0 / FOOT);
    eprintln!("metres vs feet: {rel:.5} {coverage:.5}; 3.28 x --units file: {rel_file:.5}");
    assert!(
        rel_file < 0.01,
        "3.28 x the file-unit disparities differ by {rel_file}"
    );
    let (rel_same, _) = relative_difference(&feet, &file_units, 1.0);
    assert!(rel_same > 0.6, "{rel_same}");
}
