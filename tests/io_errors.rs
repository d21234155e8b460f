//! Every bad input gives the right typed error naming the file, never a panic.

mod data_common;

use data_common::laspy;
use omnicloud::io::{self, LoadError, LoadOptions};
use std::path::{Path, PathBuf};

/// Loads the whole file (header and points); the error must name the file.
fn load_err(path: &Path) -> LoadError {
    let err = match io::load_scene(path, &LoadOptions::default()) {
        Ok((scene, _)) => panic!("{} loaded {} points", path.display(), scene.len()),
        Err(e) => e,
    };
    assert_eq!(err.path(), path);
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let text = err.to_string();
    assert!(text.contains(&name), "error does not name the file: {text}");
    assert!(!text.contains('\n'), "error is not one line: {text}");
    err
}

fn write(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `simple.las`, LAS 1.2, 1065 points of 34 bytes.
fn simple_las() -> Vec<u8> {
    std::fs::read(laspy("simple.las")).unwrap()
}

fn offset_to_points(las: &[u8]) -> usize {
    u32::from_le_bytes(las[96..100].try_into().unwrap()) as usize
}

#[test]
fn missing_empty_directory_and_unknown_files() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.las");
    assert!(matches!(load_err(&missing), LoadError::NotFound { .. }));
    assert!(matches!(
        io::open(&missing),
        Err(LoadError::NotFound { .. })
    ));

    for name in ["empty.las", "empty.ply", "empty.xyz"] {
        let path = write(&dir, name, b"");
        assert!(
            matches!(load_err(&path), LoadError::EmptyFile { .. }),
            "{name}"
        );
    }

    let sub = dir.path().join("folder.las");
    std::fs::create_dir(&sub).unwrap();
    assert!(matches!(load_err(&sub), LoadError::Unreadable { .. }));

    let xyz = write(&dir, "points.xyz", b"1 2 3\n4 5 6\n");
    match load_err(&xyz) {
        LoadError::UnsupportedFormat { extension, .. } => assert_eq!(extension, "xyz"),
        other => panic!("{other}"),
    }
    let none = write(&dir, "points", b"1 2 3\n");
    assert!(matches!(
        load_err(&none),
        LoadError::UnsupportedFormat { .. }
    ));
}

#[test]
fn wrong_magic_under_a_known_extension_is_a_corrupt_header() {
    let dir = tempfile::tempdir().unwrap();
    let mut las = simple_las();
    las[3] = b'X';
    let path = write(&dir, "bad_magic.las", &las);
    assert!(matches!(
        load_err(&path),
        LoadError::CorruptHeader { format: "LAS", .. }
    ));
    let path = write(&dir, "bad_magic.ply", b"plx\nformat ascii 1.0\n");
    assert!(matches!(
        load_err(&path),
        LoadError::CorruptHeader { format: "PLY", .. }
    ));
    // PLY magic but a broken header line.
    let path = write(
        &dir,
        "bad_header.ply",
        b"ply\nformat ascii 1.0\nelement vertex x\nend_header\n",
    );
    assert!(matches!(
        load_err(&path),
        LoadError::CorruptHeader { format: "PLY", .. }
    ));
    // Magic bytes win over the extension: a LAS file named .ply loads as LAS.
    let path = write(&dir, "really_las.ply", &simple_las());
    assert_eq!(io::open(&path).unwrap().info().point_count, 1065);
}

#[test]
fn truncated_las_at_every_kind_of_cut() {
    let dir = tempfile::tempdir().unwrap();
    let las = simple_las();
    let start = offset_to_points(&las);
    let record = 34;
    for cut in [
        2,
        50,
        200,
        start - 10,
        start + 5,
        start + 100 * record + 7,
        las.len() - 1,
    ] {
        let path = write(&dir, &format!("cut_{cut}.las"), &las[..cut]);
        let err = load_err(&path);
        if cut <= start {
            assert!(
                matches!(err, LoadError::CorruptHeader { .. }),
                "cut {cut}: {err}"
            );
        } else {
            match err {
                LoadError::PointCountExceedsFile {
                    declared,
                    available,
                    ..
                } => {
                    assert_eq!(declared, 1065);
                    assert_eq!(available, ((cut - start) / record) as u64, "cut {cut}");
                }
                other => panic!("cut {cut}: {other}"),
            }
        }
    }
}

#[test]
fn truncated_laz_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    for file in ["simple.laz", "autzen_trim.laz", "1_4_w_evlr.laz"] {
        let laz = std::fs::read(laspy(file)).unwrap();
        let len = laz.len();
        for cut in [3, 100, 400, len / 4, len / 2, len - 100, len - 1] {
            let path = write(&dir, &format!("cut_{cut}.laz"), &laz[..cut]);
            let err = load_err(&path);
            assert!(
                matches!(
                    err,
                    LoadError::CorruptHeader { .. } | LoadError::CorruptPoints { .. }
                ),
                "{file} cut {cut}: {err}"
            );
        }
    }
}

#[test]
fn point_count_larger_than_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut las = simple_las();
    las[107..111].copy_from_slice(&5000u32.to_le_bytes());
    let path = write(&dir, "too_many.las", &las);
    match load_err(&path) {
        LoadError::PointCountExceedsFile {
            declared,
            available,
            ..
        } => {
            assert_eq!((declared, available), (5000, 1065));
        }
        other => panic!("{other}"),
    }

    let header = |format: &str, n: usize| {
        format!(
            "ply\nformat {format} 1.0\nelement vertex {n}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
        )
    };
    let mut bin = header("binary_little_endian", 20).into_bytes();
    bin.extend(std::iter::repeat_n(0u8, 10 * 12 + 5));
    let path = write(&dir, "too_many_bin.ply", &bin);
    match load_err(&path) {
        LoadError::PointCountExceedsFile {
            declared,
            available,
            ..
        } => {
            assert_eq!((declared, available), (20, 10));
        }
        other => panic!("{other}"),
    }

    let mut text = header("ascii", 20);
    for i in 0..10 {
        text += &format!("{i} 0 0\n");
    }
    let path = write(&dir, "too_many.ply", text.as_bytes());
    match load_err(&path) {
        LoadError::CorruptPoints { read, declared, .. } => assert_eq!((read, declared), (10, 20)),
        other => panic!("{other}"),
    }
    // Cut inside the PLY header.
    let path = write(&dir, "cut_header.ply", &header("ascii", 3).as_bytes()[..40]);
    assert!(matches!(load_err(&path), LoadError::CorruptHeader { .. }));
}

#[test]
fn zero_points() {
    let dir = tempfile::tempdir().unwrap();
    let mut las = simple_las();
    las[107..111].copy_from_slice(&0u32.to_le_bytes());
    let path = write(&dir, "zero.las", &las);
    assert!(matches!(load_err(&path), LoadError::NoPoints { .. }));
    assert!(matches!(io::open(&path), Err(LoadError::NoPoints { .. })));

    let ply = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    let path = write(&dir, "zero.ply", ply.as_bytes());
    assert!(matches!(load_err(&path), LoadError::NoPoints { .. }));
}

#[test]
fn unsupported_las_version_and_point_format() {
    let dir = tempfile::tempdir().unwrap();
    let mut las = simple_las();
    las[25] = 5;
    let path = write(&dir, "v1_5.las", &las);
    match load_err(&path) {
        LoadError::UnsupportedLasVersion { major, minor, .. } => assert_eq!((major, minor), (1, 5)),
        other => panic!("{other}"),
    }
    let mut las = simple_las();
    las[24] = 2;
    let path = write(&dir, "v2.las", &las);
    assert!(matches!(
        load_err(&path),
        LoadError::UnsupportedLasVersion { major: 2, .. }
    ));

    let mut las = simple_las();
    las[104] = 11;
    let path = write(&dir, "format11.las", &las);
    assert!(matches!(
        load_err(&path),
        LoadError::UnsupportedLasPointFormat { .. }
    ));
}

#[test]
fn ply_without_xyz() {
    let dir = tempfile::tempdir().unwrap();
    let no_z = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n";
    let path = write(&dir, "no_z.ply", no_z.as_bytes());
    match load_err(&path) {
        LoadError::PlyMissingXyz { detail, .. } => assert!(detail.contains("'z'"), "{detail}"),
        other => panic!("{other}"),
    }
    let no_vertex = "ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n1\n";
    let path = write(&dir, "no_vertex.ply", no_vertex.as_bytes());
    assert!(matches!(load_err(&path), LoadError::PlyMissingXyz { .. }));
    let list_x = "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\nproperty float z\nend_header\n1 1 2 3\n";
    let path = write(&dir, "list_x.ply", list_x.as_bytes());
    assert!(matches!(load_err(&path), LoadError::PlyMissingXyz { .. }));
    // A garbage value in the payload is corrupt point data.
    let garbage = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n1 two 3\n";
    let path = write(&dir, "garbage.ply", garbage.as_bytes());
    assert!(matches!(
        load_err(&path),
        LoadError::CorruptPoints { read: 1, .. }
    ));
}

#[test]
fn non_finite_points_are_dropped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let head = |n: usize| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex {n}\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
        )
    };
    let body = "1 2 3 10 20 30\nNaN 0 0 1 1 1\n4 inf 6 2 2 2\n7 8 -inf 3 3 3\n9 10 11 40 50 60\n";
    let path = write(&dir, "nan.ply", (head(5) + body).as_bytes());
    let options = LoadOptions {
        origin: Some(glam::DVec3::ZERO),
        ..LoadOptions::default()
    };
    let (scene, report) = io::load_scene(&path, &options).unwrap();
    assert_eq!(report.points_read, 5);
    assert_eq!(report.dropped_nonfinite, 3);
    assert_eq!(report.points_kept, 2);
    assert_eq!(
        scene.positions,
        vec![
            glam::Vec3::new(1.0, 2.0, 3.0),
            glam::Vec3::new(9.0, 10.0, 11.0)
        ]
    );
    // Attributes stay aligned with the kept points.
    assert_eq!(scene.attributes.rgb, Some(vec![[10, 20, 30], [40, 50, 60]]));
    // The default origin (centre of the bounds) ignores the dropped points.
    let (_, report) = io::load_scene(&path, &LoadOptions::default()).unwrap();
    assert_eq!(report.origin, glam::DVec3::new(5.0, 6.0, 7.0));

    // Binary NaN/inf too, and a file of nothing but them is an error.
    let mut bin = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n".as_bytes().to_vec();
    for v in [f32::NAN, 0.0, 0.0, 0.0, f32::INFINITY, 0.0] {
        bin.extend(v.to_le_bytes());
    }
    let path = write(&dir, "all_nan.ply", &bin);
    match load_err(&path) {
        LoadError::NoFinitePoints { dropped, .. } => assert_eq!(dropped, 2),
        other => panic!("{other}"),
    }
}

/// Found by the mutation harness: a binary PLY declaring four billion zero-byte `face` records
/// before its vertices took 30 s to skip them one by one; fixed-size records are now skipped in
/// one seek, checked against the file's length.
#[test]
fn billions_of_records_before_the_vertices_are_skipped_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let vertices: Vec<u8> = (0..3u32)
        .flat_map(|k| [k as f32, 0.0, 1.0].into_iter().flat_map(f32::to_be_bytes))
        .collect();
    for (face, expect_points) in [
        // Zero bytes each: nothing to skip, the vertices follow.
        ("element face 4294967295\n", true),
        // Four bytes each: far more than the file holds.
        ("element face 4294967295\nproperty int n\n", false),
    ] {
        let mut bytes = format!(
            "ply\nformat binary_big_endian 1.0\n{face}element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
        )
        .into_bytes();
        bytes.extend(&vertices);
        let path = write(&dir, "faces_first.ply", &bytes);
        let started = std::time::Instant::now();
        let result = io::load_scene(&path, &LoadOptions::default());
        assert!(
            started.elapsed() < std::time::Duration::from_secs(2),
            "took {:?}",
            started.elapsed()
        );
        match result {
            Ok((scene, _)) => {
                assert!(expect_points, "loaded {} points", scene.len());
                assert_eq!(scene.len(), 3);
            }
            Err(e) => {
                assert!(!expect_points, "{e}");
                let text = e.to_string();
                assert!(
                    text.contains("faces_first.ply") && text.contains("face"),
                    "{text}"
                );
            }
        }
    }
}
