//! The files the tests read: real scans kept in the repository (`data/` and `tests/data/`,
//! see tests/data/README.md) and files generated on the spot, in a temporary folder, for
//! what the repository does not hold.
#![allow(dead_code)]

/// The generated building (shared with the library's unit tests).
mod building;

use std::io::Write;
use std::path::{Path, PathBuf};

/// A file of the repository, by its path from the repository's root.
pub fn repo_file(rel: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    assert!(path.exists(), "{} is missing", path.display());
    path
}

/// The sample scan: Autzen stadium, 110,000 points of LAZ.
pub fn autzen() -> PathBuf {
    repo_file("data/autzen_trim.laz")
}

/// The LAS/LAZ files of laspy's test data, all kept in the repository.
pub const LASPY_FILES: [&str; 8] = [
    "autzen_trim.laz",
    "simple.las",
    "simple.laz",
    "simple1_4.las",
    "test1_4.las",
    "1_4_w_evlr.laz",
    "vegetation_1_3.las",
    "extrabytes.las",
];

/// One of [`LASPY_FILES`] by name: `autzen_trim.laz` is the sample in `data/`, the others
/// are test data in `tests/data/laspy/`.
pub fn laspy(name: &str) -> PathBuf {
    assert!(LASPY_FILES.contains(&name), "{name} is no laspy test file");
    if name == "autzen_trim.laz" {
        autzen()
    } else {
        repo_file(&format!("tests/data/laspy/{name}"))
    }
}

/// The lion statue of Potree's example data: 341,989 photogrammetry points, LAZ, point
/// format 2 with full-range 16-bit colour.
pub fn lion() -> PathBuf {
    repo_file("tests/data/potree/lion_takanawa.laz")
}

/// Points of [`lion`].
pub const LION_POINTS: usize = 341_989;

/// A file written into its own temporary folder, deleted when this is dropped.
pub struct Generated {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

impl Generated {
    fn new(name: &str, write: impl FnOnce(&Path) -> std::io::Result<()>) -> Generated {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        write(&path).unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
        Generated { _dir: dir, path }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Points of [`building_ply`].
pub const BUILDING_POINTS: usize = building::BUILDING_POINTS;

/// `building.ply`: a generated building of [`BUILDING_POINTS`] points as ASCII PLY with
/// normals and a `segment_index` a reader must skip, no colour.
pub fn building_ply() -> Generated {
    Generated::new("building.ply", building::write_building_ply)
}

/// The lion's points as binary little-endian PLY, written from the LAZ by the `las` crate
/// (not omnicloud): double x/y/z as the LAZ's scaled coordinates, uchar RGB as the high
/// byte of its 16-bit colour.
pub fn lion_ply() -> Generated {
    Generated::new("lion_takanawa.ply", |path| {
        let points = las::Reader::from_path(lion())
            .and_then(|mut r| r.read_all())
            .map_err(std::io::Error::other)?;
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        write!(
            out,
            "ply\nformat binary_little_endian 1.0\nelement vertex {}\n\
             property double x\nproperty double y\nproperty double z\n\
             property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
            points.len()
        )?;
        let rgb = points.rgb().expect("the lion has colour");
        for (((x, y), z), (r, g, b)) in points.x().zip(points.y()).zip(points.z()).zip(rgb) {
            for v in [x, y, z] {
                out.write_all(&v.to_le_bytes())?;
            }
            out.write_all(&[r, g, b].map(|v| (v >> 8) as u8))?;
        }
        out.flush()
    })
}
