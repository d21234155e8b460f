//! Out-of-core rendering: a point file streamed in chunks through a renderer that accumulates
//! into one image, so resident memory follows the chunk size, not the point count.
//!
//! [`plan`] first surveys the file (evenly spaced blocks of it, or all of it when small) and
//! decides what needs the whole cloud: the camera, the radius, the colour ranges and the
//! 16-bit colour scale. [`stream_file`] then draws the planned cloud: the survey's copy when
//! it read every point, else chunks decoded by a worker thread while the caller's
//! [`ChunkSink`] draws the previous one; a bounded channel of depth [`CHANNEL_DEPTH`] keeps at
//! most that many decoded chunks waiting.
//!
//! Points with NaN/inf or absurd coordinates are dropped and counted, as `load_scene` does.

mod error;
pub mod node_cache;
pub mod plan;

pub use error::{SinkError, StreamError};
pub use plan::{PlanOptions, SURVEY_POINTS, StreamPlan, plan, plan_files};

use crate::io::{self, LoadError, PointChunk, Up};
use crate::prepare::filter::Stage;
use crate::prepare::{FilterCounts, FilterError, PrepareError, RadiusRule};
use crate::scene::{Attributes, Radii, Scene};
use glam::DVec3;
use indicatif::ProgressBar;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

/// Decoded chunks allowed to wait for the renderer.
pub const CHANNEL_DEPTH: usize = 2;

/// Points per chunk by default: 512 Ki points hold ~190 MB while streaming (see
/// [`crate::memory::RASTER_BYTES_PER_CHUNK_POINT`]) and fill the GPU well.
pub const DEFAULT_CHUNK_POINTS: usize = 1 << 19;

/// Receives the chunks, as scenes in the camera's frame (origin = camera world position).
pub trait ChunkSink {
    /// Draws (or otherwise consumes) one chunk.
    ///
    /// # Errors
    /// Whatever the renderer reports (as [`StreamError::Sink`], see [`StreamError::sink`]);
    /// streaming stops.
    fn draw(&mut self, chunk: &Scene) -> Result<(), StreamError>;
}

/// What a stream did.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamReport {
    /// Points the header declares.
    pub declared: u64,
    /// Points read.
    pub read: u64,
    /// Points drawn (read minus dropped).
    pub drawn: u64,
    /// Points dropped for NaN/inf/absurd coordinates.
    pub dropped: u64,
    /// Points each filter removed (not counted in `drawn` nor `dropped`).
    pub filtered: FilterCounts,
    /// Camera world position used.
    pub camera: DVec3,
    /// Radius used for points without their own.
    pub radius: f32,
    /// Wall time, seconds.
    pub seconds: f64,
}

impl StreamReport {
    /// Points read per second.
    pub fn points_per_second(&self) -> f64 {
        self.read as f64 / self.seconds.max(1e-9)
    }
}

/// A chunk as a scene relative to `origin`, without unusable points; returns it and the
/// number dropped. Points are sized by `rule`: the file's radii when it keeps them and the
/// chunk has them (its `radius` where a file radius is not a positive finite number), radii
/// from the chunk's nearest neighbours when adaptive, else its `radius`.
pub fn chunk_scene(chunk: PointChunk, origin: DVec3, up: Up, rule: &RadiusRule) -> (Scene, u64) {
    let keep: Vec<bool> = chunk
        .positions
        .iter()
        .map(|p| io::usable(up.to_world(*p)))
        .collect();
    let dropped = keep.iter().filter(|k| !**k).count() as u64;
    let file_radii = chunk.radius.filter(|_| rule.keep_file_radii);
    let scene = Scene {
        origin,
        // Unusable points are converted too, then selected away below.
        positions: chunk
            .positions
            .iter()
            .map(|p| (up.to_world(*p) - origin).as_vec3())
            .collect(),
        radii: Radii::from_file(file_radii, rule.radius),
        attributes: Attributes {
            rgb: chunk.rgb,
            intensity: chunk.intensity,
            classification: chunk.classification,
            returns: chunk.returns,
        },
    };
    let mut scene = if dropped == 0 {
        scene
    } else {
        scene.select(&keep)
    };
    if let Some(radii) = rule
        .adaptive
        .and_then(|k| crate::prepare::radius::adaptive_radii(&scene.positions, k))
    {
        scene.radii = Radii::PerPoint(radii);
    }
    (scene, dropped)
}

/// Streams the planned file through `sink` in chunks of `chunk_points`: `plan.whole` when the
/// survey read every point (the file is not read again), else the file decoded on a worker
/// thread with the plan's colour scale, each chunk relative to `plan.camera` and sized by the
/// plan's radius rule. `progress` counts points read of the declared total.
///
/// # Errors
/// A [`LoadError`] from reading, the sink's error, or a failed decoding thread.
pub fn stream_file(
    plan: &StreamPlan,
    chunk_points: usize,
    sink: &mut dyn ChunkSink,
    progress: &ProgressBar,
) -> Result<StreamReport, StreamError> {
    let started = Instant::now();
    let chunk_points = chunk_points.max(1);
    let mut report = StreamReport {
        declared: plan.declared,
        read: 0,
        drawn: 0,
        dropped: 0,
        filtered: FilterCounts::default(),
        camera: plan.camera,
        radius: plan.radii.radius,
        seconds: 0.0,
    };
    match &plan.whole {
        Some(whole) => draw_whole(plan, whole, chunk_points, sink, progress, &mut report)?,
        None => draw_decoded(plan, chunk_points, sink, progress, &mut report)?,
    }
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

/// Draws the survey's copy of the cloud in chunks.
fn draw_whole(
    plan: &StreamPlan,
    whole: &Scene,
    chunk_points: usize,
    sink: &mut dyn ChunkSink,
    progress: &ProgressBar,
    report: &mut StreamReport,
) -> Result<(), StreamError> {
    progress.set_length(plan.surveyed);
    progress.inc(plan.dropped);
    report.read = plan.surveyed;
    report.dropped = plan.dropped;
    report.filtered = plan.filtered;
    for start in (0..whole.len()).step_by(chunk_points) {
        let end = (start + chunk_points).min(whole.len());
        let chunk = whole.range(start..end);
        sink.draw(&chunk)?;
        report.drawn += chunk.len() as u64;
        progress.inc(chunk.len() as u64);
    }
    Ok(())
}

/// Decodes the file on a worker thread and draws each chunk as it arrives.
fn draw_decoded(
    plan: &StreamPlan,
    chunk_points: usize,
    sink: &mut dyn ChunkSink,
    progress: &ProgressBar,
    report: &mut StreamReport,
) -> Result<(), StreamError> {
    progress.set_length(plan.declared);
    report.filtered = plan.skipped;
    let worker_failed = |detail: String| StreamError::Worker {
        path: plan.path.clone(),
        detail,
    };
    // The las reader is not Send: the worker opens its own.
    let (tx, rx) = sync_channel::<Result<PointChunk, LoadError>>(CHANNEL_DEPTH);
    let worker = std::thread::Builder::new()
        .name("omnicloud-decode".into())
        .spawn({
            let (paths, scale) = (plan.paths.clone(), plan.color_scale);
            move || {
                for path in paths {
                    let reader = match io::open(&path) {
                        Ok(r) => r,
                        Err(e) => {
                            let _ = tx.send(Err(e));
                            return;
                        }
                    };
                    for chunk in reader.chunks_with_scale(chunk_points, scale) {
                        let failed = chunk.is_err();
                        if tx.send(chunk).is_err() || failed {
                            return; // the renderer stopped, or this file failed
                        }
                    }
                }
            }
        })
        .map_err(|e| worker_failed(e.to_string()))?;
    for chunk in rx {
        let chunk = chunk?;
        report.read += chunk.len() as u64;
        progress.inc(chunk.len() as u64);
        let (scene, dropped) = plan.chunk_scene(chunk);
        report.dropped += dropped;
        let (scene, filtered) = plan.filter.apply(scene, plan.up, Stage::All);
        report.filtered += filtered;
        report.drawn += scene.len() as u64;
        if !scene.is_empty() {
            sink.draw(&scene)?;
        }
    }
    worker
        .join()
        .map_err(|_| worker_failed("it panicked".into()))?;
    if report.drawn == 0 && report.filtered.total() > 0 {
        return Err(PrepareError::from(FilterError::NothingLeft {
            counts: report.filtered,
        })
        .into());
    }
    if report.drawn == 0 {
        return Err(if report.read == 0 {
            LoadError::NoPoints {
                path: plan.path.clone(),
            }
        } else {
            LoadError::NoFinitePoints {
                path: plan.path.clone(),
                dropped: report.dropped,
            }
        }
        .into());
    }
    Ok(())
}
