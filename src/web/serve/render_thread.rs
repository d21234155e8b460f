//! The render thread: it owns the GPU rasterizer (created on it, so nothing GPU-side crosses
//! threads) and the scan's points uploaded for the current camera. HTTP workers hand it
//! requests through a [`LatestQueue`] and wait for their own answer on a channel.
//!
//! Points live on the GPU relative to the camera (f32 keeps millimetres near the eye), so a
//! new camera position re-uploads them; IPD and pole-merge changes render the resident
//! upload again.

use std::panic::AssertUnwindSafe;
use std::sync::Arc;
use std::sync::mpsc::{Sender, channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};
use indicatif::ProgressBar;

use crate::projection::{Camera, Image, OdsOffset, Stereo};
use crate::raster::{Rasterizer, UploadedScene};
use crate::render::{Imposter, Proxy, RenderSettings};

use super::ServeError;
use super::queue::LatestQueue;
use super::request::RenderRequest;
use super::scan::{LiveScan, png_bytes};

/// A finished render.
#[derive(Debug, Clone)]
pub struct LiveFrame {
    /// The ODS pair as a top-bottom PNG (left eye on top).
    pub png: Vec<u8>,
    /// The camera it was rendered from, file coordinates.
    pub camera: DVec3,
    /// The request's sequence number.
    pub seq: u64,
    /// Time spent uploading (new camera positions only), rendering and encoding.
    pub elapsed: Duration,
}

/// Why a request got no frame.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderFailure {
    /// A newer request of the same client replaced it before it started.
    #[error("superseded by a newer render request")]
    Superseded,
    /// No ground near the asked position to stand the camera on.
    #[error("x={x}, y={y}: no points near enough to find the ground there")]
    NoGround {
        /// File X.
        x: f64,
        /// File Y.
        y: f64,
    },
    /// The renderer failed; the message says how.
    #[error("the render failed: {0}")]
    Failed(String),
    /// The render thread has stopped.
    #[error("the renderer has stopped")]
    Stopped,
}

struct Job {
    request: RenderRequest,
    reply: Sender<Result<LiveFrame, RenderFailure>>,
}

/// The render thread's handle; dropping it stops the thread once its render is done.
pub struct RenderThread {
    queue: Arc<LatestQueue<String, Job>>,
    thread: Option<JoinHandle<()>>,
    adapter: String,
    max_width: u32,
}

impl RenderThread {
    /// Starts the thread and its rasterizer; returns once the rasterizer is ready. A served
    /// width beyond [`max_width`](Self::max_width) is not refused here: its renders fail.
    ///
    /// # Errors
    /// The rasterizer could not start (no adapter, a refused device).
    pub fn start(scan: Arc<LiveScan>) -> Result<Self, ServeError> {
        let queue: Arc<LatestQueue<String, Job>> = Arc::new(LatestQueue::new());
        let (ready_tx, ready_rx) = channel();
        let thread = {
            let queue = queue.clone();
            std::thread::Builder::new()
                .name("omnicloud-render".into())
                .spawn(move || {
                    let rasterizer = match Rasterizer::new() {
                        Ok(r) => r,
                        Err(e) => {
                            let _ = ready_tx.send(Err(ServeError::Raster(e)));
                            return;
                        }
                    };
                    let _ = ready_tx.send(Ok((
                        rasterizer.adapter_name().to_owned(),
                        rasterizer.max_image_width(),
                    )));
                    let mut renderer = Renderer {
                        rasterizer,
                        scan,
                        resident: None,
                    };
                    while let Some(job) = queue.take() {
                        let answer = renderer.answer(&job.request);
                        // The asker may have given up (its client went away): no matter.
                        let _ = job.reply.send(answer);
                    }
                })
                .map_err(ServeError::Thread)?
        };
        let mut started = RenderThread {
            queue,
            thread: Some(thread),
            adapter: String::new(),
            max_width: 0,
        };
        match ready_rx.recv() {
            Ok(Ok((adapter, max_width))) => {
                started.adapter = adapter;
                started.max_width = max_width;
                Ok(started)
            }
            Ok(Err(e)) => Err(e),
            Err(_) => Err(ServeError::Thread(std::io::Error::other(
                "the render thread stopped while creating the rasterizer",
            ))),
        }
    }

    /// The GPU adapter's name and backend.
    pub fn adapter(&self) -> &str {
        &self.adapter
    }

    /// Widest panorama (pixels per eye) the adapter can render.
    pub fn max_width(&self) -> u32 {
        self.max_width
    }

    /// Queues `request` in place of its client's request still waiting, and waits for its
    /// frame. Whichever of the two is older is answered [`RenderFailure::Superseded`].
    pub fn render(&self, request: RenderRequest) -> Result<LiveFrame, RenderFailure> {
        let (reply, answer) = channel();
        let (client, seq) = (request.client.clone(), request.seq);
        if let Some(replaced) = self.queue.push(client, seq, Job { request, reply }) {
            let _ = replaced.reply.send(Err(RenderFailure::Superseded));
        }
        answer.recv().unwrap_or(Err(RenderFailure::Stopped))
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        for job in self.queue.close() {
            let _ = job.reply.send(Err(RenderFailure::Stopped));
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What the render thread holds between requests.
struct Renderer {
    rasterizer: Rasterizer,
    scan: Arc<LiveScan>,
    /// The points uploaded for a camera (local frame) and the XY it was asked for.
    resident: Option<Resident>,
}

struct Resident {
    xy: DVec2,
    camera: DVec3,
    uploaded: UploadedScene,
}

impl Renderer {
    /// Renders `request`; a panic in the renderer becomes a failure, and the next request
    /// uploads afresh.
    fn answer(&mut self, request: &RenderRequest) -> Result<LiveFrame, RenderFailure> {
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| self.render(request)));
        let answer = match result {
            Ok(answer) => answer,
            Err(panic) => Err(RenderFailure::Failed(
                panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                    .unwrap_or_else(|| "the renderer panicked".into()),
            )),
        };
        if matches!(answer, Err(RenderFailure::Failed(_))) {
            self.resident = None;
        }
        answer
    }

    fn render(&mut self, request: &RenderRequest) -> Result<LiveFrame, RenderFailure> {
        let started = Instant::now();
        let scan = &self.scan;
        let failed = |e: &dyn std::fmt::Display| RenderFailure::Failed(e.to_string());
        // The ground search reads every point: a slider moved at one position reuses it.
        let camera = match &self.resident {
            Some(r) if r.xy == request.xy => r.camera,
            _ => {
                let world = scan.camera_at(request.xy).ok_or(RenderFailure::NoGround {
                    x: request.xy.x,
                    y: request.xy.y,
                })?;
                world - scan.scene.origin
            }
        };
        let settings = live_settings(scan, camera, request);
        if self.resident.as_ref().is_none_or(|r| r.camera != camera) {
            // Free the old upload before the new one claims GPU memory.
            self.resident = None;
            let uploaded = self
                .rasterizer
                .upload(&scan.scene, &settings)
                .map_err(|e| failed(&e))?;
            self.resident = Some(Resident {
                xy: request.xy,
                camera,
                uploaded,
            });
        }
        let resident = self.resident.as_ref().expect("uploaded above");
        let (rendered, _, _) = self
            .rasterizer
            .render_uploaded(&resident.uploaded, &settings, &ProgressBar::hidden())
            .map_err(|e| failed(&e))?;
        let png = png_bytes(&rendered.top_bottom()).map_err(|e| failed(&e))?;
        self.rasterizer.recycle(rendered);
        Ok(LiveFrame {
            png,
            camera: scan.scene.origin + camera,
            seq: request.seq,
            elapsed: started.elapsed(),
        })
    }
}

/// The settings a live render uses: an ODS pair at the served width from `camera` (local
/// frame), heading north, with the request's IPD (metres, in the scan's unit) and pole merging and the scan's colour and
/// shading; proxy and imposter as `omnicloud render` defaults them.
pub fn live_settings(scan: &LiveScan, camera: DVec3, request: &RenderRequest) -> RenderSettings {
    RenderSettings {
        image: Image::equirect(scan.options.width),
        camera: Camera::new(camera, 0.0),
        stereo: Stereo::Ods {
            ipd: request.ipd * scan.options.per_metre,
            merging: request.merging,
            offset: OdsOffset::Exact,
        },
        color: scan.options.color,
        shading: scan.options.shading,
        proxy: Proxy::default(),
        imposter: Imposter::default(),
        depth_map: None,
    }
}
