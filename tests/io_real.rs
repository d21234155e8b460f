//! Real scans load with the right counts, attributes and colours.

mod data_common;

use data_common::{BUILDING_POINTS, LION_POINTS, autzen, building_ply, laspy, lion, lion_ply};
use glam::DVec3;
use omnicloud::io::{self, ColorDepth, ColorScale, Format, LoadOptions, PlyEncoding};

/// Every LAS/LAZ file of laspy's test data with its point count, LAS version and point format
/// (from tests/data/README.md).
const LAS_FILES: [(&str, u64, &str, u8); 8] = [
    ("autzen_trim.laz", 110_000, "1.2", 3),
    ("simple.las", 1_065, "1.2", 3),
    ("simple.laz", 1_065, "1.2", 3),
    ("simple1_4.las", 22_600, "1.4", 7),
    ("test1_4.las", 1_000, "1.4", 6),
    ("1_4_w_evlr.laz", 1_000, "1.4", 6),
    ("vegetation_1_3.las", 10_683, "1.3", 1),
    ("extrabytes.las", 1_065, "1.4", 3),
];

#[test]
fn every_laspy_file_loads_with_its_point_count() {
    assert_eq!(LAS_FILES.map(|f| f.0), data_common::LASPY_FILES);
    for (name, count, version, point_format) in LAS_FILES {
        let path = laspy(name);
        let reader = io::open(&path).unwrap();
        let info = reader.info().clone();
        assert_eq!(info.point_count, count, "{name}");
        assert_eq!(info.version, version, "{name}");
        assert_eq!(info.point_format, Some(point_format), "{name}");
        let laz = name.ends_with(".laz");
        assert_eq!(info.format, if laz { Format::Laz } else { Format::Las });
        assert!(info.attributes.intensity && info.attributes.classification);
        let has_rgb = [2, 3, 5, 7, 8, 10].contains(&point_format);
        assert_eq!(info.attributes.rgb, has_rgb, "{name}");

        // Streaming gives every point, in chunks no larger than asked.
        let mut streamed = 0;
        for chunk in reader.chunks(4096) {
            let chunk = chunk.unwrap();
            assert!(chunk.len() <= 4096 && !chunk.is_empty());
            assert_eq!(
                chunk.rgb.as_ref().map(Vec::len),
                has_rgb.then_some(chunk.len())
            );
            streamed += chunk.len() as u64;
        }
        assert_eq!(streamed, count, "{name}");

        let (scene, report) = io::load_scene(&path, &LoadOptions::default()).unwrap();
        assert_eq!(scene.len() as u64, count, "{name}");
        assert_eq!(report.points_read, count);
        assert_eq!(report.dropped_nonfinite, 0);
        // Points lie inside the header bounds.
        let (lo, hi) = info.bounds.unwrap();
        let slack = DVec3::splat(1e-3);
        assert!(report.bounds.0.cmpge(lo - slack).all(), "{name}");
        assert!(report.bounds.1.cmple(hi + slack).all(), "{name}");
    }
}

#[test]
fn las_and_laz_of_the_same_points_agree() {
    let (a, _) = io::load_scene(&laspy("simple.las"), &LoadOptions::default()).unwrap();
    let (b, _) = io::load_scene(&laspy("simple.laz"), &LoadOptions::default()).unwrap();
    assert_eq!(a.origin, b.origin);
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.attributes, b.attributes);
}

#[test]
fn autzen_keeps_8_bit_values_stored_in_16_bit_fields() {
    let path = autzen();
    let (scene, report) = io::load_scene(&path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.len(), 110_000);
    assert_eq!(report.color_scale, Some(ColorScale::Low8In16));
    assert_eq!(report.info.color_depth, ColorDepth::Bits16);

    // Values are the stored 16-bit values themselves (max 236), not divided by 256.
    let mut raw = las::Reader::from_path(&path).unwrap();
    let stored: Vec<[u16; 3]> = raw
        .read_all()
        .unwrap()
        .rgb()
        .unwrap()
        .map(|(r, g, b)| [r, g, b])
        .collect();
    let rgb = scene.attributes.rgb.as_ref().unwrap();
    assert_eq!(stored.iter().flatten().max(), Some(&236));
    assert_eq!(rgb.iter().flatten().max(), Some(&236));
    for (got, want) in rgb.iter().zip(&stored) {
        assert_eq!(got.map(u16::from), *want);
    }
    // Streaming decides the same from its first chunk.
    let mut chunks = io::open(&path).unwrap().chunks(1000);
    let first = chunks.next().unwrap().unwrap();
    assert_eq!(chunks.color_scale(), Some(ColorScale::Low8In16));
    assert_eq!(first.rgb.unwrap()[..10], rgb[..10]);

    // UTM-scale file: the origin is the centre of the bounds and positions are small.
    assert!(
        report.origin.x > 600_000.0 && report.origin.y > 800_000.0,
        "{}",
        report.origin
    );
    let (lo, hi) = scene.bounds().unwrap();
    assert!(lo.abs().max_element() < 2_000.0 && hi.abs().max_element() < 2_000.0);
}

#[test]
fn lion_laz_uses_full_16_bit_range_and_matches_its_ply() {
    let las_path = lion();
    let ply = lion_ply();
    let ply_path = ply.path();
    let (las_scene, las_report) = io::load_scene(&las_path, &LoadOptions::default()).unwrap();
    assert_eq!(las_scene.len(), LION_POINTS);
    assert_eq!(las_report.color_scale, Some(ColorScale::Full16));
    assert_eq!(las_report.info.format, Format::Laz);
    assert_eq!(las_report.info.version, "1.2");
    assert_eq!(las_report.info.point_format, Some(2));

    let ply_info = io::open(ply_path).unwrap().info().clone();
    assert_eq!(
        ply_info.format,
        Format::Ply(PlyEncoding::BinaryLittleEndian)
    );
    assert_eq!(ply_info.color_depth, ColorDepth::Bits8);
    assert_eq!(ply_info.point_count, LION_POINTS as u64);
    assert_eq!(ply_info.bounds, None);

    // Same origin for both so positions compare directly.
    let options = LoadOptions {
        origin: Some(las_report.origin),
        ..LoadOptions::default()
    };
    let (ply_scene, ply_report) = io::load_scene(ply_path, &options).unwrap();
    assert_eq!(ply_scene.len(), LION_POINTS);
    assert_eq!(ply_report.color_scale, Some(ColorScale::Direct8));
    let max_diff = las_scene
        .positions
        .iter()
        .zip(&ply_scene.positions)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(max_diff < 1e-4, "positions differ by up to {max_diff} m");

    let las_rgb = las_scene.attributes.rgb.as_ref().unwrap();
    let ply_rgb = ply_scene.attributes.rgb.as_ref().unwrap();
    let mismatches = las_rgb.iter().zip(ply_rgb).filter(|(a, b)| a != b).count();
    assert_eq!(mismatches, 0, "colours differ on {mismatches} points");
    // A full-range file really uses the range: bright values exist after scaling.
    assert!(las_rgb.iter().flatten().max().copied().unwrap() > 200);

    // Streaming decides Full16 from its first chunk too.
    let mut chunks = io::open(&las_path).unwrap().chunks(50_000);
    let first = chunks.next().unwrap().unwrap();
    assert_eq!(chunks.color_scale(), Some(ColorScale::Full16));
    assert_eq!(first.rgb.unwrap()[..100], las_rgb[..100]);
}

#[test]
fn building_ply_skips_normals_and_segment_index() {
    let building = building_ply();
    let path = building.path();
    let reader = io::open(path).unwrap();
    let info = reader.info().clone();
    assert_eq!(info.format, Format::Ply(PlyEncoding::Ascii));
    assert_eq!(info.point_count, BUILDING_POINTS as u64);
    assert_eq!(info.color_depth, ColorDepth::None);
    assert_eq!(
        info.ignored_properties,
        ["nx", "ny", "nz", "segment_index"].map(String::from)
    );
    let text = info.to_string();
    assert!(text.contains("points:        100,000"), "{text}");
    assert!(text.contains("PLY (ascii)"), "{text}");

    let (scene, report) = io::load_scene(path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.len(), BUILDING_POINTS);
    assert_eq!(report.points_read, BUILDING_POINTS as u64);
    assert!(scene.attributes.rgb.is_none());
    // The first vertex line's x, y, z, read here as text.
    let text = std::fs::read_to_string(path).unwrap();
    let line = text.lines().skip_while(|l| *l != "end_header").nth(1);
    let xyz: Vec<f64> = line
        .unwrap()
        .split(' ')
        .take(3)
        .map(|v| v.parse().unwrap())
        .collect();
    let first = scene.origin + scene.positions[0].as_dvec3();
    let diff = (first - DVec3::from_slice(&xyz)).abs().max_element();
    assert!(diff < 1e-5, "first point {first}, file {xyz:?}");
}

#[test]
fn info_display_for_a_las_file() {
    let path = laspy("simple.las");
    let text = io::open(&path).unwrap().info().to_string();
    let line = |key: &str| {
        text.lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("no {key} line in {text}"))
    };
    assert!(line("format:").contains("LAS"), "{text}");
    assert!(line("version:").ends_with("1.2"), "{text}");
    assert_eq!(
        line("point format:"),
        "point format:  3 (34 bytes a record)"
    );
    assert!(line("points:").ends_with("1,065"), "{text}");
    assert!(line("bounds:").contains("x 6"), "{text}");
    assert_eq!(line("scale:"), "scale:         0.01 0.01 0.01");
    assert_eq!(line("offset:"), "offset:        0 0 0");
    assert_eq!(line("crs:"), "crs:           none declared");
    assert!(
        line("attributes:").contains("rgb, intensity, classification, returns"),
        "{text}"
    );
    assert!(line("colour:").contains("16-bit"), "{text}");
    assert_eq!(
        line("by return:"),
        "by return:     1: 925, 2: 114, 3: 21, 4: 5 (header)"
    );
    assert_eq!(line("created:"), "created:       by TerraScan");
}
