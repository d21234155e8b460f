//! `omnicloud.tour`: a camera path given as an array, laid out and rendered by the library's
//! tour (the same plan, frames and `tour.json` as `omnicloud tour`).

use std::path::PathBuf;
use std::sync::Arc;

use glam::DVec3;
use numpy::PyReadonlyArray2;
use omnicloud::prepare::{EyeHeight, Lod, PrepareOptions};
use omnicloud::render::Background;
use omnicloud::renderer::Resident;
use omnicloud::tour::run::{RunError, render_frame};
use omnicloud::tour::{
    FrameFormat, Keyframe, Route, RunOptions, Sampling, TourError, TourRequest, TourScan,
};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;

use crate::cloud::PointCloud;
use crate::errors::{output_error, prepare_error, render_error, value_error};
use crate::image::Image;
use crate::options::{finite, value_enum};
use crate::progress::with_progress;
use crate::view::ViewArgs;

/// How the keyframes given as an array are named in messages and in `tour.json`.
const PATH_NAME: &str = "<path array>";

/// Renders a tour of `cloud` along `path`, as `omnicloud tour` renders a scan along a path
/// file with the same options: the same frames, byte for byte, and the same `tour.json`.
///
/// - `path`: the keyframes, a (K, 2) or (K, 3) array of numbers in the cloud's coordinates
///   (K >= 2). Rows (x, y) walk `height` above the ground, as a CSV path of `x,y` does;
///   rows (x, y, z) fly through those points, and a NaN z puts that keyframe `height`
///   above the ground under it.
/// - `output`: a folder for frame_000000.png ... and tour.json. With a folder, frames whose
///   file exists are skipped (`overwrite=True` renders them again) and `tour` returns the
///   manifest (tour.json) as a dict. Without one, nothing is written and `tour` returns the
///   frames as a list of Images (each `save` writes the frame file `omnicloud tour`
///   writes); they are all held in memory, so keep `frames` and `width` small, or give a
///   folder for long tours.
/// - `frames`: render this many frames evenly along the path; otherwise frames are spaced by
///   `speed` (metres per second) at `fps` frames per second.
/// - `height`: eye height above the ground where the path gives no z, metres [default 1.7,
///   or 20 point spacings over sparse data]; `heading_smoothing`: metres of path over which
///   the heading follows the averaged tangent (0: the exact tangent).
/// - `yaw`, `pitch`, `roll`: degrees added to every frame's heading (90 looks right of the
///   direction of travel), pitch and roll.
/// - `format`: "png", "jpg" or "exr" frame files; `quality`: JPEG quality.
/// - The image, stereo rig, renderer, colour, radius, filter, units and look options are
///   `render`'s (see `help(omnicloud.render)`), but `projection="map"` (a tour moves a
///   camera).
/// - `progress`: called as `progress(done, total)` with frames rendered.
///
/// The GIL is released while the tour is laid out and rendered. Raises ValueError for a bad
/// argument or path (fewer than two distinct keyframes, a keyframe outside the cloud's
/// bounds or with no ground under it), OSError when a file cannot be written, RuntimeError
/// when no GPU adapter is found for "raster".
#[pyfunction]
#[pyo3(signature = (
    cloud, path, *, output=None, frames=None, speed=1.4, fps=30.0, height=None,
    heading_smoothing=2.0, yaw=0.0, pitch=0.0, roll=0.0, format="png", quality=90,
    overwrite=false, width=3840, stereo="none", projection="equirect", ipd=0.064,
    pole_merge="comfortable", pole_merge_north=None, pole_merge_south=None,
    ods_offset="exact", renderer="raster", color="auto", shading="unlit", radius=None,
    classes=None, drop_classes=None, returns="all", crop=None, max_distance=None,
    units="metres", edl=None, edl_radius=1.4, supersample=1, background=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub fn tour(
    py: Python<'_>,
    cloud: &PointCloud,
    path: &Bound<'_, PyAny>,
    output: Option<PathBuf>,
    frames: Option<usize>,
    speed: f64,
    fps: f64,
    height: Option<f64>,
    heading_smoothing: f64,
    yaw: f64,
    pitch: f64,
    roll: f64,
    format: &str,
    quality: u8,
    overwrite: bool,
    width: u32,
    stereo: &str,
    projection: &str,
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
) -> PyResult<Py<PyAny>> {
    let args = ViewArgs {
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
    };
    let view = args.parse(cloud)?;
    let keyframes = keyframes(py, path)?;
    let Some(image) = view.image else {
        return Err(value_error(
            "a tour looks around from each pose: projection \"map\" has no camera to move",
        ));
    };
    view.look.render_image(&image).map_err(value_error)?;
    let format: FrameFormat = value_enum("format", format)?;
    if format == FrameFormat::Jpg && view.look.background == Some(Background::Transparent) {
        return Err(value_error(
            "a JPEG has no alpha, so its background cannot be transparent: use format=\"png\" \
             or \"exr\", or give a colour (background=\"black\")",
        ));
    }
    if !(1..=100).contains(&quality) {
        return Err(value_error(format!(
            "quality: {quality} is not within 1..=100"
        )));
    }
    let positive = |what: &str, v: f64| {
        if finite(what, v)? > 0.0 {
            Ok(v)
        } else {
            Err(value_error(format!("{what}: {v} must be greater than 0")))
        }
    };
    let sampling = match frames {
        Some(0) => return Err(value_error("frames: a tour needs at least one frame")),
        Some(n) => Sampling::Frames(n),
        None => Sampling::Speed {
            speed: view.scale.length(positive("speed", speed)?),
            fps: positive("fps", fps)?,
        },
    };
    let fps = positive("fps", fps)?;
    if finite("heading_smoothing", heading_smoothing)? < 0.0 {
        return Err(value_error(format!(
            "heading_smoothing: {heading_smoothing} must not be negative"
        )));
    }
    let height = height
        .map(|h| finite("height", h).map(|h| view.scale.height(h)))
        .transpose()?;
    let scale = &view.scale;
    let request = TourRequest {
        scan: TourScan::Points {
            scene: Arc::clone(&cloud.scene),
            info: cloud.info.clone().map(Box::new),
            name: cloud.name.clone(),
        },
        route: Route::Keyframes {
            keyframes,
            name: PATH_NAME.into(),
        },
        prepare: PrepareOptions {
            up: cloud.up,
            radius: view.radius,
            filter: view.filter,
            lod: Lod::Off,
            ..PrepareOptions::default()
        },
        height: EyeHeight::new(height, scale.height(1.0)),
        sampling,
        heading_window: scale.length(heading_smoothing),
        yaw_offset: finite("yaw", yaw)?,
        pitch_offset: finite("pitch", pitch)?,
        roll_offset: finite("roll", roll)?,
    };
    let mut render_command = vec![
        "omnicloud".to_string(),
        "render".to_string(),
        cloud.name.display().to_string(),
        format!("--quality={quality}"),
    ];
    render_command.extend(args.render_options(cloud)?);
    render_command.push("--lod=off".into());
    let options = RunOptions {
        settings: view.settings,
        dir: output.clone().unwrap_or_default(),
        format,
        jpeg_quality: quality,
        fps,
        overwrite,
        render_command,
        look: view.look,
        metres_per_unit: scale.metres_per_unit,
    };
    let kind = view.renderer;
    match output {
        Some(dir) => {
            let manifest = with_progress(py, progress, |pb| -> PyResult<_> {
                let planned = omnicloud::tour::plan(&request, pb).map_err(tour_error)?;
                std::fs::create_dir_all(&dir).map_err(|e| {
                    PyOSError::new_err(format!("creating the output folder {}: {e}", dir.display()))
                })?;
                let manifest = omnicloud::tour::run::manifest(&request, &planned, &options);
                manifest
                    .write(&dir)
                    .map_err(|e| PyOSError::new_err(e.to_string()))?;
                let (todo, _) =
                    omnicloud::tour::run::frames_to_render(&options, 0..planned.poses.len());
                if !todo.is_empty() {
                    let mut resident = Resident::new(&planned.scene, kind, &options.settings)
                        .map_err(render_error)?;
                    omnicloud::tour::render_frames(
                        &planned,
                        &mut resident,
                        &options,
                        &todo,
                        pb,
                        |_, _, _| {},
                    )
                    .map_err(run_error)?;
                }
                Ok(manifest)
            })??;
            let json = serde_json::to_string(&manifest).map_err(value_error)?;
            Ok(py.import("json")?.call_method1("loads", (json,))?.unbind())
        }
        None => {
            let images = with_progress(py, progress, |pb| -> PyResult<_> {
                let planned = omnicloud::tour::plan(&request, pb).map_err(tour_error)?;
                let mut resident =
                    Resident::new(&planned.scene, kind, &options.settings).map_err(render_error)?;
                pb.set_position(0);
                pb.set_length(planned.poses.len() as u64);
                let mut images = Vec::with_capacity(planned.poses.len());
                for (index, pose) in planned.poses.iter().enumerate() {
                    let rendered = render_frame(&planned, &mut resident, &options, index)
                        .map_err(run_error)?;
                    images.push(Image::new(
                        rendered,
                        options.output_options(&planned, index),
                        Some(DVec3::from_array(pose.position)),
                    ));
                    pb.inc(1);
                }
                Ok(images)
            })??;
            Ok(images.into_pyobject(py)?.into_any().unbind())
        }
    }
}

/// The rows of `path` as keyframes, each error a ValueError naming the row.
fn keyframes(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Vec<Keyframe>> {
    let np = py.import("numpy")?;
    let array = np.call_method1("asarray", (path,))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") || shape.len() != 2 || !(2..=3).contains(&shape[1])
    {
        return Err(value_error(format!(
            "path must be a (K, 2) or (K, 3) array of numbers (x, y[, z] per keyframe), got an \
             array of {} with shape {}",
            array.getattr("dtype")?,
            array.getattr("shape")?
        )));
    }
    let array = array.call_method1("astype", ("float64",))?;
    let rows: PyReadonlyArray2<'_, f64> = array.extract()?;
    let rows = rows.as_array();
    if rows.nrows() < 2 {
        return Err(value_error(format!(
            "path needs at least two keyframes, got {}",
            rows.nrows()
        )));
    }
    rows.rows()
        .into_iter()
        .enumerate()
        .map(|(i, row)| {
            let (x, y) = (row[0], row[1]);
            if !(x.is_finite() && y.is_finite()) {
                return Err(value_error(format!(
                    "path row {i}: x and y must be finite, got ({x}, {y})"
                )));
            }
            let z = match row.get(2) {
                Some(z) if z.is_nan() => None,
                Some(z) if !z.is_finite() => {
                    return Err(value_error(format!(
                        "path row {i}: z must be finite (or NaN for the ground), got {z}"
                    )));
                }
                z => z.copied(),
            };
            Ok(Keyframe {
                x,
                y,
                z,
                yaw: None,
                pitch: 0.0,
                roll: 0.0,
                at: format!("row {i}"),
            })
        })
        .collect()
}

/// A tour that could not be laid out: preparing the points as `render` raises it, the
/// keyframes on this cloud a bad argument.
fn tour_error(e: TourError) -> PyErr {
    match e {
        TourError::Prepare(e) => prepare_error(e),
        TourError::Path(e) => PyOSError::new_err(e.to_string()),
        e => value_error(e),
    }
}

/// A frame that could not be rendered or written.
fn run_error(e: RunError) -> PyErr {
    match e {
        RunError::Render { source, .. } => render_error(source),
        RunError::Output(e) => output_error(e),
        RunError::Look(e) => value_error(e),
    }
}
