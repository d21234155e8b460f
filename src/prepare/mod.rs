//! Scene preparation: a scan read, its frame centred on the camera and its sphere radii
//! chosen. [`prepare`] is the one path the render command, the stream plan and the benchmark
//! take; [`subsample`] thins a prepared scene for a given render.

pub mod placement;
pub mod radius;
pub mod subsample;

use std::path::{Path, PathBuf};

use glam::DVec3;
use indicatif::ProgressBar;

use crate::io::{LoadError, LoadOptions, LoadReport, Up, load_scene_with_progress};
use crate::scene::Scene;

pub use radius::{RadiusChoice, RadiusRule};
pub use subsample::Subsample;

/// What preparation may be told; the rest is decided from the file.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrepareOptions {
    /// Camera world position (file coordinates); `None` = automatic
    /// ([`placement::auto_camera_position`]).
    pub camera: Option<DVec3>,
    /// Up axis of the file.
    pub up: Up,
    /// Sphere radius; `None` = the file's per-point radii when it has them, else auto
    /// ([`radius::apply_choice`]).
    pub radius: Option<RadiusChoice>,
    /// Zero of the scene's local frame (file coordinates); `None` = the camera position.
    /// A tour keeps one origin for all its frames and moves the camera within that frame.
    /// Only [`prepare`] reads it: the stream plan always centres its chunks on the camera.
    pub origin: Option<DVec3>,
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
}

/// Loads `path`, places the camera (given, or automatic), moves the local zero onto the
/// camera (or onto [`PrepareOptions::origin`]) and sizes the spheres by the radius rule.
/// `progress` counts the point records read.
///
/// # Errors
/// A [`LoadError`] (also when no point has usable coordinates), or
/// [`PrepareError::CameraPlacement`].
pub fn prepare(
    path: &Path,
    options: &PrepareOptions,
    progress: &ProgressBar,
) -> Result<Prepared, PrepareError> {
    let load = LoadOptions {
        origin: options.origin.or(options.camera),
        up: options.up,
        ..LoadOptions::default()
    };
    let (mut scene, report) = load_scene_with_progress(path, &load, progress)?;
    let placed = match options.origin {
        // The scene stays in the origin's frame, loaded there once (no second rounding).
        Some(_) => match options.camera {
            Some(c) => Some(c),
            None => placement::auto_camera_position(&scene).map(|p| scene.origin + p),
        },
        None => placement::center_on_camera(&mut scene, options.camera),
    };
    let camera_world = placed.ok_or_else(|| PrepareError::CameraPlacement {
        path: path.to_path_buf(),
    })?;
    let radii = radius::apply_choice(&mut scene, options.radius);
    Ok(Prepared {
        scene,
        camera_world,
        radii,
        report,
    })
}
