//! `omnicloud index`: the COPC it writes gives back every point exactly (through `las`, through
//! the library's COPC node reader, and through laspy's `CopcReader` when Python has it), with
//! stored radii the level-of-detail path keeps; a small memory cap splits the buckets; broken
//! inputs and interrupts leave no output and no temporary file.

mod data_common;
mod interrupt_common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use indicatif::ProgressBar;
use omnicloud::index::{self, IndexOptions};
use omnicloud::io::{self, LoadOptions};

/// One point as compared: coordinates and every kept attribute, as exact bits.
type Row = (u64, u64, u64, u16, u8, u8, u8, [u16; 3], u64);

/// Every point of a LAS/LAZ/COPC file through the `las` crate, sorted.
fn las_rows(path: &Path) -> Vec<Row> {
    let mut reader = las::Reader::from_path(path).unwrap();
    let mut rows: Vec<Row> = reader
        .read_all()
        .unwrap()
        .points()
        .map(|p| {
            let p = p.unwrap();
            let c = p.color.map_or([0; 3], |c| [c.red, c.green, c.blue]);
            (
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits(),
                p.intensity,
                u8::from(p.classification),
                p.return_number,
                p.number_of_returns,
                c,
                p.gps_time.unwrap_or(0.0).to_bits(),
            )
        })
        .collect();
    rows.sort_unstable();
    rows
}

/// One point as the library's readers give it (colour scaled to 8 bits, no GPS time).
type LibraryRow = (u64, u64, u64, u16, u8, u8, u8, [u8; 3]);

/// Point and attribute rows through the library's readers: `reader` gives the chunks.
fn library_rows(reader: io::PointReader) -> Vec<LibraryRow> {
    let mut rows = Vec::new();
    for chunk in reader.chunks(10_000) {
        let c = chunk.unwrap();
        for i in 0..c.len() {
            let p = c.positions[i];
            let r = c.returns.as_ref().unwrap()[i];
            rows.push((
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits(),
                c.intensity.as_ref().unwrap()[i],
                c.classification.as_ref().unwrap()[i],
                r.number,
                r.of,
                c.rgb.as_ref().map_or([0; 3], |v| v[i]),
            ));
        }
    }
    rows.sort_unstable();
    rows
}

fn index_into(
    inputs: &[PathBuf],
    dir: &Path,
    options: &IndexOptions,
) -> (PathBuf, index::IndexReport) {
    let out = dir.join("out.copc.laz");
    let report = index::index(inputs, &out, options, &ProgressBar::hidden()).unwrap();
    (out, report)
}

fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// Checks that `out` holds exactly the points of `inputs`: through `las`, and through the
/// library's COPC reader with every node against its plain reader of the inputs.
fn assert_round_trip(inputs: &[PathBuf], out: &Path) {
    let mut expected: Vec<Row> = inputs.iter().flat_map(|p| las_rows(p)).collect();
    expected.sort_unstable();
    let got = las_rows(out);
    assert_eq!(got.len(), expected.len());
    assert!(got == expected, "{}: the points differ", out.display());

    let octree = io::read_octree(out).unwrap();
    assert_eq!(octree.point_count as usize, expected.len());
    let every: Vec<_> = octree.nodes.keys().copied().collect();
    let nodes = library_rows(io::open_nodes(out, &every).unwrap());
    let mut plain: Vec<_> = inputs
        .iter()
        .flat_map(|p| library_rows(io::open(p).unwrap()))
        .collect();
    plain.sort_unstable();
    assert!(nodes == plain, "{}: the node reader differs", out.display());
}

#[test]
fn autzen_lion_and_vegetation_come_back_exactly() {
    for input in [
        data_common::autzen(),
        data_common::lion(),
        data_common::laspy("vegetation_1_3.las"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let inputs = std::slice::from_ref(&input);
        let (out, report) = index_into(inputs, dir.path(), &IndexOptions::default());
        assert_round_trip(inputs, &out);
        // Colour gives format 7, none format 6; the radii are stored.
        let info = io::read_info(&out).unwrap();
        assert!(io::is_copc(&info));
        assert_eq!(info.point_format, Some(report.point_format));
        assert_eq!(report.point_format, if info.attributes.rgb { 7 } else { 6 });
        assert!(info.attributes.radius, "{}", input.display());
        assert_eq!(leftovers(dir.path()), ["out.copc.laz"]);
    }
}

/// Autzen cut at its median x into two LAS tiles with Autzen's grid.
fn autzen_tiles(dir: &Path) -> Vec<PathBuf> {
    let mut reader = las::Reader::from_path(data_common::autzen()).unwrap();
    let points: Vec<las::Point> = reader
        .read_all()
        .unwrap()
        .points()
        .map(Result::unwrap)
        .collect();
    let mut xs: Vec<f64> = points.iter().map(|p| p.x).collect();
    xs.sort_by(f64::total_cmp);
    let median = xs[xs.len() / 2];
    let mut builder = las::Builder::from(reader.header().clone());
    builder.point_format.is_compressed = false;
    let header = builder.into_header().unwrap();
    let paths: Vec<PathBuf> = (0..2).map(|i| dir.join(format!("tile{i}.las"))).collect();
    for (i, path) in paths.iter().enumerate() {
        let mut w = las::Writer::from_path(path, header.clone()).unwrap();
        for p in points.iter().filter(|p| (p.x >= median) == (i == 1)) {
            w.write_point(p.clone()).unwrap();
        }
        w.close().unwrap();
    }
    paths
}

#[test]
fn two_tiles_make_one_index() {
    let dir = tempfile::tempdir().unwrap();
    let tiles = autzen_tiles(dir.path());
    let (out, report) = index_into(&tiles, dir.path(), &IndexOptions::default());
    assert_eq!(report.points, 110_000);
    assert_round_trip(&tiles, &out);
    // The coordinate system comes along.
    let crs = io::read_info(&out).unwrap().las.unwrap().crs.unwrap();
    assert!(crs.name.unwrap().contains("Lambert"));
}

#[test]
fn a_small_memory_cap_splits_the_work_and_keeps_every_point() {
    let dir = tempfile::tempdir().unwrap();
    let input = data_common::lion();
    // 16 MB: buckets of at most 50,000 points (the floor) for the 341,989 points.
    let options = IndexOptions {
        max_memory: 16 << 20,
        ..IndexOptions::default()
    };
    let (out, report) = index_into(std::slice::from_ref(&input), dir.path(), &options);
    assert!(report.buckets >= 7, "{} buckets", report.buckets);
    assert!(report.largest_bucket <= 50_000, "{}", report.largest_bucket);
    assert_round_trip(&[input], &out);
}

#[test]
fn stored_radii_are_kept_by_the_level_of_detail_read() {
    use omnicloud::prepare::{CameraChoice, Lod, PrepareOptions, prepare};
    let dir = tempfile::tempdir().unwrap();
    let (out, _) = index_into(
        &[data_common::autzen()],
        dir.path(),
        &IndexOptions::default(),
    );
    // Full detail, whole file: the stored full-detail radii (adaptive:8, median measured
    // 1.215 ft).
    let (scene, _) = io::load_scene(&out, &LoadOptions::default()).unwrap();
    let omnicloud::Radii::PerPoint(fine) = &scene.radii else {
        panic!("the stored radii are not read");
    };
    let mut sorted = fine.clone();
    sorted.sort_by(f32::total_cmp);
    let median = sorted[sorted.len() / 2];
    assert!((1.1..1.35).contains(&median), "median radius {median}");
    // A view from 2,500 ft above reads fewer points, keeps the stored radii (no neighbour
    // search) and its stopping points are larger than the full-detail ones.
    let options = PrepareOptions {
        camera: CameraChoice::At(glam::DVec3::new(636_600.0, 849_200.0, 3_000.0)),
        lod: Lod::Pixels {
            width: 256,
            pixels: 1.0,
            floor: 0,
        },
        ..PrepareOptions::default()
    };
    let prepared = prepare(&out, &options, &ProgressBar::hidden()).unwrap();
    let lod = prepared.lod.unwrap();
    // Measured: 9,255 points (the root), their stopping radius 4.77 ft (the root's 9.2 ft
    // spacing closed).
    assert!(lod.points_read < 12_000, "{lod}");
    assert!(prepared.radii.keep_file_radii);
    let omnicloud::Radii::PerPoint(radii) = &prepared.scene.radii else {
        panic!("per-point radii expected");
    };
    let mut sorted = radii.clone();
    sorted.sort_by(f32::total_cmp);
    let coarse = sorted[sorted.len() / 2];
    assert!(
        coarse > median * 3.0 && coarse < 6.0,
        "coarse view median {coarse} against {median}"
    );
}

/// A level-of-detail read decodes the attributes its render asks for and leaves the others
/// out, with the same points, radii and colours as a read of every attribute.
#[test]
fn a_read_decodes_only_the_attributes_asked_for() {
    use omnicloud::io::PointFields;
    use omnicloud::prepare::{CameraChoice, Lod, PrepareOptions, prepare};
    use omnicloud::render::ColorMode;
    let dir = tempfile::tempdir().unwrap();
    let (out, _) = index_into(
        &[data_common::autzen()],
        dir.path(),
        &IndexOptions::default(),
    );
    let read = |fields: PointFields| {
        let options = PrepareOptions {
            camera: CameraChoice::At(glam::DVec3::new(636_600.0, 849_200.0, 1_500.0)),
            lod: Lod::Pixels {
                width: 512,
                pixels: 1.0,
                floor: 0,
            },
            fields,
            ..PrepareOptions::default()
        };
        prepare(&out, &options, &ProgressBar::hidden()).unwrap()
    };
    let all = read(PointFields::ALL);
    let lod = all.lod.as_ref().unwrap();
    // Measured: 39,705 points (9 nodes, levels 0-1), most where refinement stopped.
    assert!((30_000..50_000).contains(&lod.points_read), "{lod}");
    let a = &all.scene.attributes;
    assert!(a.rgb.is_some() && a.intensity.is_some() && a.classification.is_some());
    for (mode, rgb, intensity, classification) in [
        (ColorMode::Auto, true, false, false),
        (ColorMode::Elevation, false, false, false),
        (ColorMode::Intensity, false, true, false),
        (ColorMode::Classification, false, false, true),
    ] {
        let some = read(mode.fields());
        assert_eq!(some.scene.positions, all.scene.positions, "{mode:?}");
        assert_eq!(some.scene.radii, all.scene.radii, "{mode:?}");
        let b = &some.scene.attributes;
        assert_eq!(b.rgb.is_some(), rgb, "{mode:?}");
        assert_eq!(b.intensity.is_some(), intensity, "{mode:?}");
        assert_eq!(b.classification.is_some(), classification, "{mode:?}");
        // Return numbers decode with the coordinates.
        assert_eq!(b.returns, a.returns, "{mode:?}");
        if rgb {
            assert_eq!(b.rgb, a.rgb);
        }
        if intensity {
            assert_eq!(b.intensity, a.intensity);
        }
        if classification {
            assert_eq!(b.classification, a.classification);
        }
    }
    // A class filter reads the classification whatever the colour.
    let filtered = PrepareOptions {
        filter: omnicloud::prepare::PointFilter {
            drop_classes: Some(omnicloud::prepare::filter::ClassSet::of(&[7])),
            ..Default::default()
        },
        fields: ColorMode::Elevation.fields(),
        ..PrepareOptions::default()
    };
    assert!(filtered.fields_read().classification);
}

/// A fixed `--radius` is metres, stored in the unit the file declares (Autzen: international
/// feet), or the file's unit as given with `Units::File`.
#[test]
fn a_fixed_radius_is_metres_stored_in_the_files_unit() {
    use omnicloud::prepare::{RadiusChoice, Units};
    let dir = tempfile::tempdir().unwrap();
    let input = data_common::autzen();
    for (units, want) in [(Units::Metres, 0.3 / 0.3048), (Units::File, 0.3)] {
        let options = IndexOptions {
            radius: Some(RadiusChoice::Fixed(0.3)),
            units,
            ..IndexOptions::default()
        };
        let (out, _) = index_into(std::slice::from_ref(&input), dir.path(), &options);
        let (scene, _) = io::load_scene(&out, &LoadOptions::default()).unwrap();
        let radii = match &scene.radii {
            omnicloud::Radii::PerPoint(r) => r.clone(),
            other => panic!("{units:?}: stored radii not read: {other:?}"),
        };
        assert!(
            radii.iter().all(|&r| (f64::from(r) - want).abs() < 1e-6),
            "{units:?}: radii {:?}.., want {want}",
            &radii[..3]
        );
    }
}

/// laspy's CopcReader reads the index, every point and both radius fields.
#[test]
fn laspy_reads_the_index() {
    let probe = Command::new("python3")
        .args(["-c", "import laspy, lazrs"])
        .status();
    if !probe.is_ok_and(|s| s.success()) {
        assert!(
            std::env::var_os("OMNICLOUD_REQUIRE_LASPY").is_none(),
            "OMNICLOUD_REQUIRE_LASPY is set but python3 cannot import laspy and lazrs"
        );
        eprintln!(
            "\n*** SKIPPED laspy_reads_the_index: python3 with laspy and lazrs is not importable \
             (pip install laspy lazrs) ***\n"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (out, _) = index_into(&[data_common::lion()], dir.path(), &IndexOptions::default());
    let script = r#"
import sys, numpy as np
from laspy import CopcReader
with CopcReader.open(sys.argv[1]) as r:
    pts = r.query()
    fmt = r.header.point_format.id
    names = list(pts.point_format.extra_dimension_names)
    lod = np.asarray(pts.omnicloud_lod_radius) >= np.asarray(pts.omnicloud_radius)
print(len(pts), fmt, ",".join(names), bool(lod.all()))
"#;
    let run = Command::new("python3")
        .args(["-c", script])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "laspy failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(
        stdout.trim(),
        format!(
            "{} 7 omnicloud_radius,omnicloud_lod_radius True",
            data_common::LION_POINTS
        )
    );
}

fn omnicloud_index(inputs: &[&Path], out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .arg("index")
        .args(inputs)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn broken_inputs_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let lion = std::fs::read(data_common::lion()).unwrap();
    let truncated = dir.path().join("truncated.laz");
    std::fs::write(&truncated, &lion[..lion.len() / 2]).unwrap();
    let garbage = dir.path().join("garbage.las");
    let mut bytes = b"LASF".to_vec();
    bytes.extend((0..2000u32).map(|i| (i * 7919 % 251) as u8));
    std::fs::write(&garbage, bytes).unwrap();
    for bad in [&truncated, &garbage] {
        let out = dir.path().join("out.copc.laz");
        let run = omnicloud_index(&[&data_common::autzen(), bad], &out);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success());
        let name = bad.file_name().unwrap().to_string_lossy();
        assert!(stderr.contains(name.as_ref()), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        let mut left: HashSet<String> = leftovers(dir.path()).into_iter().collect();
        left.remove("truncated.laz");
        left.remove("garbage.las");
        assert!(left.is_empty(), "left behind: {left:?}");
    }
}

#[test]
fn an_interrupt_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lion.copc.laz");
    let mut command = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    command
        .args(["index", "--max-memory", "16M"])
        .arg(data_common::lion())
        .arg("-o")
        .arg(&out);
    let run = interrupt_common::interrupt_at_progress(command, "indexing");
    interrupt_common::assert_interrupted(&run);
    assert!(
        leftovers(dir.path()).is_empty(),
        "left behind: {:?}",
        leftovers(dir.path())
    );
}
