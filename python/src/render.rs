//! `omnicloud.render`: the cloud prepared and rendered by the library, as `omnicloud render`
//! prepares and renders a file.

use std::sync::Arc;

use glam::DVec3;
use omnicloud::output::{Layout, OutputOptions};
use omnicloud::prepare::{CameraChoice, EyeHeight, Lod, PrepareOptions, prepare_scene};
use omnicloud::projection::Camera;
use omnicloud::render::RenderSettings;
use omnicloud::renderer::Resident;
use pyo3::prelude::*;

use crate::cloud::PointCloud;
use crate::errors::{prepare_error, render_error, value_error};
use crate::image::Image;
use crate::options::{as_text, finite, parse};
use crate::progress::with_progress;
use crate::view::{View, ViewArgs};

/// Renders `cloud` to a panorama (or another projection), as `omnicloud render` renders a
/// file with the same options; `Image.save` then writes the same file.
///
/// - `width`: image width per eye, even, 16 to 16384 (the height follows the projection).
/// - `stereo`: "none" (mono), "ods" (omnidirectional stereo, left eye on top), "parallel"
///   or "cubemap[:N]".
/// - `projection`: "equirect[:HFOV,VFOV]", "hammer", "cylindrical[:VFOV]", "fisheye[:FOV]",
///   "cubemap" or "map" (top-down over the cloud, mono).
/// - `camera`: "auto" (open space near the centre, ground below), "center", or (x, y, z)
///   in the cloud's coordinates; `height`: eye height above the ground for "auto" and
///   "center", metres [default 1.7, or 20 point spacings over sparse data].
/// - `yaw`, `pitch`, `roll`: degrees (yaw 0 looks along +Y, 90 along +X).
/// - `ipd`: interocular distance, metres; `pole_merge` (and `pole_merge_north`,
///   `pole_merge_south`): "off", "comfortable", "cycles", "marrinan:START,END,EXP" or
///   "cycles:FROM,TO"; `ods_offset`: "exact" or "paper".
/// - `renderer`: "raster" (GPU, Vulkan) or "raytrace" (CPU, exact).
/// - `color`: "auto" (rgb when present, else elevation), "rgb", "intensity",
///   "classification", "elevation" or "flat"; `shading`: "unlit", "phong" or "normal".
/// - `radius`: sphere radius in metres, "auto" or "adaptive[:K]" [default: the cloud's
///   per-point radii when it has them, else adaptive:8].
/// - Filters: `classes`, `drop_classes` (codes as "2,6" or a list), `returns` ("all",
///   "first", "last"), `crop` (x0, y0, x1, y1), `max_distance` (metres from the camera).
/// - `units`: "metres" (lengths above are metres, converted to the cloud's unit) or
///   "file" (taken in the cloud's unit).
/// - `edl` (strength, e.g. 1.0) and `edl_radius` (pixels): eye-dome lighting;
///   `supersample`: N x N samples per pixel; `background`: "#rrggbb", "black", (r, g, b),
///   "transparent" [default: transparent].
/// - `progress`: called as `progress(done, total)` while rendering.
///
/// The cloud is left as it is: the render prepares a copy (centred on the camera, filtered),
/// so memory peaks at about twice the cloud's. The GIL is released while rendering. Raises ValueError for a bad argument (with the
/// library's message), RuntimeError when no GPU adapter is found for "raster".
#[pyfunction]
#[pyo3(signature = (
    cloud, *, width=3840, stereo="none", projection="equirect", camera=None, height=None,
    yaw=0.0, pitch=0.0, roll=0.0, ipd=0.064, pole_merge="comfortable",
    pole_merge_north=None, pole_merge_south=None, ods_offset="exact", renderer="raster",
    color="auto", shading="unlit", radius=None, classes=None, drop_classes=None,
    returns="all", crop=None, max_distance=None, units="metres", edl=None, edl_radius=1.4,
    supersample=1, background=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub fn render(
    py: Python<'_>,
    cloud: &PointCloud,
    width: u32,
    stereo: &str,
    projection: &str,
    camera: Option<&Bound<'_, PyAny>>,
    height: Option<f64>,
    yaw: f64,
    pitch: f64,
    roll: f64,
    ipd: f64,
    pole_merge: &str,
    pole_merge_north: Option<&str>,
    pole_merge_south: Option<&str>,
    ods_offset: &str,
    renderer: &str,
    color: &str,
    shading: &str,
    radius: Option<&Bound<'_, PyAny>>,
    classes: Option<&Bound<'_, PyAny>>,
    drop_classes: Option<&Bound<'_, PyAny>>,
    returns: &str,
    crop: Option<&Bound<'_, PyAny>>,
    max_distance: Option<f64>,
    units: &str,
    edl: Option<f32>,
    edl_radius: f32,
    supersample: u32,
    background: Option<&Bound<'_, PyAny>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Image> {
    let view = ViewArgs {
        width,
        stereo,
        projection,
        ipd,
        pole_merge,
        pole_merge_north,
        pole_merge_south,
        ods_offset,
        renderer,
        color,
        shading,
        radius,
        classes,
        drop_classes,
        returns,
        crop,
        max_distance,
        units,
        edl,
        edl_radius,
        supersample,
        background,
    }
    .parse(cloud)?;
    let View {
        scale,
        projection,
        renderer: kind,
        look,
        ..
    } = view;
    let camera_choice = match camera {
        None => CameraChoice::default(),
        Some(c) => parse::<CameraChoice>("camera", &as_text("camera", c)?)?,
    };
    if height.is_some() && matches!(camera_choice, CameraChoice::At(_)) {
        return Err(value_error(
            "height places an automatic camera: drop it with camera=(x, y, z)",
        ));
    }
    let height = match height {
        Some(h) if !(h.is_finite() && h > 0.0) => {
            return Err(value_error(format!(
                "height: {h} is not a positive distance in metres"
            )));
        }
        h => h.map(|h| scale.height(h)),
    };
    let map = view.image.is_none();
    let image = match &view.image {
        Some(out) => look.render_image(out).map_err(value_error)?,
        None => view.settings.image,
    };
    let options = PrepareOptions {
        camera: camera_choice,
        height: EyeHeight::new(height, scale.height(1.0)),
        up: cloud.up,
        radius: view.radius,
        filter: view.filter,
        lod: Lod::Off,
        // The scene is in memory already: no read, so no attribute selection applies.
        ..PrepareOptions::default()
    };
    let settings = RenderSettings {
        image,
        // Scenes are centred on the camera: it sits at the local origin.
        camera: Camera::new(DVec3::ZERO, finite("yaw", yaw)?)
            .with_orientation(finite("pitch", pitch)?, finite("roll", roll)?),
        ..view.settings
    };
    let scene = Arc::clone(&cloud.scene);
    let name = cloud.name.clone();
    let rendered = with_progress(py, progress, |pb| {
        let prepared = prepare_scene((*scene).clone(), &options, &name).map_err(prepare_error)?;
        let settings = if map {
            let map = omnicloud::prepare::map_extent::map_image(&prepared.scene, width)
                .map_err(|e| value_error(format!("{}: {e}", name.display())))?;
            RenderSettings {
                image: look.render_image(&map).map_err(value_error)?,
                ..settings
            }
        } else {
            settings
        };
        let resident = Resident::new(&prepared.scene, kind, &settings).map_err(render_error)?;
        let rendered = resident.render(&settings, pb).map_err(render_error)?;
        Ok::<_, PyErr>((look.finish(rendered), prepared.camera_world))
    })??;
    let (rendered, camera_world) = rendered;
    Ok(Image::new(
        rendered,
        OutputOptions {
            layout: Layout::TopBottom,
            jpeg_quality: omnicloud::output::jpeg::DEFAULT_QUALITY,
            yaw_degrees: yaw,
            projection,
            metres_per_unit: scale.metres_per_unit,
        },
        Some(camera_world),
    ))
}
