//! Generated PLY files: every encoding, coordinate and colour type, radius, Y-up, and the
//! UTM-scale origin handling.

use glam::{DVec3, Vec3};
use omnicloud::Radii;
use omnicloud::io::{self, ColorDepth, ColorScale, Format, LoadOptions, PlyEncoding, Up};
use omnicloud::prepare::placement;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A PLY property: name and PLY type.
type Prop = (&'static str, &'static str);

/// Writes a PLY whose single `vertex` element has `props`, one row of values per point.
/// A `face` element with one list entry follows, so readers must stop at the vertices.
fn write_ply(path: &Path, encoding: PlyEncoding, props: &[Prop], rows: &[Vec<f64>]) {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment generated\nelement vertex {}\n",
        rows.len()
    );
    for (name, ty) in props {
        out += &format!("property {ty} {name}\n");
    }
    out += "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let mut bytes = out.into_bytes();
    let big = encoding == PlyEncoding::BinaryBigEndian;
    for row in rows {
        if encoding == PlyEncoding::Ascii {
            let line: Vec<String> = row.iter().map(|v| format!("{v}")).collect();
            bytes.extend(line.join(" ").bytes());
            bytes.push(b'\n');
            continue;
        }
        for ((_, ty), v) in props.iter().zip(row) {
            macro_rules! put {
                ($t:ty) => {{
                    let x = *v as $t;
                    bytes.extend(if big {
                        x.to_be_bytes().to_vec()
                    } else {
                        x.to_le_bytes().to_vec()
                    });
                }};
            }
            match *ty {
                "uchar" => put!(u8),
                "char" => put!(i8),
                "ushort" => put!(u16),
                "short" => put!(i16),
                "int" => put!(i32),
                "uint" => put!(u32),
                "float" => put!(f32),
                "double" => put!(f64),
                other => panic!("unknown type {other}"),
            }
        }
    }
    match encoding {
        PlyEncoding::Ascii => bytes.extend(b"3 0 1 2\n"),
        _ => {
            bytes.push(3);
            for i in 0..3i32 {
                bytes.extend(if big {
                    i.to_be_bytes()
                } else {
                    i.to_le_bytes()
                });
            }
        }
    }
    std::fs::File::create(path)
        .unwrap()
        .write_all(&bytes)
        .unwrap();
}

const ENCODINGS: [PlyEncoding; 3] = [
    PlyEncoding::Ascii,
    PlyEncoding::BinaryLittleEndian,
    PlyEncoding::BinaryBigEndian,
];

fn tmp(dir: &tempfile::TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

/// Ten points with distinct coordinates (exact in f32) and attributes.
fn rows(colour_max: f64) -> Vec<Vec<f64>> {
    (0..10)
        .map(|i| {
            let f = i as f64;
            vec![
                1.5 * f,
                -2.25 * f,
                0.125 * f + 3.0,
                colour_max * f / 9.0,
                colour_max * (9.0 - f) / 9.0,
                colour_max * 0.5,
                1000.0 + f,
                f + 1.0,
                0.01 * (f + 1.0),
                7.0, // an extra property to skip
            ]
        })
        .collect()
}

#[test]
fn every_encoding_coordinate_and_colour_type_reads_the_same_points() {
    let dir = tempfile::tempdir().unwrap();
    // (coordinate type, colour type, value range of the colour, expected depth)
    let colour_cases = [
        ("uchar", 255.0, ColorDepth::Bits8),
        ("ushort", 65535.0, ColorDepth::Bits16),
        ("float", 1.0, ColorDepth::Float),
    ];
    for encoding in ENCODINGS {
        for coord in ["float", "double"] {
            for (colour, max, depth) in colour_cases {
                let props: Vec<Prop> = vec![
                    ("x", coord),
                    ("y", coord),
                    ("z", coord),
                    ("red", colour),
                    ("green", colour),
                    ("blue", colour),
                    ("intensity", "ushort"),
                    ("classification", "uchar"),
                    ("radius", "float"),
                    ("nx", "float"),
                ];
                let case = format!("{encoding:?} {coord} {colour}");
                let path = tmp(&dir, &format!("{encoding:?}_{coord}_{colour}.ply"));
                // Binary ushort/uchar colour stores integers: round the generated values.
                let data: Vec<Vec<f64>> = rows(max)
                    .into_iter()
                    .map(|mut r| {
                        if colour != "float" {
                            for v in &mut r[3..6] {
                                *v = v.round();
                            }
                        }
                        r
                    })
                    .collect();
                write_ply(&path, encoding, &props, &data);

                let info = io::open(&path).unwrap().info().clone();
                assert_eq!(info.format, Format::Ply(encoding), "{case}");
                assert_eq!(info.point_count, 10, "{case}");
                assert_eq!(info.color_depth, depth, "{case}");
                assert!(info.attributes.rgb && info.attributes.intensity, "{case}");
                assert!(
                    info.attributes.classification && info.attributes.radius,
                    "{case}"
                );
                assert_eq!(info.ignored_properties, vec!["nx".to_string()], "{case}");

                let options = LoadOptions {
                    origin: Some(DVec3::ZERO),
                    ..LoadOptions::default()
                };
                let (scene, report) = io::load_scene(&path, &options).unwrap();
                assert_eq!(scene.len(), 10, "{case}");
                assert_eq!(report.dropped_nonfinite, 0);
                let rgb = scene.attributes.rgb.as_ref().unwrap();
                for (i, row) in data.iter().enumerate() {
                    let want = Vec3::new(row[0] as f32, row[1] as f32, row[2] as f32);
                    assert_eq!(scene.positions[i], want, "{case} point {i}");
                    // Every colour type lands on the same 8-bit value (+-1 for rounding).
                    let want_rgb = [row[3], row[4], row[5]].map(|v| (v / max * 255.0).round());
                    for c in 0..3 {
                        let got = f64::from(rgb[i][c]);
                        assert!(
                            (got - want_rgb[c]).abs() <= 1.0,
                            "{case} point {i}: {got} vs {}",
                            want_rgb[c]
                        );
                    }
                    assert_eq!(
                        scene.attributes.intensity.as_ref().unwrap()[i],
                        1000 + i as u16
                    );
                    assert_eq!(
                        scene.attributes.classification.as_ref().unwrap()[i],
                        i as u8 + 1
                    );
                }
                match &scene.radii {
                    Radii::PerPoint(r) => {
                        assert_eq!(r.len(), 10);
                        assert!((r[4] - 0.05).abs() < 1e-6, "{case}");
                    }
                    other => panic!("{case}: expected per-point radii, got {other:?}"),
                }
                let expected_scale = if colour == "ushort" {
                    ColorScale::Full16
                } else {
                    ColorScale::Direct8
                };
                assert_eq!(report.color_scale, Some(expected_scale), "{case}");
            }
        }
    }
}

#[test]
fn streaming_small_chunks_gives_every_point_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = tmp(&dir, "pts.ply");
    let props: Vec<Prop> = vec![("x", "double"), ("y", "double"), ("z", "double")];
    let data: Vec<Vec<f64>> = (0..1000).map(|i| vec![i as f64, 0.0, 0.0]).collect();
    write_ply(&path, PlyEncoding::BinaryBigEndian, &props, &data);
    let xs: Vec<f64> = io::open(&path)
        .unwrap()
        .chunks(7)
        .flat_map(|c| {
            let c = c.unwrap();
            assert!(c.len() <= 7 && c.rgb.is_none() && c.radius.is_none());
            c.positions.into_iter().map(|p| p.x)
        })
        .collect();
    assert_eq!(xs, (0..1000).map(f64::from).collect::<Vec<_>>());
}

#[test]
fn y_up_files_are_turned_z_up() {
    let dir = tempfile::tempdir().unwrap();
    let path = tmp(&dir, "yup.ply");
    let props: Vec<Prop> = vec![("x", "float"), ("y", "float"), ("z", "float")];
    // A point 2 m up (file Y) and 3 m towards the viewer (file +Z).
    write_ply(
        &path,
        PlyEncoding::Ascii,
        &props,
        &[vec![1.0, 2.0, 3.0], vec![0.0, 0.0, 0.0]],
    );
    let options = LoadOptions {
        origin: Some(DVec3::ZERO),
        up: Up::Y,
        ..LoadOptions::default()
    };
    let (scene, _) = io::load_scene(&path, &options).unwrap();
    assert_eq!(scene.positions[0], Vec3::new(1.0, -3.0, 2.0));
    let (scene, _) = io::load_scene(
        &path,
        &LoadOptions {
            up: Up::Z,
            ..options
        },
    )
    .unwrap();
    assert_eq!(scene.positions[0], Vec3::new(1.0, 2.0, 3.0));
}

#[test]
fn utm_scale_points_keep_millimetres_next_to_an_auto_placed_camera() {
    let dir = tempfile::tempdir().unwrap();
    let path = tmp(&dir, "utm.ply");
    let props: Vec<Prop> = vec![("x", "double"), ("y", "double"), ("z", "double")];
    // Flat ground at z = 100 m over 40 m x 40 m at UTM coordinates, plus one marker point.
    let (x0, y0) = (637_000.0, 851_000.0);
    let mut data: Vec<Vec<f64>> = Vec::new();
    for i in 0..=80 {
        for j in 0..=80 {
            data.push(vec![
                x0 - 20.0 + 0.5 * i as f64,
                y0 - 20.0 + 0.5 * j as f64,
                100.0,
            ]);
        }
    }
    let marker = DVec3::new(x0 + 1.234_5, y0 + 2.345_6, 101.111_1);
    data.push(marker.to_array().to_vec());
    write_ply(&path, PlyEncoding::BinaryLittleEndian, &props, &data);

    let (mut scene, report) = io::load_scene(&path, &LoadOptions::default()).unwrap();
    assert!((report.origin - DVec3::new(x0, y0, 100.0 + 1.1111 / 2.0)).length() < 1e-9);
    let camera_local = placement::auto_camera_position(&scene).unwrap();
    assert!(
        (camera_local.z - (100.0 + 1.7 - report.origin.z)).abs() < 1e-4,
        "{camera_local}"
    );
    let camera_world = scene.origin + camera_local;
    assert!((camera_world.truncate() - glam::DVec2::new(x0, y0)).length() < 1e-6);

    // Re-origin at the camera (what the renderer does) and measure the marker relative to it.
    scene.recenter(camera_world);
    let got = scene.positions[data.len() - 1].as_dvec3();
    let want = marker - camera_world;
    assert!(
        (got - want).abs().max_element() < 1e-3 * 0.01,
        "{got} vs {want}"
    );
    // Storing absolute UTM coordinates in f32 would not: its spacing there is 6 cm.
    let naive = (marker.as_vec3() - camera_world.as_vec3()).as_dvec3();
    assert!(
        (naive - want).abs().max_element() > 1e-3,
        "the check above would not bite"
    );
    // The same file loaded with the camera as origin agrees to well under a millimetre.
    let direct = LoadOptions {
        origin: Some(camera_world),
        ..LoadOptions::default()
    };
    let (scene2, _) = io::load_scene(&path, &direct).unwrap();
    let got2 = scene2.positions[data.len() - 1].as_dvec3();
    assert!((got2 - want).abs().max_element() < 1e-5, "{got2} vs {want}");
}
