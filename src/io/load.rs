//! Whole-file loading into a [`Scene`]: f64 file coordinates minus one f64 origin, stored as
//! f32 (DESIGN §1), non-finite points dropped and counted.

use super::chunk::{ColorScale, RawChunk, RawRgb};
use super::error::LoadError;
use super::info::FileInfo;
use super::{PointReader, open};
use crate::scene::{Attributes, Radii, Scene, extend_masked, masked};
use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};

/// Points read per chunk while loading.
const LOAD_CHUNK: usize = 1 << 16;
/// Upper bound on memory reserved from a header's (untrusted) point count.
const MAX_RESERVE: u64 = 1 << 24;

/// Which file axis points up (`--up`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Up {
    /// Z up (LAS/LiDAR convention): coordinates are kept.
    #[default]
    Z,
    /// Y up (many PLY exports): file `(x, y, z)` becomes world `(x, -z, y)`, a rotation that
    /// keeps the frame right-handed.
    Y,
}

impl Up {
    /// File coordinates to the Z-up world frame.
    #[inline]
    pub fn to_world(self, p: DVec3) -> DVec3 {
        match self {
            Up::Z => p,
            Up::Y => DVec3::new(p.x, -p.z, p.y),
        }
    }
}

/// How [`load_scene`] places and sizes the points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadOptions {
    /// World (Z-up, after the `up` swap) coordinate of the local frame's zero; `None` = the
    /// centre of the points' bounds.
    pub origin: Option<DVec3>,
    /// Which file axis points up.
    pub up: Up,
    /// Sphere radius (metres) for files without a per-point `radius`, and for points whose
    /// radius is not a positive finite number.
    pub default_radius: f32,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            origin: None,
            up: Up::Z,
            default_radius: 0.02,
        }
    }
}

/// What [`load_scene`] did, for the caller to print once.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadReport {
    /// Header facts of the file.
    pub info: FileInfo,
    /// Point records read from the file.
    pub points_read: u64,
    /// Points kept in the scene.
    pub points_kept: u64,
    /// Points dropped because a coordinate was NaN or infinite.
    pub dropped_nonfinite: u64,
    /// How colour was scaled to 8 bits (`None` without colour); decided from every point.
    pub color_scale: Option<ColorScale>,
    /// Origin of the scene's local frame (world coordinates).
    pub origin: DVec3,
    /// `(min, max)` of the kept points in world coordinates.
    pub bounds: (DVec3, DVec3),
}

/// Positions while loading: local f32 once the origin is known, f64 world until then.
enum Positions {
    Local(DVec3, Vec<Vec3>),
    World(Vec<DVec3>),
}

/// Colour while loading, unscaled.
enum ColorAccum {
    Bits8(Vec<[u8; 3]>),
    Bits16(Vec<[u16; 3]>),
}

/// Largest |coordinate| kept, metres. Beyond it a point is treated like a NaN one: f64 values
/// near f32::MAX become infinite once re-originated to f32 (the fuzz harness found PLY files
/// whose retyped properties read as 1e300), and no scan spans 1e30 m.
const MAX_COORDINATE: f64 = 1e30;

/// Widest header bounds (metres) trusted as the origin's source: larger than any real scan.
pub(crate) const MAX_HEADER_EXTENT: f64 = 1e7;

/// The union of the files' header bounds in world (Z-up) coordinates; `None` when any file
/// has none.
pub(crate) fn header_extent(infos: &[FileInfo], up: Up) -> Option<(DVec3, DVec3)> {
    infos
        .iter()
        .map(|i| {
            i.bounds.map(|(lo, hi)| {
                let (a, b) = (up.to_world(lo), up.to_world(hi));
                (a.min(b), a.max(b))
            })
        })
        .reduce(|a, b| a.zip(b).map(|(a, b)| (a.0.min(b.0), a.1.max(b.1))))
        .flatten()
}

/// A point that survives loading: finite and within [`MAX_COORDINATE`].
pub(crate) fn usable(p: DVec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// Reads a whole LAS/LAZ/PLY file into a [`Scene`].
///
/// The origin is `options.origin`, else the centre of the header bounds (LAS, when the first
/// chunk lies inside them), else the centre of the points' bounds (positions are then held as
/// f64 until the end: 24 extra bytes per point). Points with a NaN/inf coordinate are dropped
/// and counted in the report; nothing is printed. 16-bit colour is scaled by a
/// [`ColorScale`] decided from all points.
///
/// # Errors
/// Any [`LoadError`] from [`open`] or from reading the points; [`LoadError::NoFinitePoints`]
/// when no point survives.
pub fn load_scene(path: &Path, options: &LoadOptions) -> Result<(Scene, LoadReport), LoadError> {
    load_scene_with_progress(path, options, &ProgressBar::hidden())
}

/// [`load_scene`], with `progress` counting the point records read (its length set to the
/// declared count).
///
/// # Errors
/// As [`load_scene`].
pub fn load_scene_with_progress(
    path: &Path,
    options: &LoadOptions,
    progress: &ProgressBar,
) -> Result<(Scene, LoadReport), LoadError> {
    load_files_with_progress(&[path.to_path_buf()], options, progress)
}

/// Several files read into one [`Scene`], in order, as [`load_scene_with_progress`] reads one:
/// one origin for all (`options.origin`, else the centre of the union of the headers' bounds
/// when every file has them and the first points lie inside, else the centre of all points),
/// one colour scale decided from every point. An attribute some file lacks (colour, a PLY
/// without classification) is left out for all. The report's `info` is the first file's;
/// its counts and bounds cover all files.
///
/// # Errors
/// As [`load_scene`], naming the file that failed.
///
/// # Panics
/// When `paths` is empty.
pub fn load_files_with_progress(
    paths: &[PathBuf],
    options: &LoadOptions,
    progress: &ProgressBar,
) -> Result<(Scene, LoadReport), LoadError> {
    load_files_with_reader(paths, options, progress, &open)
}

/// [`load_files_with_progress`] with the files opened by `open` (e.g. [`super::open_nodes`]
/// for chosen nodes of a COPC file) instead of [`super::open`].
///
/// # Errors
/// As [`load_scene`], naming the file that failed.
///
/// # Panics
/// When `paths` is empty.
pub fn load_files_with_reader(
    paths: &[PathBuf],
    options: &LoadOptions,
    progress: &ProgressBar,
    open: &dyn Fn(&Path) -> Result<PointReader, LoadError>,
) -> Result<(Scene, LoadReport), LoadError> {
    assert!(!paths.is_empty(), "load_files_with_progress needs a file");
    let path = paths[0].as_path();
    let mut infos = Vec::with_capacity(paths.len());
    let mut declared = 0u64;
    let mut first_reader = None;
    for p in paths {
        let reader = open(p)?;
        infos.push(reader.info().clone());
        declared = declared.saturating_add(reader.points_to_read());
        if first_reader.is_none() {
            first_reader = Some(reader);
        }
    }
    let info = infos[0].clone();
    let up = options.up;
    // The count is untrusted (LAZ and ascii PLY cannot check it against the file size), so the
    // reservation is also bounded by the file length: real files spend at least about a byte
    // per point, and where one spends less the vectors simply grow.
    let file_len: u64 = paths
        .iter()
        .map(|p| std::fs::metadata(p).map_or(0, |m| m.len()))
        .sum();
    let reserve = declared.min(MAX_RESERVE).min(file_len) as usize;
    progress.set_length(declared);
    let header_centre = header_extent(&infos, up);

    let mut positions: Option<Positions> = None;
    let mut rgb: Option<ColorAccum> = None;
    let mut intensity = None;
    let mut classification = None;
    let mut returns = None;
    let mut radius = None;
    let mut points_read = 0u64;
    let mut dropped = 0u64;
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);

    for p in paths {
        let mut reader = match first_reader.take() {
            Some(r) => r,
            None => open(p)?,
        };
        while let Some(raw) = reader.next_raw(LOAD_CHUNK)? {
            let RawChunk {
                positions: file_positions,
                rgb: chunk_rgb,
                intensity: chunk_intensity,
                classification: chunk_classification,
                returns: chunk_returns,
                radius: chunk_radius,
                gps_time: _,
            } = raw;
            points_read += file_positions.len() as u64;
            progress.inc(file_positions.len() as u64);
            let world: Vec<DVec3> = file_positions.into_iter().map(|p| up.to_world(p)).collect();
            let kept: Vec<bool> = world.iter().map(|p| usable(*p)).collect();
            dropped += kept.iter().filter(|k| !**k).count() as u64;

            let positions = positions.get_or_insert_with(|| {
                // Header bounds are trusted for the origin only if they are plausible (finite, no
                // wider than any scan) and the data agrees with them: a corrupt header must not
                // put the origin where positions overflow f32.
                let header_origin = header_centre
                    .filter(|(blo, bhi)| {
                        usable(*blo)
                            && usable(*bhi)
                            && (*bhi - *blo).max_element() <= MAX_HEADER_EXTENT
                    })
                    .filter(|(blo, bhi)| {
                        let slack = DVec3::splat(1.0) + (*bhi - *blo) * 0.01;
                        world
                            .iter()
                            .filter(|p| usable(**p))
                            .all(|p| p.cmpge(*blo - slack).all() && p.cmple(*bhi + slack).all())
                    })
                    .map(|(blo, bhi)| (blo + bhi) * 0.5);
                match options.origin.or(header_origin) {
                    Some(origin) => Positions::Local(origin, Vec::with_capacity(reserve)),
                    None => Positions::World(Vec::with_capacity(reserve)),
                }
            });
            for p in world.iter().filter(|p| usable(**p)) {
                lo = lo.min(*p);
                hi = hi.max(*p);
                match positions {
                    Positions::Local(origin, v) => v.push((*p - *origin).as_vec3()),
                    Positions::World(v) => v.push(*p),
                }
            }

            match chunk_rgb {
                Some(RawRgb::Bits8(c)) => {
                    let acc =
                        rgb.get_or_insert_with(|| ColorAccum::Bits8(Vec::with_capacity(reserve)));
                    if let ColorAccum::Bits8(v) = acc {
                        v.extend(masked(&c, &kept));
                    }
                }
                Some(RawRgb::Bits16(c)) => {
                    let acc =
                        rgb.get_or_insert_with(|| ColorAccum::Bits16(Vec::with_capacity(reserve)));
                    if let ColorAccum::Bits16(v) = acc {
                        v.extend(masked(&c, &kept));
                    }
                }
                None => {}
            }
            extend_masked(&mut intensity, chunk_intensity.as_deref(), &kept);
            extend_masked(&mut classification, chunk_classification.as_deref(), &kept);
            extend_masked(&mut returns, chunk_returns.as_deref(), &kept);
            extend_masked(&mut radius, chunk_radius.as_deref(), &kept);
        }
    }

    let points_kept = points_read - dropped;
    if points_kept == 0 {
        return Err(if points_read == 0 {
            LoadError::NoPoints {
                path: path.to_path_buf(),
            }
        } else {
            LoadError::NoFinitePoints {
                path: path.to_path_buf(),
                dropped,
            }
        });
    }
    let (origin, positions) = match positions {
        Some(Positions::Local(origin, v)) => (origin, v),
        Some(Positions::World(v)) => {
            let placed = Scene::from_world(v.len(), |i| v[i], options.origin, 0.0);
            (placed.origin, placed.positions)
        }
        None => unreachable!("points_kept > 0 implies a chunk was read"),
    };
    // An attribute some file lacks covers only part of the points: left out for all.
    let n = positions.len();
    fn whole<T>(v: Option<Vec<T>>, n: usize) -> Option<Vec<T>> {
        v.filter(|v| v.len() == n)
    }
    let rgb = rgb.filter(|c| match c {
        ColorAccum::Bits8(v) => v.len() == n,
        ColorAccum::Bits16(v) => v.len() == n,
    });
    let intensity = whole(intensity, n);
    let classification = whole(classification, n);
    let returns = whole(returns, n);
    let radius = whole(radius, n);
    let (rgb, color_scale) = match rgb {
        None => (None, None),
        Some(ColorAccum::Bits8(v)) => (Some(v), Some(ColorScale::Direct8)),
        Some(ColorAccum::Bits16(v)) => {
            let raw = RawRgb::Bits16(v);
            let scale = ColorScale::detect_16(raw.max_16().unwrap_or(0));
            (Some(raw.into_u8(scale)), Some(scale))
        }
    };
    let radii = Radii::from_file(radius, options.default_radius);
    let scene = Scene {
        origin,
        positions,
        radii,
        attributes: Attributes {
            rgb,
            intensity,
            classification,
            returns,
        },
    };
    let report = LoadReport {
        info,
        points_read,
        points_kept,
        dropped_nonfinite: dropped,
        color_scale,
        origin,
        bounds: (lo, hi),
    };
    Ok((scene, report))
}
