//! Loading a scan for rendering: read it, centre it on the camera, choose sphere radii.

use anyhow::{Context, Result, bail};
use glam::DVec3;

use crate::io::{LoadOptions, Up, load_scene};
use crate::scene::{Radii, Scene};
use crate::{placement, radius};

use super::args::UpArg;
use super::parse::RadiusChoice;

/// A scan ready to render: local frame centred on the camera.
pub struct Prepared {
    /// The scene, camera at the local origin.
    pub scene: Scene,
    /// The camera's position in file coordinates.
    pub camera_world: DVec3,
}

/// Loads `file`, places the camera (given, or automatic), and sets the radii: a fixed radius,
/// `auto`, or by default the file's per-point radii when present, else `auto`.
/// Warnings (dropped points) go through `warn`.
pub fn prepare(
    file: &std::path::Path,
    camera: Option<DVec3>,
    up: UpArg,
    radius_choice: Option<RadiusChoice>,
    warn: impl Fn(String),
) -> Result<Prepared> {
    let options = LoadOptions {
        origin: camera,
        up: match up {
            UpArg::Z => Up::Z,
            UpArg::Y => Up::Y,
        },
        ..LoadOptions::default()
    };
    let (mut scene, report) = load_scene(file, &options)?;
    if report.dropped_nonfinite > 0 {
        warn(format!(
            "warning: dropped {} points with NaN/inf coordinates from {}",
            report.dropped_nonfinite,
            file.display()
        ));
    }
    if scene.is_empty() {
        bail!(
            "{}: no point with finite coordinates to render",
            file.display()
        );
    }
    let camera_world = placement::center_on_camera(&mut scene, camera)
        .context("could not place the camera automatically; pass --camera X,Y,Z")?;
    match radius_choice {
        Some(RadiusChoice::Fixed(r)) => scene.radii = Radii::Uniform(r),
        None if matches!(scene.radii, Radii::PerPoint(_)) => {}
        Some(RadiusChoice::Auto) | None => {
            scene.radii = Radii::Uniform(radius::auto_radius(&scene))
        }
    }
    Ok(Prepared {
        scene,
        camera_world,
    })
}
