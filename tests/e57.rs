//! E57 input: scans posed into the file's frame (Cartesian and spherical), picks of scans,
//! `info` on real files, and one clear error line for each broken file.

mod e57_common;

use e57_common::*;
use glam::DVec3;
use omnicloud::io::{self, LoadOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/e57")
        .join(name)
}

fn site(dir: &Path) -> PathBuf {
    let path = dir.join("site.e57");
    write_site(&path);
    path
}

fn omnicloud(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap()
}

/// The spherical image's pixel that scan 1's grid cell (row, column) falls in: the image
/// shares the scan's pose, columns run with azimuth from the middle, rows down from the top.
fn pano_pixel(row: usize, column: usize) -> [u8; 3] {
    let (_, a, e) = scan1_spherical(row, column);
    let x = (PANO_W as f64 / 2.0 + a / (2.0 * std::f64::consts::PI / PANO_W as f64)).floor();
    let y = (PANO_H as f64 / 2.0 - e / (std::f64::consts::PI / PANO_H as f64)).floor();
    pano_color(x as u32, y as u32)
}

#[test]
fn colour_comes_from_each_stations_photos() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    // Scan 1 stores no colour: its photo colours it by default, and the pattern comes back.
    let (_, rgb, _) = stream(&path);
    let n0 = scan0_points().len();
    for row in 0..ROWS {
        for column in 0..COLUMNS {
            let got = rgb[n0 + row * COLUMNS + column];
            assert_eq!(got, pano_pixel(row, column), "{row},{column}");
        }
    }
    // Scan 0's stored colours stay, unless its photo is asked for: the pinhole camera looks
    // along the scan's +X, its left half (red) above the scanner, right half (blue) below.
    let stored: Vec<[u8; 3]> = scan0_points().iter().map(|p| p.1).collect();
    assert_eq!(rgb[..n0], stored[..]);
    let forced = PathBuf::from(format!("{}#scan:0#color:image", path.display()));
    let (_, rgb, intensity) = stream(&forced);
    let (mut red, mut blue, mut grey) = (0, 0, 0);
    for (((p, _), c), i) in scan0_points().iter().zip(&rgb).zip(&intensity) {
        // The photo spans ±45° across (the scan's z) and ±36.9° down (its y) at 4 m.
        let seen = p.x == 4.0 && p.y.abs() < 2.9 && p.z.abs() < 3.9 && p.z.abs() > 0.05;
        if seen && p.z > 0.0 {
            assert_eq!(*c, PHOTO_LEFT, "{p}");
            red += 1;
        } else if seen {
            assert_eq!(*c, PHOTO_RIGHT, "{p}");
            blue += 1;
        } else if p.x <= 0.0 {
            // Behind the photo's camera: intensity as grey. (A photo has no depth: points in
            // front of the wall, on the floor, take the wall's colour where it would show.)
            let g = (f64::from(*i) / 65535.0 * 255.0).round() as u8;
            assert_eq!(*c, [g; 3], "{p}");
            grey += 1;
        }
    }
    assert!(
        red > 200 && blue > 100 && grey > 1500,
        "{red} {blue} {grey}"
    );
    let info = io::read_info(&path).unwrap();
    assert_eq!(info.color_depth, io::ColorDepth::FromImages);
    let bunny = format!("{}#color:image", data("bunnyFloat.e57").display());
    let err = io::open(Path::new(&bunny)).unwrap_err().to_string();
    assert!(err.contains("no scan read has an image"), "{err}");
}

/// Every point of `path` as the chunk stream gives it.
fn stream(path: &Path) -> (Vec<DVec3>, Vec<[u8; 3]>, Vec<u16>) {
    let mut out = (Vec::new(), Vec::new(), Vec::new());
    for chunk in io::open(path).unwrap().chunks(1000) {
        let c = chunk.unwrap();
        out.0.extend(c.positions);
        out.1.extend(c.rgb.unwrap());
        out.2.extend(c.intensity.unwrap());
    }
    out
}

#[test]
fn points_land_at_r_p_plus_t_for_both_coordinate_kinds() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    let (positions, rgb, intensity) = stream(&path);
    let scan0 = scan0_points();
    assert_eq!(
        positions.len(),
        scan0.len() + ROWS * COLUMNS,
        "the invalid point is dropped"
    );
    let mut worst: f64 = 0.0;
    for (i, (p, c)) in scan0.iter().enumerate() {
        worst = worst.max((positions[i] - posed(POSE0_Q, POSE0_T, *p)).length());
        assert_eq!(rgb[i], *c);
        let expect = ((i % 4096) as f64 / 4095.0 * 65535.0).round() as u16;
        assert!(
            intensity[i].abs_diff(expect) <= 1,
            "{} vs {expect}",
            intensity[i]
        );
    }
    let n0 = scan0.len();
    for row in 0..ROWS {
        for column in 0..COLUMNS {
            let (r, a, e) = scan1_spherical(row, column);
            let local = DVec3::new(r * e.cos() * a.cos(), r * e.cos() * a.sin(), r * e.sin());
            let got = positions[n0 + row * COLUMNS + column];
            worst = worst.max((got - posed(pose1_q(), POSE1_T, local)).length());
        }
    }
    assert!(worst < 1e-9, "largest error {worst} m");
    assert!(
        intensity[n0..].iter().all(|&i| i == 65535),
        "full-scale intensity"
    );
    // The scan's stated bounds, posed, hold every point.
    let info = io::read_info(&path).unwrap();
    let (lo, hi) = info.bounds.unwrap();
    assert!(
        positions
            .iter()
            .all(|p| p.cmpge(lo - 1e-9).all() && p.cmple(hi + 1e-9).all())
    );
    assert_eq!(info.point_count, (n0 + 1 + ROWS * COLUMNS) as u64);
}

#[test]
fn scans_are_picked_by_index_or_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    let pick = |sel: &str| PathBuf::from(format!("{}#scan:{sel}", path.display()));
    let (by_index, _, _) = stream(&pick("1"));
    let (by_name, _, _) = stream(&pick("South"));
    assert_eq!(by_index.len(), ROWS * COLUMNS);
    assert_eq!(by_index, by_name);
    let (both, _, _) = stream(&pick("South,0"));
    assert_eq!(both.len(), ROWS * COLUMNS + scan0_points().len());
    assert_eq!(both[..ROWS * COLUMNS], by_index[..], "in the order asked");
    let err = io::open(&pick("7")).unwrap_err().to_string();
    assert!(
        err.contains("site.e57") && err.contains("no scan 7"),
        "{err}"
    );
    let err = io::open(&pick("Roof")).unwrap_err().to_string();
    assert!(err.contains("no scan is named 'Roof'"), "{err}");
    // A whole load of one scan, as every command does.
    let (scene, report) = io::load_scene(&pick("0"), &LoadOptions::default()).unwrap();
    assert_eq!(scene.positions.len(), scan0_points().len());
    assert_eq!(report.points_read, scan0_points().len() as u64);
    assert!(scene.attributes.rgb.is_some() && scene.attributes.intensity.is_some());
}

#[test]
fn seeking_restarts_at_a_record() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    let (all, _, _) = stream(&path);
    let mut reader = io::open(&path).unwrap();
    // Record 700 of scan 0 (no invalid record before it).
    reader.seek(700).unwrap();
    let first = reader.chunks(10).next().unwrap().unwrap();
    assert_eq!(first.positions[..], all[700..710]);
}

/// `recordCount` of each `points` element in the file's XML section.
fn xml_counts(path: &Path) -> Vec<u64> {
    let xml = e57::E57Reader::raw_xml(std::fs::File::open(path).unwrap()).unwrap();
    let xml = String::from_utf8(xml).unwrap();
    xml.match_indices("<points ")
        .map(|(at, _)| {
            let tag = &xml[at..at + xml[at..].find('>').unwrap()];
            let start = tag.find("recordCount=\"").unwrap() + "recordCount=\"".len();
            let len = tag[start..].find('"').unwrap();
            tag[start..start + len].parse().unwrap()
        })
        .collect()
}

#[test]
fn info_json_matches_the_counts_in_each_files_xml() {
    for (name, expect) in [("bunnyFloat.e57", 30_571u64), ("pipeSpherical.e57", 1_220)] {
        let path = data(name);
        let counts = xml_counts(&path);
        assert_eq!(counts.iter().sum::<u64>(), expect, "{name}");
        let out = omnicloud(&["info", "--json", path.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: Value = serde_json::from_slice(&out.stdout).unwrap();
        let json = if json.is_array() {
            json[0].clone()
        } else {
            json
        };
        assert_eq!(json["format"], "E57");
        assert_eq!(json["point_count"], expect, "{name}");
        let scans: Vec<u64> = json["e57"]["scans"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["points"].as_u64().unwrap())
            .collect();
        assert_eq!(scans, counts, "{name}");
    }
    let pipe = io::read_info(&data("pipeSpherical.e57")).unwrap();
    let e = pipe.e57.as_ref().unwrap();
    // Despite its name the pipe's points are Cartesian, with colour and intensity.
    assert_eq!(e.scans[0].coordinates, io::e57::Coordinates::Cartesian);
    assert_eq!(
        e.writer.as_deref(),
        Some("E57Format-2.3.0-AMD64_64-windows")
    );
    assert!(pipe.attributes.rgb && pipe.attributes.intensity);
    let bunny = io::read_info(&data("bunnyFloat.e57")).unwrap();
    assert!(!bunny.attributes.rgb);
    // Every point of both files reads.
    for name in ["bunnyFloat.e57", "pipeSpherical.e57"] {
        let (scene, _) = io::load_scene(&data(name), &LoadOptions::default()).unwrap();
        assert!(scene.positions.len() > 1000, "{name}");
    }
}

#[test]
fn info_lists_scans_and_images_of_a_generated_site() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    let out = omnicloud(&["info", "--json", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let e = &json["e57"];
    assert_eq!(e["scans"][0]["name"], "North");
    assert_eq!(e["scans"][1]["grid"]["rows"], ROWS as u64);
    assert_eq!(e["scans"][1]["grid"]["columns"], COLUMNS as u64);
    let t = &e["scans"][0]["pose"]["translation"];
    assert_eq!(
        [t[0].as_f64(), t[1].as_f64(), t[2].as_f64()],
        POSE0_T.map(Some)
    );
    // A quarter turn anticlockwise: +Y looks along -X.
    assert!((e["scans"][0]["pose"]["yaw_degrees"].as_f64().unwrap() + 90.0).abs() < 1e-9);
    assert_eq!(e["images"][0]["projection"], "spherical");
    assert_eq!(e["images"][0]["width"], PANO_W);
    assert_eq!(e["images"][0]["scan"], 1);
    assert_eq!(e["images"][1]["projection"], "pinhole");
    assert_eq!(e["images"][1]["scan"], 0);
    let text = omnicloud(&["info", path.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("scan 1 'South': 648 points, spherical"),
        "{text}"
    );
    assert!(
        text.contains("image 0 'South panorama': spherical 64 x 32 png"),
        "{text}"
    );
}

/// The one line of error `command` prints for `path`.
fn error_line(path: &Path) -> String {
    let out = omnicloud(&["info", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr).trim().to_string();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(path.file_name().unwrap().to_str().unwrap()),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    err
}

#[test]
fn broken_files_give_one_clear_line() {
    assert!(error_line(&data("empty.e57")).contains("the file is empty"));
    let invalid = error_line(&data("invalid.e57"));
    assert!(invalid.contains("'ASTM-E57'"), "{invalid}");
    let xml = error_line(&data("justxml.e57"));
    assert!(xml.contains("'ASTM-E57'"), "{xml}");

    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(data("bunnyFloat.e57")).unwrap();
    let cut = dir.path().join("cut.e57");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let line = error_line(&cut);
    assert!(line.contains("truncated"), "{line}");

    // A flipped byte in the point data: the page's checksum fails while reading points.
    let flipped = dir.path().join("flipped.e57");
    let mut bad = bytes.clone();
    bad[4096] ^= 0x55;
    std::fs::write(&flipped, &bad).unwrap();
    let err = io::load_scene(&flipped, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("flipped.e57") && err.to_lowercase().contains("checksum"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);

    // A flipped byte in the XML section fails at opening, naming the file.
    let xml_at = u64::from_le_bytes(bytes[24..32].try_into().unwrap()) as usize;
    let mut bad = bytes.clone();
    bad[xml_at + 10] ^= 0x55;
    let broken_xml = dir.path().join("xmlcrc.e57");
    std::fs::write(&broken_xml, &bad).unwrap();
    let line = error_line(&broken_xml);
    assert!(line.to_lowercase().contains("checksum"), "{line}");
}

#[test]
fn images_are_extracted_as_stored() {
    let dir = tempfile::tempdir().unwrap();
    let path = site(dir.path());
    let out = dir.path().join("images");
    let run = omnicloud(&[
        "info",
        path.to_str().unwrap(),
        "--extract-images",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let pano = image::open(out.join("image_000.png")).unwrap().to_rgb8();
    assert_eq!(pano.dimensions(), (PANO_W, PANO_H));
    assert!(
        pano.enumerate_pixels()
            .all(|(x, y, p)| p.0 == pano_color(x, y))
    );
    let photo = image::open(out.join("image_001.png")).unwrap().to_rgb8();
    assert_eq!(photo.get_pixel(5, 5).0, PHOTO_LEFT);
    assert_eq!(photo.get_pixel(35, 5).0, PHOTO_RIGHT);
    let err = io::e57::read_image(&path, 2).unwrap_err().to_string();
    assert!(err.contains("no image 2: the file holds 2"), "{err}");
}

#[test]
fn e57_choices_on_other_formats_say_what_they_need() {
    let las = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/laspy/simple.las");
    let las = las.to_str().unwrap();
    let err = |args: &[&str]| {
        let out = omnicloud(args);
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    let e = err(&[
        "render",
        las,
        "-o",
        "/nonexistent/x.png",
        "--color",
        "image",
    ]);
    assert!(
        e.contains("simple.las") && e.contains("needs an E57 file"),
        "{e}"
    );
    let e = err(&["render", las, "-o", "/nonexistent/x.png", "--scan", "1"]);
    assert!(e.contains("only E57 files have scans"), "{e}");
    let e = err(&[
        "render",
        las,
        "-o",
        "/nonexistent/x.png",
        "--camera",
        "station:0",
    ]);
    assert!(e.contains("--camera station:.. needs an E57 file"), "{e}");
}
