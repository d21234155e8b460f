//! Scene preparation: a scan read, its frame centred on the camera and its sphere radii
//! chosen. [`prepare`] is the one path the render command, the stream plan and the benchmark
//! take; [`subsample`] thins a prepared scene for a given render.

pub mod filter;
pub mod knn;
pub mod lengths;
pub mod lod;
pub mod map_extent;
pub mod placement;
pub mod radius;
pub mod subsample;

use std::path::{Path, PathBuf};

use glam::DVec3;
use indicatif::ProgressBar;

use crate::io::{LoadError, LoadOptions, LoadReport, PointFields, Up, load_files_with_progress};
use crate::scene::Scene;

pub use filter::{FilterCounts, FilterError, PointFilter};
pub use lengths::{LengthScale, Units};
pub use lod::{Lod, LodChoice, LodReport};
pub use placement::{CameraChoice, EyeHeight, StationPick};
pub use radius::{RadiusChoice, RadiusRule};
pub use subsample::Subsample;

/// What preparation may be told; the rest is decided from the file.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrepareOptions {
    /// Where the camera goes: open space near the centre (default), the centre, or a world
    /// position (file coordinates) ([`placement::camera_position`]).
    pub camera: CameraChoice,
    /// Eye height above the local ground for the automatic choices, in file units (given, or
    /// the default rule for a person's eye height in the file's unit).
    pub height: EyeHeight,
    /// Up axis of the file.
    pub up: Up,
    /// Sphere radius; `None` = the file's per-point radii when it has them, else auto
    /// ([`radius::apply_choice`]).
    pub radius: Option<RadiusChoice>,
    /// Which points to keep (classes, returns, crop, distance from the camera).
    pub filter: PointFilter,
    /// Zero of the scene's local frame (file coordinates); `None` = the camera position.
    /// A tour keeps one origin for all its frames and moves the camera within that frame.
    /// Only [`prepare`] reads it: the stream plan always centres its chunks on the camera.
    pub origin: Option<DVec3>,
    /// Level of detail for COPC input ([`lod`]); off by default.
    pub lod: Lod,
    /// The attributes the render needs (its colour's): a COPC read through the level of
    /// detail decodes only these and the filter's, leaving the others out of the scene.
    /// Every attribute by default.
    pub fields: PointFields,
}

impl PrepareOptions {
    /// The attributes a read for these options decodes: the render's and the filter's.
    pub fn fields_read(&self) -> PointFields {
        self.fields.or(self.filter.fields())
    }
}

/// A scan ready to render: its local frame centred on the camera (or on the given origin).
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The scene; its local zero is the camera, or [`PrepareOptions::origin`] when given.
    pub scene: Scene,
    /// The camera's position in file coordinates.
    pub camera_world: DVec3,
    /// How the spheres were sized.
    pub radii: RadiusRule,
    /// What loading did (points read and dropped, colour scale), for the caller to report.
    pub report: LoadReport,
    /// Points each filter removed.
    pub filtered: FilterCounts,
    /// What a view-dependent COPC read chose; `None` when every point was read.
    pub lod: Option<LodReport>,
}

/// Why a scan could not be prepared.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    /// Reading the file failed, or it holds no usable point (the error names the file).
    #[error(transparent)]
    Load(#[from] LoadError),
    /// No camera position could be found on the points.
    #[error(
        "{}: could not place the camera automatically (no usable ground near the centre); pass --camera X,Y,Z",
        path.display()
    )]
    CameraPlacement {
        /// The file.
        path: PathBuf,
    },
    /// A filter cannot run on a file, or the filters left no point.
    #[error(transparent)]
    Filter(#[from] FilterError),
}

/// A note for renders of a file whose coordinate system does not count in metres: with
/// [`Units::Metres`], that the lengths given are converted (the view is life-size); with
/// [`Units::File`], that they are taken in the file's unit and what to give for a life-size
/// view; for degrees, that lengths cannot be converted. `None` for metric files and files
/// that declare no unit.
pub fn units_note(info: &crate::io::FileInfo, scale: &LengthScale) -> Option<String> {
    let units = info.units();
    let path = info.path.display();
    if matches!(units.across, crate::io::Across::Degrees) {
        return Some(format!(
            "{path}: {units}: lengths (--ipd, --height, --radius, --max-distance) cannot be \
             converted to degrees and are taken as coordinate units"
        ));
    }
    match scale.units {
        Units::Metres if scale.converts() => Some(format!(
            "{path}: {units}; {scale}, so the view is life-size (--units file takes them in the \
             file's unit)"
        )),
        Units::Metres => None,
        Units::File => {
            let unit = units.non_metric_across()?;
            let per_metre = 1.0 / unit.metres;
            Some(format!(
                "{path}: with --units file every length (--ipd, --height, --radius, \
                 --max-distance, a tour's --speed) is in {} here, so the default rig is \
                 {per_metre:.2} times too small for the scene; drop --units file for a \
                 life-size view",
                unit.name,
            ))
        }
    }
}

/// Loads `path`, places the camera (given, or automatic), moves the local zero onto the
/// camera (or onto [`PrepareOptions::origin`]), applies the filters and sizes the spheres by
/// the radius rule. `progress` counts the point records read.
///
/// # Errors
/// A [`LoadError`] (also when no point has usable coordinates),
/// [`PrepareError::CameraPlacement`], or a [`FilterError`].
pub fn prepare(
    path: &Path,
    options: &PrepareOptions,
    progress: &ProgressBar,
) -> Result<Prepared, PrepareError> {
    prepare_files(&[path.to_path_buf()], options, progress)
}

/// [`prepare`] for several files rendered as one scene (tiles of a survey): one origin, one
/// camera, one radius rule over all their points (see [`crate::io::load_files_with_progress`]).
/// The crop applies before the camera is placed, the other filters after
/// ([`filter`]).
///
/// # Errors
/// As [`prepare`], naming the file at fault.
///
/// # Panics
/// When `paths` is empty.
pub fn prepare_files(
    paths: &[PathBuf],
    options: &PrepareOptions,
    progress: &ProgressBar,
) -> Result<Prepared, PrepareError> {
    let mut infos = Vec::with_capacity(paths.len());
    for p in paths {
        let info = crate::io::read_info(p)?;
        options.filter.check(&info)?;
        infos.push(info);
    }
    let (paths, skipped) = filter::files_to_read(paths, &infos, options);
    if paths.is_empty() {
        return Err(FilterError::NothingLeft { counts: skipped }.into());
    }
    let load = LoadOptions {
        // A fixed origin is reached from the file's own, as points already in memory are
        // moved onto it: one rounding for both, so a tour of a file and a tour of the same
        // points read into memory give the same frames.
        origin: options.camera.given().filter(|_| options.origin.is_none()),
        up: options.up,
        ..LoadOptions::default()
    };
    let read_infos: Vec<crate::io::FileInfo> = infos
        .iter()
        .filter(|i| paths.contains(&i.path))
        .cloned()
        .collect();
    let (scene, report, lod_read) = match lod::read(&paths, &read_infos, options, progress)? {
        Some((scene, report, lod_read)) => (scene, report, Some(lod_read)),
        None => {
            let (mut scene, report) = load_files_with_progress(&paths, &load, progress)?;
            if let Some(origin) = options.origin {
                scene.recenter(origin);
            }
            (scene, report, None)
        }
    };
    // A view-dependent read has placed the camera already.
    let camera = match &lod_read {
        Some(l) if options.camera.given().is_none() => CameraChoice::At(l.camera_world),
        _ => options.camera,
    };
    let (mut scene, camera_world, filtered) =
        place_and_filter(scene, camera, options, &paths[0], skipped)?;
    let radii = match &lod_read {
        Some(l) => l.apply_radii(&mut scene, options.radius, options.up),
        None => radius::apply_choice(&mut scene, options.radius),
    };
    Ok(Prepared {
        scene,
        camera_world,
        radii,
        report,
        filtered,
        lod: lod_read.map(|l| l.report),
    })
}

/// A scene held in memory (points handed over by a caller rather than read from a file),
/// prepared as [`prepare`] prepares a file's: the same filters, camera placement and radii.
#[derive(Debug, Clone)]
pub struct PreparedScene {
    /// The scene; its local zero is the camera, or [`PrepareOptions::origin`] when given.
    pub scene: Scene,
    /// The camera's position in world coordinates.
    pub camera_world: DVec3,
    /// How the spheres were sized.
    pub radii: RadiusRule,
    /// Points each filter removed.
    pub filtered: FilterCounts,
}

/// [`prepare`]'s steps after reading, for a scene already in memory: the filters, the camera
/// (given or automatic), the local zero moved onto it (or onto [`PrepareOptions::origin`]),
/// the radius rule. `name` names the scene in errors. [`PrepareOptions::lod`] does not apply
/// (there is no file to read selectively).
///
/// # Errors
/// [`FilterError::MissingAttribute`] for a filter whose attribute the scene lacks,
/// [`PrepareError::CameraPlacement`], or a filter that leaves no point.
pub fn prepare_scene(
    mut scene: Scene,
    options: &PrepareOptions,
    name: &Path,
) -> Result<PreparedScene, PrepareError> {
    if let Some(origin) = options.origin {
        scene.recenter(origin);
    }
    let a = &scene.attributes;
    options
        .filter
        .check_attributes(name, a.classification.is_some(), a.returns.is_some())?;
    let (mut scene, camera_world, filtered) = place_and_filter(
        scene,
        options.camera,
        options,
        name,
        FilterCounts::default(),
    )?;
    let radii = radius::apply_choice(&mut scene, options.radius);
    Ok(PreparedScene {
        scene,
        camera_world,
        radii,
        filtered,
    })
}

/// The filters before the camera, the camera placed at `camera`, the local zero moved onto it
/// (or onto [`PrepareOptions::origin`]), the filters after it: what [`prepare_files`] and
/// [`prepare_scene`] share. Returns the scene, the camera's world position and the counts,
/// `skipped` (files left unread) included.
fn place_and_filter(
    scene: Scene,
    camera: CameraChoice,
    options: &PrepareOptions,
    name: &Path,
    skipped: FilterCounts,
) -> Result<(Scene, DVec3, FilterCounts), PrepareError> {
    let (mut scene, mut filtered) =
        options
            .filter
            .apply(scene, options.up, filter::Stage::BeforeCamera);
    filtered += skipped;
    if scene.is_empty() {
        return Err(FilterError::NothingLeft { counts: filtered }.into());
    }
    let placed = match options.origin {
        // The scene is in the origin's frame already.
        Some(_) => {
            placement::camera_position(&scene, camera, options.height).map(|p| scene.origin + p)
        }
        None => placement::center_on_camera(&mut scene, camera, options.height),
    };
    let camera_world = placed.ok_or_else(|| PrepareError::CameraPlacement {
        path: name.to_path_buf(),
    })?;
    let (scene, after) = options
        .filter
        .apply(scene, options.up, filter::Stage::AfterCamera);
    filtered += after;
    if scene.is_empty() {
        return Err(FilterError::NothingLeft { counts: filtered }.into());
    }
    Ok((scene, camera_world, filtered))
}
