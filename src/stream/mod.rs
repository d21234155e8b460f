//! Out-of-core rendering: a point file streamed in chunks through a renderer that accumulates
//! into one image, so resident memory follows the chunk size, not the point count.
//!
//! A worker thread decodes chunks while the caller's [`ChunkSink`] draws the previous one;
//! a bounded channel of depth [`CHANNEL_DEPTH`] keeps at most that many decoded chunks
//! waiting. What needs the whole cloud is decided from the first chunk:
//! - the camera (when not given): [`crate::placement::auto_camera_position`] on the first
//!   chunk — LAS files are usually stored in spatial order, so this is the ground at the
//!   centre of the first patch, not of the whole scan; pass `--camera` for a chosen view;
//! - `--radius auto`: half the median spacing of the first chunk (a local patch gives the
//!   local spacing, which is what the radius is for).
//!
//! Points with NaN/inf or absurd coordinates are dropped and counted, as `load_scene` does.

use crate::io::{self, LoadError, PointChunk, Up};
use crate::scene::{Attributes, Radii, Scene};
use glam::DVec3;
use indicatif::ProgressBar;
use std::path::Path;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

/// Decoded chunks allowed to wait for the renderer.
pub const CHANNEL_DEPTH: usize = 2;

/// Points per chunk by default: 1 M points is ~40 MB decoded, ~16 MB on the GPU.
pub const DEFAULT_CHUNK_POINTS: usize = 1 << 20;

/// Receives the chunks, as scenes in the camera's frame (origin = camera world position).
pub trait ChunkSink {
    /// Draws (or otherwise consumes) one chunk.
    ///
    /// # Errors
    /// Whatever the renderer reports; streaming stops.
    fn draw(&mut self, chunk: &Scene) -> anyhow::Result<()>;
}

/// How to stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreamOptions {
    /// Points per chunk.
    pub chunk_points: usize,
    /// Camera world position; `None` = placed on the first chunk (see the module docs).
    pub camera: Option<DVec3>,
    /// Sphere radius; `None` = auto from the first chunk (files with per-point radii keep them).
    pub radius: Option<f32>,
    /// Up axis of the file.
    pub up: Up,
}

impl Default for StreamOptions {
    fn default() -> Self {
        StreamOptions {
            chunk_points: DEFAULT_CHUNK_POINTS,
            camera: None,
            radius: None,
            up: Up::Z,
        }
    }
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
/// number dropped.
pub fn chunk_scene(chunk: PointChunk, origin: DVec3, up: Up, radius: f32) -> (Scene, u64) {
    let keep: Vec<bool> = chunk
        .positions
        .iter()
        .map(|p| {
            let w = up.to_world(*p);
            w.is_finite() && w.abs().max_element() <= 1e30
        })
        .collect();
    let dropped = keep.iter().filter(|k| !**k).count() as u64;
    fn pick<T: Copy>(v: Option<Vec<T>>, keep: &[bool]) -> Option<Vec<T>> {
        v.map(|v| {
            v.into_iter()
                .zip(keep)
                .filter(|(_, k)| **k)
                .map(|(x, _)| x)
                .collect()
        })
    }
    let positions = chunk
        .positions
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| (up.to_world(*p) - origin).as_vec3())
        .collect();
    let radii = match pick(chunk.radius, &keep) {
        Some(mut r) => {
            for x in &mut r {
                if !(x.is_finite() && *x > 0.0) {
                    *x = radius;
                }
            }
            Radii::PerPoint(r)
        }
        None => Radii::Uniform(radius),
    };
    let scene = Scene {
        origin,
        positions,
        radii,
        attributes: Attributes {
            rgb: pick(chunk.rgb, &keep),
            intensity: pick(chunk.intensity, &keep),
            classification: pick(chunk.classification, &keep),
        },
    };
    (scene, dropped)
}

/// Streams `path` through `sink` (see the module docs); `progress` counts points read of the
/// declared total.
///
/// # Errors
/// A [`LoadError`] from reading, an empty first chunk, or the sink's error.
pub fn stream_file(
    path: &Path,
    options: &StreamOptions,
    sink: &mut dyn ChunkSink,
    progress: &ProgressBar,
) -> anyhow::Result<StreamReport> {
    let started = Instant::now();
    // The las reader is not Send: the header is read here, the points by a second reader
    // opened on the worker thread.
    let declared = io::open(path)?.info().point_count;
    progress.set_length(declared);
    let chunk_points = options.chunk_points.max(1);
    let (tx, rx) = sync_channel::<Result<PointChunk, LoadError>>(CHANNEL_DEPTH);
    let worker = std::thread::Builder::new()
        .name("omnicloud-decode".into())
        .spawn({
            let path = path.to_path_buf();
            move || {
                let reader = match io::open(&path) {
                    Ok(r) => r,
                    Err(e) => {
                        let _ = tx.send(Err(e));
                        return;
                    }
                };
                for chunk in reader.chunks(chunk_points) {
                    if tx.send(chunk).is_err() {
                        break; // the renderer stopped
                    }
                }
            }
        })?;

    let mut report = StreamReport {
        declared,
        read: 0,
        drawn: 0,
        dropped: 0,
        camera: DVec3::ZERO,
        radius: 0.0,
        seconds: 0.0,
    };
    let mut frame: Option<(DVec3, f32)> = None;
    for chunk in rx {
        let chunk = chunk?;
        report.read += chunk.len() as u64;
        progress.inc(chunk.len() as u64);
        let (camera, radius) = match frame {
            Some(f) => f,
            None => {
                let f = first_chunk_frame(path, &chunk, options)?;
                frame = Some(f);
                f
            }
        };
        let (scene, dropped) = chunk_scene(chunk, camera, options.up, radius);
        report.dropped += dropped;
        report.drawn += scene.len() as u64;
        if !scene.is_empty() {
            sink.draw(&scene)?;
        }
    }
    let _ = worker.join();
    let (camera, radius) = frame.ok_or_else(|| LoadError::NoPoints {
        path: path.to_path_buf(),
    })?;
    report.camera = camera;
    report.radius = radius;
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

/// Camera and radius decided on the first chunk.
fn first_chunk_frame(
    path: &Path,
    chunk: &PointChunk,
    options: &StreamOptions,
) -> anyhow::Result<(DVec3, f32)> {
    let probe_origin = chunk
        .positions
        .iter()
        .map(|p| options.up.to_world(*p))
        .find(|p| p.is_finite())
        .ok_or_else(|| LoadError::NoFinitePoints {
            path: path.to_path_buf(),
            dropped: chunk.len() as u64,
        })?;
    let (scene, _) = chunk_scene(chunk.clone(), probe_origin, options.up, 0.0);
    let camera = match options.camera {
        Some(c) => c,
        None => {
            probe_origin
                + crate::placement::auto_camera_position(&scene).ok_or_else(|| {
                    anyhow::anyhow!("{}: could not place the camera", path.display())
                })?
        }
    };
    let radius = options
        .radius
        .unwrap_or_else(|| crate::radius::auto_radius(&scene));
    Ok((camera, radius))
}
