//! A whole scene uploaded once (in chunks of one storage binding each) and rendered any
//! number of times.

use indicatif::ProgressBar;

use crate::frame::Rendered;
use crate::render::{ColorMode, ColorRule, RenderSettings};
use crate::scene::Scene;

use super::chunk::{GpuChunk, GpuPoint, pack_color};
use super::error::RasterError;
use super::rasterizer::Rasterizer;
use super::stats::RasterStats;
use super::timing::FrameTiming;

/// A scene's points and colours on the GPU, relative to one point of the scene's frame (the
/// camera centre they were uploaded for); any camera centre can render them.
pub struct UploadedScene {
    chunks: Vec<GpuChunk>,
    points_origin: glam::DVec3,
    color: ColorMode,
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

    /// Bytes its buffers take on the GPU.
    pub fn gpu_bytes(&self) -> u64 {
        let per_point = (size_of::<GpuPoint>() + size_of::<u32>()) as u64;
        self.chunks
            .iter()
            .map(|c| u64::from(c.capacity))
            .sum::<u64>()
            * per_point
    }
}

impl Rasterizer {
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

    /// Uploads `scene` (positions relative to `settings.camera.center`, colours under
    /// `settings.color`) for repeated rendering with [`Rasterizer::render_uploaded`], from
    /// that camera centre or any other: a tour uploads once and moves the camera.
    pub fn upload(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<UploadedScene, RasterError> {
        self.upload_colored(
            scene,
            settings,
            ColorRule::for_scene(scene, settings.color)?,
        )
    }

    /// [`Rasterizer::upload`] with colours from `color` rather than measured on `scene`:
    /// pieces of one cloud uploaded apart colour alike.
    pub fn upload_colored(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        color: ColorRule,
    ) -> Result<UploadedScene, RasterError> {
        let colors = color.colors(scene)?;
        let c = settings.camera.center;
        let per_chunk = self.points_per_chunk() as usize;
        let mut chunks = Vec::new();
        let mut start = 0;
        while start < scene.len() {
            let end = (start + per_chunk).min(scene.len());
            let pts: Vec<GpuPoint> = (start..end).map(|i| GpuPoint::of(scene, i, c)).collect();
            let cols: Vec<u32> = colors[start..end].iter().copied().map(pack_color).collect();
            let mut chunk = GpuChunk::new(&self.ctx, (end - start) as u32)?;
            chunk.write(&self.ctx, &pts, &cols)?;
            chunks.push(chunk);
            start = end;
        }
        Ok(UploadedScene {
            chunks,
            points_origin: c,
            color: settings.color,
            points: scene.len() as u64,
        })
    }

    /// Renders an uploaded scene; also returns the time the expand and draw work took. The
    /// camera may stand anywhere in the scene's frame: positions stay on the GPU, relative to
    /// the centre they were uploaded for, and the shaders subtract the camera's offset from it
    /// (in f32: positions far from that centre lose precision as f32 does, about 1e-7 of
    /// their distance).
    pub fn render_uploaded(
        &self,
        uploaded: &UploadedScene,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        if uploaded.color != settings.color {
            return Err(RasterError::Settings(
                "the scene was uploaded for another colour mode".into(),
            ));
        }
        let largest = uploaded.chunks.iter().map(|c| c.len as u64).max();
        let mut frame = self.begin_frame(settings, largest.unwrap_or(1))?;
        frame.set_points_origin(uploaded.points_origin);
        progress.set_length(uploaded.points * frame.eyes() as u64);
        for chunk in &uploaded.chunks {
            frame.draw(chunk, progress)?;
        }
        frame.finish()
    }

    /// Renders pieces of one cloud uploaded apart (each by [`Rasterizer::upload_colored`]
    /// under the same settings, so relative to the same point and coloured alike), gathered
    /// on the GPU into batches of up to one chunk: a frame then costs a draw per batch, not
    /// per piece, and no point crosses from the host again.
    pub fn render_gathered(
        &self,
        pieces: &[&UploadedScene],
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, RasterError> {
        Ok(self.render_gathered_timed(pieces, settings, progress)?.0)
    }

    /// [`Rasterizer::render_gathered`] with the frame's counters and time.
    pub fn render_gathered_timed(
        &self,
        pieces: &[&UploadedScene],
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        let origin = pieces
            .first()
            .map_or(settings.camera.center, |p| p.points_origin);
        if pieces
            .iter()
            .any(|p| p.points_origin != origin || p.color != settings.color)
        {
            return Err(RasterError::Settings(
                "pieces gathered into one frame were uploaded under other settings".into(),
            ));
        }
        let total: u64 = pieces.iter().map(|p| p.points).sum();
        let capacity = total.clamp(1, self.points_per_chunk().min(u64::from(u32::MAX))) as u32;
        let mut frame = self.begin_frame(settings, u64::from(capacity))?;
        frame.set_points_origin(origin);
        progress.set_length(total * frame.eyes() as u64);
        let mut batch = GpuChunk::new(&self.ctx, capacity)?;
        let device = &self.ctx.device;
        let point_bytes = size_of::<GpuPoint>() as u64;
        let color_bytes = size_of::<u32>() as u64;
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut filled = 0u32;
        for chunk in pieces.iter().flat_map(|p| &p.chunks) {
            let mut from = 0u32;
            while from < chunk.len {
                let n = (chunk.len - from).min(capacity - filled);
                let (src, dst, len) = (u64::from(from), u64::from(filled), u64::from(n));
                encoder.copy_buffer_to_buffer(
                    &chunk.points,
                    src * point_bytes,
                    &batch.points,
                    dst * point_bytes,
                    len * point_bytes,
                );
                encoder.copy_buffer_to_buffer(
                    &chunk.colors,
                    src * color_bytes,
                    &batch.colors,
                    dst * color_bytes,
                    len * color_bytes,
                );
                from += n;
                filled += n;
                if filled == capacity {
                    // The copies reach the queue before the batch's draw, which submits its
                    // own work; the next copies follow that draw.
                    let full = std::mem::replace(
                        &mut encoder,
                        device.create_command_encoder(&Default::default()),
                    );
                    self.ctx.queue.submit([full.finish()]);
                    batch.len = filled;
                    frame.draw(&batch, progress)?;
                    filled = 0;
                }
            }
        }
        if filled > 0 {
            self.ctx.queue.submit([encoder.finish()]);
            batch.len = filled;
            frame.draw(&batch, progress)?;
        }
        frame.finish()
    }
}
