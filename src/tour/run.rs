//! Rendering a tour's frames: one file per frame, written atomically by the same writers and
//! with the same metadata as `omnicloud render`; frames whose file exists are skipped, so a
//! killed job restarts where it stopped.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::DVec3;
use indicatif::ProgressBar;

use super::manifest::{FrameRecord, MANIFEST_VERSION, StereoLayout, TourManifest, shell_line};
use super::{Tour, TourRequest};
use crate::Rendered;
use crate::output::{self, Layout, OutputError, OutputOptions};
use crate::projection::Camera;
use crate::render::{Look, LookError, RenderSettings};
use crate::renderer::{DrawsFrames, ResidentError};

/// The frame files' format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum FrameFormat {
    /// 8-bit sRGB PNG with coverage as alpha.
    #[default]
    Png,
    /// 8-bit sRGB JPEG.
    Jpg,
    /// Linear float OpenEXR with depth.
    Exr,
}

impl FrameFormat {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            FrameFormat::Png => "png",
            FrameFormat::Jpg => "jpg",
            FrameFormat::Exr => "exr",
        }
    }

    /// `frame_000042.png` and so on.
    pub fn file_name(self, index: usize) -> String {
        crate::frames::frame_file_name(index, self.extension())
    }
}

/// How the frames are rendered and written.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Settings of every frame; the camera is replaced by each frame's.
    pub settings: RenderSettings,
    /// The output folder.
    pub dir: PathBuf,
    /// File format.
    pub format: FrameFormat,
    /// JPEG quality.
    pub jpeg_quality: u8,
    /// Playback frames per second (recorded in the manifest).
    pub fps: f64,
    /// Re-render frames whose file exists.
    pub overwrite: bool,
    /// `omnicloud render` and every option of the frames' render settings (scan included;
    /// without `--origin`, `--camera`, `--yaw` and `-o`, which each frame adds).
    pub render_command: Vec<String>,
    /// Passes on each rendered frame (eye-dome lighting, supersampling, background);
    /// `settings.image` is the output size, the renderer draws the look's render size.
    pub look: Look,
    /// Metres per unit of the scan's coordinates (recorded in the manifest and each frame's
    /// description); `None` when the scan declares no unit of length.
    pub metres_per_unit: Option<f64>,
}

impl RunOptions {
    /// Each frame's file.
    pub fn frame_path(&self, index: usize) -> PathBuf {
        self.dir.join(self.format.file_name(index))
    }

    /// The settings of frame `pose` of `tour` (camera in the tour's local frame).
    pub fn frame_settings(&self, tour: &Tour, index: usize) -> RenderSettings {
        let pose = &tour.poses[index];
        let local = DVec3::from_array(pose.position) - tour.origin;
        RenderSettings {
            camera: Camera::new(local, pose.yaw).with_orientation(pose.pitch, pose.roll),
            ..self.settings
        }
    }

    /// How frame `index` of `tour` is written: top-bottom stereo, its heading and the
    /// scan's unit in the metadata.
    pub fn output_options(&self, tour: &Tour, index: usize) -> OutputOptions {
        OutputOptions {
            layout: Layout::TopBottom,
            jpeg_quality: self.jpeg_quality,
            yaw_degrees: tour.poses[index].yaw,
            projection: self.settings.image.projection,
            metres_per_unit: self.metres_per_unit,
        }
    }
}

/// Frame `index` of `tour` rendered with `resident`, the look applied: the image
/// [`render_frames`] writes (under [`RunOptions::output_options`]).
pub fn render_frame(
    tour: &Tour,
    renderer: &mut dyn DrawsFrames,
    options: &RunOptions,
    index: usize,
) -> Result<Rendered, RunError> {
    let image = options.look.render_image(&options.settings.image)?;
    let settings = options.frame_settings(tour, index);
    let rendered = renderer
        .render_frame(
            &RenderSettings { image, ..settings },
            &ProgressBar::hidden(),
        )
        .map_err(|source| RunError::Render { index, source })?;
    Ok(options.look.finish(rendered))
}

/// What [`render_frames`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunReport {
    /// Frames rendered, in order.
    pub rendered: Vec<usize>,
    /// Frames skipped because their file existed.
    pub skipped: Vec<usize>,
    /// Time spent rendering and writing the rendered frames.
    pub busy: Duration,
}

impl RunReport {
    /// Rendered frames per second of rendering and writing.
    pub fn sustained_fps(&self) -> f64 {
        self.rendered.len() as f64 / self.busy.as_secs_f64().max(1e-9)
    }
}

/// Why frames could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The renderer failed.
    #[error("frame {index}: {source}")]
    Render {
        /// The frame.
        index: usize,
        /// The cause.
        source: ResidentError,
    },
    /// Writing a file failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The look cannot be rendered at this size.
    #[error(transparent)]
    Look(#[from] LookError),
}

/// The manifest of `tour` rendered under `options` (the same for every shard).
pub fn manifest(request: &TourRequest, tour: &Tour, options: &RunOptions) -> TourManifest {
    let image = options.settings.image;
    let eyes = options.settings.views().len() as u32;
    let o = tour.origin;
    let frames = tour
        .poses
        .iter()
        .enumerate()
        .map(|(index, pose)| {
            let [x, y, z] = pose.position;
            let mut argv = options.render_command.clone();
            argv.extend([
                format!("--origin={},{},{}", o.x, o.y, o.z),
                format!("--camera={x},{y},{z}"),
                format!("--yaw={}", pose.yaw),
                format!("--pitch={}", pose.pitch),
                format!("--roll={}", pose.roll),
                "-o".to_string(),
                options.frame_path(index).display().to_string(),
            ]);
            FrameRecord {
                index,
                file: options.format.file_name(index),
                pose: *pose,
                command: shell_line(&argv),
            }
        })
        .collect();
    TourManifest {
        version: MANIFEST_VERSION,
        scan: request.scan.name().display().to_string(),
        path: request.route.to_string(),
        fps: options.fps,
        speed: match request.sampling {
            super::Sampling::Speed { speed, .. } => Some(speed),
            super::Sampling::Frames(_) => None,
        },
        length: tour.length,
        metres_per_unit: options.metres_per_unit,
        width: image.width,
        height: image.height * eyes,
        stereo_layout: if eyes == 2 {
            StereoLayout::TopBottom
        } else {
            StereoLayout::Mono
        },
        format: options.format.extension().to_string(),
        origin: o.to_array(),
        render_options: options.render_command.iter().skip(2).cloned().collect(),
        frames,
        stations: tour.stations.clone(),
    }
}

/// The frames of `range` whose file is missing (all of them with `overwrite`).
pub fn frames_to_render(options: &RunOptions, range: Range<usize>) -> (Vec<usize>, Vec<usize>) {
    range.partition(|&i| options.overwrite || !options.frame_path(i).exists())
}

/// How old a stale temporary `tour.json` must be before it is removed: every shard of a tour
/// writes the manifest when it starts (in milliseconds), so a younger one may be another
/// shard's write in progress.
const STALE_MANIFEST_AGE: Duration = Duration::from_secs(60);

/// Removes the temporary files that killed runs (`kill -9`, a node lost) left in the tour's
/// folder: those of the frames `todo`, which no other process renders, and those of
/// `tour.json` older than [`STALE_MANIFEST_AGE`]. Returns how many were removed; a folder
/// that cannot be listed removes none (writing the frames then reports it).
pub fn remove_stale_temps(options: &RunOptions, todo: &[usize]) -> usize {
    let frames: std::collections::HashSet<String> =
        todo.iter().map(|&i| options.format.file_name(i)).collect();
    let Ok(entries) = std::fs::read_dir(&options.dir) else {
        return 0;
    };
    let stale = |entry: &std::fs::DirEntry| {
        let name = entry.file_name();
        let Some(dest) = name.to_str().and_then(output::atomic::staged_for) else {
            return false;
        };
        frames.contains(dest)
            || (dest == crate::frames::MANIFEST_NAME
                && entry
                    .metadata()
                    .and_then(|m| m.modified())
                    .ok()
                    .and_then(|t| t.elapsed().ok())
                    .is_some_and(|age| age >= STALE_MANIFEST_AGE))
    };
    entries
        .flatten()
        .filter(|e| stale(e) && std::fs::remove_file(e.path()).is_ok())
        .count()
}

/// Renders and writes the frames `todo` of `tour` with `renderer` (the scene kept resident, or
/// a level-of-detail node stream); `progress` counts frames and shows the frame rate;
/// `on_frame` hears each frame written.
pub fn render_frames(
    tour: &Tour,
    renderer: &mut dyn DrawsFrames,
    options: &RunOptions,
    todo: &[usize],
    progress: &ProgressBar,
    mut on_frame: impl FnMut(usize, &Path, Duration),
) -> Result<RunReport, RunError> {
    let mut report = RunReport::default();
    progress.set_length(todo.len() as u64);
    for &index in todo {
        let started = Instant::now();
        let rendered = render_frame(tour, renderer, options, index)?;
        let path = options.frame_path(index);
        output::write_image_with(&path, &rendered, &options.output_options(tour, index))?;
        renderer.recycle_frame(rendered);
        let took = started.elapsed();
        report.busy += took;
        report.rendered.push(index);
        on_frame(index, &path, took);
        progress.set_message(format!("{:.2} fps", report.sustained_fps()));
        progress.inc(1);
    }
    Ok(report)
}
