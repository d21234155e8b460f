//! The render thread: it owns the renderer chosen at run time with the scan resident
//! ([`Resident`]), or for a COPC scan its level-of-detail node stream ([`NodeStream`], whose
//! node cache lasts across requests), created on the thread, so nothing GPU-side crosses
//! threads. HTTP workers hand
//! it requests through a [`LatestQueue`] and wait for their own answer on a channel (a PNG);
//! the live stream's connections queue theirs through a [`RenderQueue`] and take the raw
//! pair, to encode it themselves while the next one renders.
//!
//! The rasterizer's points live on the GPU relative to the camera (f32 keeps millimetres near
//! the eye), so a new camera position places them again, keeping the rasterizer; IPD and
//! pole-merge changes render the resident points again.

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};
use indicatif::ProgressBar;

use crate::frame::Frame;
use crate::prepare::PrepareOptions;
use crate::projection::{Camera, Image, OdsOffset, Stereo};
use crate::render::{ColorRule, Imposter, Proxy, RenderSettings, RendererKind};
use crate::renderer::{Anchor, DrawsFrames, NodeRules, NodeStream, Resident};

use super::ServeError;
use super::queue::LatestQueue;
use super::request::RenderRequest;
use super::scan::{LiveScan, ServedLod, png_bytes};

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

/// How far (metres) the live stream's camera may stand from the points' anchor before they
/// are placed again.
const KEEP_ANCHOR_METRES: f64 = 100.0;

/// How many stacked pairs handed back ([`RenderQueue::give_back`]) are kept for the next
/// renders to stack into: one being encoded while the next is stacked.
const KEEP_SPENT: usize = 2;

/// Stacked pairs their askers are done with, for the next renders to stack into: memory
/// already paged in, where a fresh pair costs a page fault and a zero-fill per page.
#[derive(Default)]
struct Spent(Mutex<Vec<Frame>>);

impl Spent {
    fn put(&self, frame: Frame) {
        let mut kept = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        if kept.len() < KEEP_SPENT {
            kept.push(frame);
        }
    }

    /// A frame to stack into: a spent one, else an empty one.
    fn take(&self) -> Frame {
        let mut kept = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        kept.pop().unwrap_or_else(|| Frame::new(0, 0))
    }
}

/// A finished render not yet encoded (the live stream encodes it while the next renders).
#[derive(Debug, Clone)]
pub struct RawFrame {
    /// The ODS pair, top-bottom (left eye on top).
    pub frame: Frame,
    /// The camera it was rendered from, file coordinates.
    pub camera: DVec3,
    /// The request's sequence number.
    pub seq: u64,
    /// Time spent uploading (new camera positions only) and rendering.
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
    /// As many `/api/render` requests as the server lets wait are waiting already.
    #[error("too many renders asked for at once; try again later")]
    Busy,
    /// The render thread has stopped.
    #[error("the renderer has stopped")]
    Stopped,
}

/// Where a job's answer goes: a PNG for `/api/render`, the raw pair for the live stream.
enum Answer {
    Png(Sender<Result<LiveFrame, RenderFailure>>),
    Raw(Sender<Result<RawFrame, RenderFailure>>),
}

impl Answer {
    fn fail(self, why: RenderFailure) {
        // The asker may have given up (its client went away): no matter.
        match self {
            Answer::Png(tx) => drop(tx.send(Err(why))),
            Answer::Raw(tx) => drop(tx.send(Err(why))),
        }
    }
}

struct Job {
    request: RenderRequest,
    /// Panorama width per eye.
    width: u32,
    reply: Answer,
}

/// A handle that queues renders on the render thread from any thread; it outlives nothing:
/// once the [`RenderThread`] is dropped its renders fail [`RenderFailure::Stopped`].
#[derive(Clone)]
pub struct RenderQueue {
    queue: Arc<LatestQueue<String, Job>>,
    spent: Arc<Spent>,
}

impl RenderQueue {
    /// Queues `request` at panorama `width` in place of its client's request still waiting
    /// and returns at once; the raw pair (or why there is none) arrives on the receiver.
    pub fn submit(
        &self,
        request: RenderRequest,
        width: u32,
    ) -> Receiver<Result<RawFrame, RenderFailure>> {
        let (reply, answer) = channel();
        self.push(request, width, Answer::Raw(reply));
        answer
    }

    /// Hands a [`RawFrame`]'s pair back once it is encoded: a later render stacks its pair
    /// into that memory.
    pub fn give_back(&self, frame: Frame) {
        self.spent.put(frame);
    }

    fn push(&self, request: RenderRequest, width: u32, reply: Answer) {
        let (client, seq) = (request.client.clone(), request.seq);
        let job = Job {
            request,
            width,
            reply,
        };
        if let Some(replaced) = self.queue.push(client, seq, job) {
            replaced.reply.fail(RenderFailure::Superseded);
        }
    }
}

/// [`RenderThread::render`] calls waiting at once; more are answered
/// [`RenderFailure::Busy`] at once, so that a storm of render requests neither holds every
/// HTTP worker nor lengthens the queue. Enough for two pages each with a render running and
/// a newer one waiting.
pub const MAX_WAITING_RENDERS: usize = 4;

/// The render thread's handle; dropping it stops the thread once its render is done.
pub struct RenderThread {
    queue: Arc<LatestQueue<String, Job>>,
    spent: Arc<Spent>,
    /// [`render`](Self::render) calls waiting for their frame.
    waiting: AtomicUsize,
    thread: Option<JoinHandle<()>>,
    adapter: String,
    max_width: u32,
    /// The served width, of `/api/render`'s pairs.
    width: u32,
}

impl RenderThread {
    /// Starts the thread with `kind` and the scan resident for the default camera; returns
    /// once it is ready. A served width beyond [`max_width`](Self::max_width) is not refused
    /// here: its renders fail.
    ///
    /// # Errors
    /// The renderer could not start (no adapter, a refused device, a scan it cannot hold).
    pub fn start(scan: Arc<LiveScan>, kind: RendererKind) -> Result<Self, ServeError> {
        let queue: Arc<LatestQueue<String, Job>> = Arc::new(LatestQueue::new());
        let spent = Arc::new(Spent::default());
        let width = scan.options.width;
        let (ready_tx, ready_rx) = channel();
        let thread = {
            let queue = queue.clone();
            let spent = spent.clone();
            std::thread::Builder::new()
                .name("omnicloud-render".into())
                .spawn(move || {
                    let scan: &LiveScan = &scan;
                    let first = RenderRequest::default_at(&scan.limits);
                    let camera = DVec3::from_array(scan.info.camera) - scan.scene.origin;
                    let settings = live_settings(scan, camera, &first);
                    let resident = match drawer(scan, kind, &settings, camera) {
                        Ok(r) => r,
                        Err(e) => {
                            let _ = ready_tx.send(Err(e));
                            return;
                        }
                    };
                    let _ = ready_tx.send(Ok((
                        resident.device().to_owned(),
                        resident.max_image_width().unwrap_or(u32::MAX),
                    )));
                    let mut renderer = Renderer {
                        scan,
                        resident,
                        asked: Some((first.xy, None, camera)),
                        spent: &spent,
                    };
                    while let Some(job) = queue.take() {
                        let keep_anchor = matches!(job.reply, Answer::Raw(_));
                        let raw = renderer.answer(&job.request, job.width, keep_anchor);
                        // The asker may have given up (its client went away): no matter.
                        match job.reply {
                            Answer::Raw(tx) => drop(tx.send(raw)),
                            Answer::Png(tx) => drop(tx.send(raw.and_then(|raw| {
                                let started = Instant::now();
                                let png = png_bytes(&raw.frame)
                                    .map_err(|e| RenderFailure::Failed(e.to_string()))?;
                                spent.put(raw.frame);
                                Ok(LiveFrame {
                                    png,
                                    camera: raw.camera,
                                    seq: raw.seq,
                                    elapsed: raw.elapsed + started.elapsed(),
                                })
                            }))),
                        }
                    }
                })
                .map_err(ServeError::Thread)?
        };
        let mut started = RenderThread {
            queue,
            spent,
            waiting: AtomicUsize::new(0),
            thread: Some(thread),
            adapter: String::new(),
            max_width: 0,
            width,
        };
        match ready_rx.recv() {
            Ok(Ok((adapter, max_width))) => {
                started.adapter = adapter;
                started.max_width = max_width;
                Ok(started)
            }
            Ok(Err(e)) => Err(e),
            Err(_) => Err(ServeError::Thread(std::io::Error::other(
                "the render thread stopped while making the scan resident",
            ))),
        }
    }

    /// The device that renders: the GPU adapter's name and backend, or the CPU.
    pub fn adapter(&self) -> &str {
        &self.adapter
    }

    /// Widest panorama (pixels per eye) the renderer can render.
    pub fn max_width(&self) -> u32 {
        self.max_width
    }

    /// Queues `request` in place of its client's request still waiting, and waits for its
    /// frame. Whichever of the two is older is answered [`RenderFailure::Superseded`]; with
    /// [`MAX_WAITING_RENDERS`] calls waiting already, `request` is answered
    /// [`RenderFailure::Busy`] at once.
    pub fn render(&self, request: RenderRequest) -> Result<LiveFrame, RenderFailure> {
        if self.waiting.fetch_add(1, Ordering::SeqCst) >= MAX_WAITING_RENDERS {
            self.waiting.fetch_sub(1, Ordering::SeqCst);
            return Err(RenderFailure::Busy);
        }
        let (reply, answer) = channel();
        self.queue().push(request, self.width, Answer::Png(reply));
        let frame = answer.recv().unwrap_or(Err(RenderFailure::Stopped));
        self.waiting.fetch_sub(1, Ordering::SeqCst);
        frame
    }

    /// A handle for queueing renders from other threads (the live stream's connections).
    pub fn queue(&self) -> RenderQueue {
        RenderQueue {
            queue: self.queue.clone(),
            spent: self.spent.clone(),
        }
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        for job in self.queue.close() {
            job.reply.fail(RenderFailure::Stopped);
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What the render thread holds between requests.
struct Renderer<'a> {
    scan: &'a LiveScan,
    /// The renderer with the scan resident or its node stream, placed for the last camera.
    resident: Box<dyn DrawsFrames + 'a>,
    /// The XY and height above the ground last asked for and their camera (local frame),
    /// while the resident is placed there.
    asked: Option<(DVec2, Option<f64>, DVec3)>,
    /// Stacked pairs handed back, to stack the next pairs into.
    spent: &'a Spent,
}

impl Renderer<'_> {
    /// Renders `request`; a panic in the renderer becomes a failure, and the next request
    /// uploads afresh.
    fn answer(
        &mut self,
        request: &RenderRequest,
        width: u32,
        keep_anchor: bool,
    ) -> Result<RawFrame, RenderFailure> {
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| {
            self.render(request, width, keep_anchor)
        }));
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
            self.asked = None;
            self.resident.release();
        }
        answer
    }

    /// Renders `request` at `width`; `keep_anchor`: the points stay where they are when the
    /// camera is near them (the live stream), else they are placed at the camera, so that a
    /// render is the library's render there bit for bit (`/api/render`).
    fn render(
        &mut self,
        request: &RenderRequest,
        width: u32,
        keep_anchor: bool,
    ) -> Result<RawFrame, RenderFailure> {
        let started = Instant::now();
        let scan = self.scan;
        let failed = |e: &dyn std::fmt::Display| RenderFailure::Failed(e.to_string());
        // The ground search reads every point: a slider moved at one position reuses it.
        let camera = match (self.asked, request.z) {
            (_, Some(z)) => request.xy.extend(z) - scan.scene.origin,
            (Some((xy, height, camera)), None) if xy == request.xy && height == request.height => {
                camera
            }
            _ => {
                let world = scan.camera_at_height(request.xy, request.height).ok_or(
                    RenderFailure::NoGround {
                        x: request.xy.x,
                        y: request.xy.y,
                    },
                )?;
                world - scan.scene.origin
            }
        };
        let mut settings = live_settings(scan, camera, request);
        settings.image = Image::equirect(width);
        // A walk keeps the points where they are while the camera stays near them: the
        // upload is most of a small frame's time, and f32 offsets stay within a fraction of
        // a millimetre over the distance.
        let near = self.resident.anchor().position().distance(camera)
            < KEEP_ANCHOR_METRES * scan.options.per_metre;
        self.asked = None;
        if !(keep_anchor && near) {
            self.resident
                .place(Anchor::Camera(camera))
                .map_err(|e| failed(&e))?;
        }
        self.asked = Some((request.xy, request.height, camera));
        let rendered = self
            .resident
            .render_frame(&settings, &ProgressBar::hidden())
            .map_err(|e| failed(&e))?;
        let mut frame = self.spent.take();
        rendered.top_bottom_into(&mut frame);
        self.resident.recycle_frame(rendered);
        Ok(RawFrame {
            frame,
            camera: scan.scene.origin + camera,
            seq: request.seq,
            elapsed: started.elapsed(),
        })
    }
}

/// The scan's renderer on this thread, placed at `camera` (local frame) under `settings`:
/// its level-of-detail node stream when it has one and `kind` is the rasterizer, else every
/// point resident.
fn drawer<'a>(
    scan: &'a LiveScan,
    kind: RendererKind,
    settings: &RenderSettings,
    camera: DVec3,
) -> Result<Box<dyn DrawsFrames + 'a>, ServeError> {
    match (&scan.lod, kind) {
        (Some(lod), RendererKind::Raster) => {
            Ok(Box::new(node_stream(scan, lod, settings, camera)?))
        }
        _ => Ok(Box::new(Resident::anchored(
            &scan.scene,
            kind,
            settings,
            Anchor::Camera(camera),
        )?)),
    }
}

/// The node stream of `lod`, coloured as the whole scan is and around its origin, so that a
/// render through every node is the resident scan's.
fn node_stream(
    scan: &LiveScan,
    lod: &ServedLod,
    settings: &RenderSettings,
    camera: DVec3,
) -> Result<NodeStream, ServeError> {
    let color = ColorRule::for_scene(&scan.scene, settings.color)?;
    let rasterizer =
        crate::raster::Rasterizer::new().map_err(crate::renderer::ResidentError::from)?;
    let options = PrepareOptions {
        origin: Some(scan.scene.origin),
        up: lod.up,
        fields: settings.color.fields(),
        ..PrepareOptions::default()
    };
    let rules = NodeRules {
        radii: lod.radii,
        color,
        pixels: lod.pixels,
        floor: lod.floor,
        budget: lod.budget,
    };
    let mut stream = NodeStream::new(rasterizer, &lod.path, &options, rules, settings)?;
    stream.place(Anchor::Camera(camera));
    Ok(stream)
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::Vec3;

    use super::*;
    use crate::render::ColorMode;
    use crate::scene::Scene;
    use crate::web::serve::scan::LiveOptions;

    /// A 20 m x 20 m floor with a 2 m wall along its north side, prepared around file
    /// (300, 700, 20).
    fn courtyard() -> LiveScan {
        let mut pts = Vec::new();
        for i in 0..=80 {
            let x = i as f32 * 0.25 - 10.0;
            for j in 0..=80 {
                pts.push(Vec3::new(x, j as f32 * 0.25 - 10.0, -1.7));
            }
            for k in 0..=8 {
                pts.push(Vec3::new(x, 10.0, k as f32 * 0.25 - 1.7));
            }
        }
        let scene = Scene::new(DVec3::new(300.0, 700.0, 20.0), pts, 0.15);
        let options = LiveOptions {
            width: 64,
            color: ColorMode::Elevation,
            map_size: 40,
            ..LiveOptions::default()
        };
        LiveScan::new(Path::new("courtyard.laz"), scene, options).unwrap()
    }

    #[test]
    fn the_ray_tracer_serves_the_frames_it_renders_alone() {
        let scan = Arc::new(courtyard());
        let thread = RenderThread::start(scan.clone(), RendererKind::Raytrace).unwrap();
        assert_eq!(thread.adapter(), "CPU ray tracer");
        assert_eq!(thread.max_width(), u32::MAX);
        let at_default = RenderRequest::default_at(&scan.limits);
        let moved = RenderRequest {
            xy: DVec2::new(304.0, 697.5),
            ipd: 0.1,
            seq: 2,
            ..at_default.clone()
        };
        for request in [at_default, moved] {
            let served = thread.render(request.clone()).unwrap();
            let camera = scan.camera_at(request.xy).unwrap();
            assert_eq!(served.camera, camera);
            assert_eq!(served.seq, request.seq);
            let settings = live_settings(&scan, camera - scan.scene.origin, &request);
            let alone =
                crate::raytrace::render(&scan.scene, &settings, &ProgressBar::hidden()).unwrap();
            assert!(alone.frames()[0].coverage_count() > 64 * 32 / 4);
            assert!(
                served.png == png_bytes(&alone.top_bottom()).unwrap(),
                "the frame served at {} differs",
                request.xy
            );
        }
    }

    #[test]
    fn a_pair_handed_back_holds_the_next_live_pair() {
        let scan = Arc::new(courtyard());
        let thread = RenderThread::start(scan.clone(), RendererKind::Raytrace).unwrap();
        let queue = thread.queue();
        let first = RenderRequest::default_at(&scan.limits);
        let raw = queue.submit(first.clone(), 64).recv().unwrap().unwrap();
        let memory = raw.frame.color.as_ptr();
        queue.give_back(raw.frame);
        let moved = RenderRequest {
            xy: DVec2::new(304.0, 697.5),
            seq: 1,
            ..first
        };
        let raw = queue.submit(moved.clone(), 64).recv().unwrap().unwrap();
        assert_eq!(
            raw.frame.color.as_ptr(),
            memory,
            "stacked into the pair handed back"
        );
        let camera = scan.camera_at(moved.xy).unwrap();
        let settings = live_settings(&scan, camera - scan.scene.origin, &moved);
        let alone =
            crate::raytrace::render(&scan.scene, &settings, &ProgressBar::hidden()).unwrap();
        assert!(
            raw.frame == alone.top_bottom(),
            "the pair differs from a render alone"
        );
    }
}
