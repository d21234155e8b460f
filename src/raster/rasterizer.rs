//! The rasterizer: uploads a scene in chunks, expands and draws each batch per eye through
//! one depth buffer, and reads the frames back.

use indicatif::ProgressBar;

use crate::frame::Rendered;
use crate::render::{RenderSettings, base_colors};
use crate::scene::Scene;

use super::context::GpuContext;
use super::error::RasterError;
use super::pipelines::Pipelines;
use super::raster_frame::{GpuChunk, packed_color, packed_point};
use super::targets::map_read;

/// Counts from one render, summed over the eyes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RasterStats {
    /// Points whose centre has no projection (inside the viewing circle); ray-cast imposters
    /// still draw them with a conservative proxy, sprites drop them.
    pub culled: u64,
    /// Points that produced a proxy.
    pub drawn: u64,
    /// Proxies drawn as analytic bounds with forced ray casting (eye-enclosing, near the
    /// eye, containing a pole, or a billboard that could not be projected).
    pub special: u64,
    /// Proxies drawn a second time across the seam.
    pub seam_copies: u64,
    /// Proxies ray cast by the compute splat instead of drawn (counted in `drawn` too).
    pub splatted: u64,
    /// Vertices written.
    pub vertices: u64,
    /// Expand/draw batches submitted (per eye).
    pub batches: u64,
}

impl std::fmt::Display for RasterStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} proxies drawn ({} special, {} seam copies, {} splatted, {} vertices, {} batches), \
             {} points inside the viewing circle",
            self.drawn,
            self.special,
            self.seam_copies,
            self.splatted,
            self.vertices,
            self.batches,
            self.culled
        )
    }
}

/// How a frame time was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries around the work.
    GpuTimestamps,
    /// Wall clock from the first submission to the end of the GPU work.
    WallClock,
}

/// A frame time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameTiming {
    /// Seconds spent expanding and drawing (excluding read-back).
    pub seconds: f64,
    /// How it was measured.
    pub source: TimingSource,
}

/// Default largest sphere the compute splat ray casts, in pixels per side of its bounds;
/// larger ones are drawn.
pub const DEFAULT_SPLAT_LIMIT: u32 = 16;

/// A GPU imposter-sphere rasterizer bound to one device; reusable across renders.
pub struct Rasterizer {
    pub(crate) ctx: GpuContext,
    pub(crate) pipelines: Pipelines,
    pub(crate) batch_limit: Option<u32>,
    pub(crate) splat_limit: u32,
}

/// A scene's points and colours on the GPU, relative to one camera centre.
pub struct UploadedScene {
    chunks: Vec<GpuChunk>,
    camera_center: glam::DVec3,
    color: crate::render::ColorMode,
    points: u64,
}

impl UploadedScene {
    /// Number of points uploaded.
    pub fn len(&self) -> u64 {
        self.points
    }

    /// True when no point was uploaded.
    pub fn is_empty(&self) -> bool {
        self.points == 0
    }
}

impl Rasterizer {
    /// Creates the device and compiles the pipelines.
    pub fn new() -> Result<Self, RasterError> {
        let ctx = GpuContext::new()?;
        let pipelines = Pipelines::new(&ctx)?;
        Ok(Rasterizer {
            ctx,
            pipelines,
            batch_limit: None,
            splat_limit: DEFAULT_SPLAT_LIMIT,
        })
    }

    /// Caps the points per expand/draw batch (default: as many as the vertex buffer holds).
    /// Smaller batches exercise the chunked path; results must not change.
    pub fn set_batch_limit(&mut self, points: Option<u32>) {
        self.batch_limit = points;
    }

    /// Sets the largest sphere (pixels per side of its bounds) that the compute splat ray
    /// casts instead of drawing; 0 draws every sphere. The splat runs only for ray-cast
    /// imposters on analytic bounds, on devices with 64-bit atomics; results must not change.
    pub fn set_splat_limit(&mut self, pixels: u32) {
        self.splat_limit = pixels;
    }

    /// True when this device can run the compute splat.
    pub fn can_splat(&self) -> bool {
        self.ctx.int64_atomics
    }

    /// The adapter's name and backend.
    pub fn adapter_name(&self) -> &str {
        &self.ctx.adapter_name
    }

    /// Widest equirectangular image (pixels per eye) the adapter's textures allow.
    pub fn max_image_width(&self) -> u32 {
        self.ctx.limits.max_texture_dimension_2d
    }

    /// True when frame timings come from GPU timestamps.
    pub fn has_timestamps(&self) -> bool {
        self.ctx.timestamps
    }

    /// Renders `scene` under `settings`: one frame per view, laid out as the ray tracer's.
    pub fn render(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<(Rendered, RasterStats), RasterError> {
        let uploaded = self.upload(scene, settings)?;
        let (rendered, stats, _) = self.render_uploaded(&uploaded, settings, progress)?;
        Ok((rendered, stats))
    }

    pub(crate) fn points_per_chunk(&self) -> u64 {
        let binding = self
            .ctx
            .limits
            .max_storage_buffer_binding_size
            .min(self.ctx.limits.max_buffer_size)
            .min(256 << 20);
        // 16 bytes per point (centre relative to C, radius).
        (binding / 16).max(1)
    }

    /// Uploads `scene` (positions relative to `settings.camera.center`, colours under
    /// `settings.color`) for repeated rendering with [`Rasterizer::render_uploaded`].
    pub fn upload(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<UploadedScene, RasterError> {
        let colors = base_colors(scene, settings.color)?;
        let c = settings.camera.center;
        let per_chunk = self.points_per_chunk() as usize;
        let mut chunks = Vec::new();
        let mut start = 0;
        while start < scene.len() {
            let end = (start + per_chunk).min(scene.len());
            let pts: Vec<[f32; 4]> = (start..end).map(|i| packed_point(scene, i, c)).collect();
            let cols: Vec<u32> = colors[start..end]
                .iter()
                .copied()
                .map(packed_color)
                .collect();
            let mut chunk = GpuChunk::new(self, (end - start) as u32)?;
            chunk.write(self, &pts, &cols)?;
            chunks.push(chunk);
            start = end;
        }
        Ok(UploadedScene {
            chunks,
            camera_center: c,
            color: settings.color,
            points: scene.len() as u64,
        })
    }

    /// Seconds between the two timestamps of `query`, or `None` when they make no sense.
    pub(crate) fn read_timestamps(
        &self,
        query: &wgpu::QuerySet,
    ) -> Result<Option<f64>, RasterError> {
        let device = &self.ctx.device;
        let (resolve, read) = self.ctx.scoped("reading timestamps", || {
            let make = |label, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: 16,
                    usage,
                    mapped_at_creation: false,
                })
            };
            (
                make(
                    "timestamps",
                    wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                ),
                make(
                    "timestamps read-back",
                    wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                ),
            )
        })?;
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.resolve_query_set(query, 0..2, &resolve, 0);
        encoder.copy_buffer_to_buffer(&resolve, 0, &read, 0, None);
        self.ctx.queue.submit([encoder.finish()]);
        let raw = map_read(&self.ctx, &read, "reading timestamps")?;
        let t: Vec<u64> = bytemuck::pod_collect_to_vec(&raw);
        let period_ns = self.ctx.queue.get_timestamp_period() as f64;
        Ok((t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period_ns * 1e-9))
    }

    /// Renders an uploaded scene; also returns the time the expand and draw work took.
    pub fn render_uploaded(
        &self,
        uploaded: &UploadedScene,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        if uploaded.camera_center != settings.camera.center || uploaded.color != settings.color {
            return Err(RasterError::Settings(
                "the scene was uploaded for another camera centre or colour mode".into(),
            ));
        }
        let largest = uploaded.chunks.iter().map(|c| c.len as u64).max();
        let mut frame = self.begin_frame(settings, largest.unwrap_or(1))?;
        progress.set_length(uploaded.points * frame.eyes() as u64);
        for chunk in &uploaded.chunks {
            frame.draw(chunk, progress)?;
        }
        frame.finish()
    }
}
