//! `omnicloud info`: header-only by default, `--stats` for a pass over the points, `--json`
//! for scripts, the coordinate system from the WKT VLR or the GeoTIFF keys.

mod data_common;

use std::path::Path;
use std::process::{Command, Output};

use data_common::{LASPY_FILES, building_ply, laspy, lion, lion_ply};
use serde_json::Value;

fn omnicloud(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json_of(out: &Output) -> Value {
    let text = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(text.trim()).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// `(min, max)` corners.
type Corners = ([f64; 3], [f64; 3]);

/// `(declared points, header bounds)` read independently of omnicloud: the `las` crate for
/// LAS/LAZ, the `element vertex N` line for PLY (which has no bounds).
fn header_truth(path: &Path) -> (u64, Option<Corners>) {
    if path.extension().is_some_and(|e| e == "ply") {
        let bytes = std::fs::read(path).unwrap();
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
        let n = text
            .lines()
            .find_map(|l| l.strip_prefix("element vertex "))
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        return (n, None);
    }
    let reader = las::Reader::from_path(path).unwrap();
    let h = reader.header();
    let b = h.bounds();
    (
        h.number_of_points(),
        Some(([b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z])),
    )
}

fn xyz(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|i| a[i].as_f64().unwrap())
}

#[test]
fn json_of_every_test_file_gives_the_header_count_and_bounds() {
    let (building, lion_ply) = (building_ply(), lion_ply());
    let mut files: Vec<_> = LASPY_FILES.iter().map(|name| laspy(name)).collect();
    files.extend([
        lion(),
        building.path().to_owned(),
        lion_ply.path().to_owned(),
    ]);
    for path in files {
        let name = path.display().to_string();
        let out = omnicloud(&["info", "--json", &name]);
        assert!(out.status.success(), "{name}: {out:?}");
        let v = json_of(&out);
        let (count, bounds) = header_truth(&path);
        assert_eq!(v["point_count"].as_u64(), Some(count), "{name}");
        assert_eq!(v["file"].as_str(), Some(name.as_str()));
        assert_eq!(v["truncated"], Value::Bool(false), "{name}");
        match bounds {
            Some((lo, hi)) => {
                // serde_json's default float parsing may be one ULP off.
                let near = |a: [f64; 3], b: [f64; 3]| {
                    (0..3).all(|i| (a[i] - b[i]).abs() <= 1e-12 * b[i].abs().max(1.0))
                };
                assert!(near(xyz(&v["bounds"]["min"]), lo), "{name}: {lo:?}");
                assert!(near(xyz(&v["bounds"]["max"]), hi), "{name}: {hi:?}");
                assert!(
                    v["scale"].is_array() && v["point_format"].is_u64(),
                    "{name}"
                );
            }
            None => assert!(v["bounds"].is_null(), "{name}"),
        }
    }
}

#[test]
fn the_sample_shows_its_crs_and_stats() {
    let autzen = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz");
    let autzen = autzen.to_str().unwrap();
    let out = omnicloud(&["info", autzen]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{out:?}");
    assert!(
        text.contains("crs:           NAD_1983_HARN_Lambert_Conformal_Conic"),
        "{text}"
    );
    // Autzen's WKT gives feet (UNIT["foot",0.3048]): sizes say so.
    assert!(
        text.contains("units:         x, y in foot (0.3048 m); z not declared"),
        "{text}"
    );
    assert!(
        text.contains("(size 1177.460 x 562.700 x 114.250 ft)"),
        "{text}"
    );
    assert!(
        !text.contains("classes:"),
        "no point pass without --stats: {text}"
    );

    let out = omnicloud(&["info", "--stats", "--json", autzen]);
    assert!(out.status.success(), "{out:?}");
    let v = json_of(&out);
    let s = &v["stats"];
    assert_eq!(s["points_read"], 110_000);
    let classes: Vec<(u64, &str, u64)> = s["classes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["code"].as_u64().unwrap(),
                c["name"].as_str().unwrap(),
                c["count"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        classes,
        [(1, "unclassified", 83_893), (2, "ground", 26_107)]
    );
    // The per-point return numbers agree with the header's counts by return.
    let by_return: Vec<u64> = s["return_numbers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["count"].as_u64().unwrap())
        .collect();
    assert_eq!(by_return, [99_257, 9_021, 1_623, 99]);
    assert_eq!(
        v["points_by_return"].as_array().unwrap().len(),
        by_return.len()
    );
    assert_eq!(s["intensity"]["max"], 254);
    assert_eq!(s["color_scale"], "8-bit values in 16-bit fields");
    let spacing = s["spacing"].as_f64().unwrap();
    assert!((spacing - 1.336).abs() < 0.01, "{spacing}");
}

/// A LAS 1.4 file with a WKT coordinate system, written with the `las` crate.
fn write_las_with_wkt(path: &Path, wkt: &str) {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(6).unwrap();
    let mut header = builder.into_header().unwrap();
    header.set_wkt_crs(wkt.as_bytes().to_vec()).unwrap();
    let mut writer = las::Writer::from_path(path, header).unwrap();
    for i in 0..10 {
        writer
            .write_point(las::Point {
                x: 1_000.0 + f64::from(i),
                y: 2_000.0,
                z: 10.0,
                return_number: 1,
                number_of_returns: 1,
                gps_time: Some(0.0),
                ..Default::default()
            })
            .unwrap();
    }
    writer.close().unwrap();
}

#[test]
fn a_wkt_crs_is_printed_by_name_with_its_epsg_code() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("utm.las");
    let wkt = r#"PROJCS["WGS 84 / UTM zone 10N",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]],PROJECTION["Transverse_Mercator"],PARAMETER["central_meridian",-123],UNIT["metre",1],AUTHORITY["EPSG","32610"]]"#;
    write_las_with_wkt(&path, wkt);
    let name = path.to_str().unwrap();
    let out = omnicloud(&["info", name]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("crs:           WGS 84 / UTM zone 10N (EPSG:32610, from the WKT VLR)"),
        "{text}"
    );
    let v = json_of(&omnicloud(&["info", "--json", name]));
    assert_eq!(v["crs"]["name"], "WGS 84 / UTM zone 10N");
    assert_eq!(v["crs"]["epsg"], 32610);
    assert_eq!(v["crs"]["source"], "wkt");
    assert_eq!(v["crs"]["wkt"], wkt);
    assert_eq!(v["crs"]["units"]["across"], "metre");
    assert_eq!(v["crs"]["units"]["across_metres"], 1.0);
    assert!(v["crs"]["units"]["up"].is_null());
    assert!(
        text.contains("units:         x, y in metre; z not declared"),
        "{text}"
    );
    assert!(text.contains("(size 9.000 x 0.000 x 0.000 m)"), "{text}");
    assert_eq!(v["version"], "1.4");
    assert_eq!(v["point_count"], 10);
}

#[test]
fn header_mode_reads_no_point_and_stats_report_truncation() {
    let dir = tempfile::tempdir().unwrap();
    // simple.las: 1,065 records of 34 bytes after a 227-byte header; cut inside the points.
    let whole = std::fs::read(laspy("simple.las")).unwrap();
    let cut = dir.path().join("cut.las");
    std::fs::write(&cut, &whole[..20_000]).unwrap();
    let name = cut.to_str().unwrap();
    let out = omnicloud(&["info", name]);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(
            "points:        1,065 declared, but the file holds only 581 records: truncated"
        ),
        "{text}"
    );
    let v = json_of(&omnicloud(&["info", "--json", name]));
    assert_eq!(
        (v["point_count"].as_u64(), v["records_in_file"].as_u64()),
        (Some(1065), Some(581))
    );
    assert_eq!(v["truncated"], true);

    let out = omnicloud(&["info", "--stats", name]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--stats") && err.contains("declares 1065 points but the file holds only 581"),
        "{err}"
    );

    // A LAZ file cut in half: its header is still read; the point pass says what broke.
    let whole =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz")).unwrap();
    let cut = dir.path().join("cut.laz");
    std::fs::write(&cut, &whole[..whole.len() / 2]).unwrap();
    let name = cut.to_str().unwrap();
    let v = json_of(&omnicloud(&["info", "--json", name]));
    assert_eq!(v["point_count"], 110_000);
    let out = omnicloud(&["info", "--stats", "--json", name]);
    assert!(!out.status.success());
    let v = json_of(&out);
    let e = v["stats_error"].as_str().unwrap();
    assert!(e.contains("truncated or corrupt"), "{e}");
    assert!(v["stats"].is_null());
}

#[test]
fn survey_feet_are_named_and_a_render_in_feet_says_what_its_rig_is() {
    let evlr = laspy("1_4_w_evlr.laz");
    let out = omnicloud(&["info", evlr.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{out:?}");
    assert!(
        text.contains("units:         x, y in US survey foot (0.30480061 m); z not declared"),
        "{text}"
    );
    assert!(text.contains("x 6.320 ftUS)"), "{text}");
    let v = json_of(&omnicloud(&["info", "--json", evlr.to_str().unwrap()]));
    let per_unit = v["crs"]["units"]["across_metres"].as_f64().unwrap();
    assert!((per_unit - 1200.0 / 3937.0).abs() < 1e-15, "{per_unit}");

    // The note comes before the render, whichever renderer; a metric file has none.
    let dir = tempfile::tempdir().unwrap();
    let autzen = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz");
    let note = "note: ";
    let out = dir.path().join("a.png");
    // The render's stderr, after checking it succeeded.
    let render = |file: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--renderer",
            "raytrace",
        ];
        args.extend(extra);
        let run = omnicloud(&args);
        let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
        assert!(run.status.success(), "{stderr}");
        stderr
    };
    let stderr = render(&autzen, &[]);
    assert!(
        stderr.contains(&format!(
            "{note}{}: x, y in foot (0.3048 m); z not declared; lengths in metres (1 m = 3.2808 \
             ft), so the view is life-size (--units file takes them in the file's unit)\n",
            autzen.display()
        )),
        "{stderr}"
    );
    let stderr = render(&autzen, &["--units", "file", "--stereo", "ods"]);
    assert!(
        stderr.contains(&format!(
            "{note}{}: with --units file every length (--ipd, --height, --radius, \
             --max-distance, a tour's --speed) is in foot here, so the default rig is 3.28 times \
             too small for the scene; drop --units file for a life-size view: --ipd 0.064 ft\n",
            autzen.display()
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("radius adaptive:8 (median 1.2154 ft)"),
        "{stderr}"
    );
    let utm = dir.path().join("utm.las");
    write_las_with_wkt(
        &utm,
        r#"PROJCS["WGS 84 / UTM zone 10N",GEOGCS["WGS 84",UNIT["degree",0.0174532925199433]],UNIT["metre",1]]"#,
    );
    let stderr = render(&utm, &["--camera", "1004.5,2000,11.7"]);
    assert!(!stderr.contains(note), "{stderr}");
}
