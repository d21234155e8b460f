//! A whole scene uploaded once (in chunks of one storage binding each) and rendered any
//! number of times.

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;

use crate::frame::Rendered;
use crate::render::{ColorMode, ColorRule, RenderSettings};
use crate::scene::Scene;

use super::chunk::{GpuChunk, GpuPoint, pack_color};
use super::error::RasterError;
use super::piece_occlusion::OcclusionTiles;
use super::raster_frame::RasterFrame;
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
    /// The box of its spheres (centres plus radii) relative to `points_origin`, as the
    /// shaders see them; `None` when empty.
    extent: Option<(DVec3, DVec3)>,
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

    /// Its box of spheres relative to the camera centre `c`.
    fn extent_from(&self, c: DVec3) -> Option<(DVec3, DVec3)> {
        let shift = self.points_origin - c;
        self.extent.map(|(lo, hi)| (lo + shift, hi + shift))
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
        let mut extent: Option<(DVec3, DVec3)> = None;
        while start < scene.len() {
            let end = (start + per_chunk).min(scene.len());
            let pts: Vec<GpuPoint> = (start..end).map(|i| GpuPoint::of(scene, i, c)).collect();
            for p in &pts {
                let (centre, r) = (Vec3::from(p.position).as_dvec3(), f64::from(p.radius));
                let (lo, hi) = (centre - DVec3::splat(r), centre + DVec3::splat(r));
                extent = Some(extent.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
            }
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
            extent,
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
    /// per piece, and no point crosses from the host again. The pieces are drawn nearest
    /// first, and where the frame keeps occlusion tiles a piece hidden whole behind those
    /// drawn before it is skipped (`piece_occlusion`): the image is the same.
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
        let eyes = frame.eyes() as u64;
        progress.set_length(total * eyes);
        let camera = settings.camera.center;
        let skips = self.knobs().skip_hidden_pieces && frame.keeps_tiles();
        // Nearest first: what is drawn early hides more of what follows.
        let mut order: Vec<(f64, &UploadedScene)> = pieces
            .iter()
            .map(|p| {
                let d = p
                    .extent_from(camera)
                    .map_or(0.0, |(lo, hi)| DVec3::ZERO.clamp(lo, hi).length());
                (d, *p)
            })
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut batch = Gather::new(self, capacity)?;
        let mut tiles: Option<OcclusionTiles> = None;
        // The tiles are read back once an eighth of the points is drawn, then each time the
        // points drawn double.
        let mut next_look = total.div_ceil(8);
        let mut gathered = 0u64;
        let mut hidden = (0u64, 0u64);
        for (k, (_, piece)) in order.iter().enumerate() {
            if let (Some(t), Some((lo, hi))) = (&tiles, piece.extent_from(camera))
                && t.hide(lo, hi)
            {
                hidden.0 += 1;
                hidden.1 += piece.points;
                progress.inc(piece.points * eyes);
                continue;
            }
            for chunk in &piece.chunks {
                batch.add(chunk, &mut frame, progress)?;
            }
            gathered += piece.points;
            if skips && gathered >= next_look && k + 1 < order.len() {
                batch.flush(&mut frame, progress)?;
                tiles = frame.occlusion_tiles()?;
                next_look = gathered * 2;
            }
        }
        batch.flush(&mut frame, progress)?;
        let (rendered, mut stats, timing) = frame.finish()?;
        stats.hidden_pieces = hidden.0;
        stats.hidden_points = hidden.1 * eyes;
        Ok((rendered, stats, timing))
    }
}

/// One batch of gathered points being filled by buffer copies, drawn whenever it is full.
struct Gather<'r> {
    rasterizer: &'r Rasterizer,
    batch: GpuChunk,
    encoder: wgpu::CommandEncoder,
    filled: u32,
}

impl<'r> Gather<'r> {
    fn new(rasterizer: &'r Rasterizer, capacity: u32) -> Result<Self, RasterError> {
        Ok(Gather {
            rasterizer,
            batch: GpuChunk::new(&rasterizer.ctx, capacity)?,
            encoder: rasterizer
                .ctx
                .device
                .create_command_encoder(&Default::default()),
            filled: 0,
        })
    }

    /// Copies `chunk`'s points into the batch, drawing it into `frame` each time it fills.
    fn add(
        &mut self,
        chunk: &GpuChunk,
        frame: &mut RasterFrame<'_>,
        progress: &ProgressBar,
    ) -> Result<(), RasterError> {
        let point_bytes = size_of::<GpuPoint>() as u64;
        let color_bytes = size_of::<u32>() as u64;
        let capacity = self.batch.capacity;
        let mut from = 0u32;
        while from < chunk.len {
            let n = (chunk.len - from).min(capacity - self.filled);
            let (src, dst, len) = (u64::from(from), u64::from(self.filled), u64::from(n));
            self.encoder.copy_buffer_to_buffer(
                &chunk.points,
                src * point_bytes,
                &self.batch.points,
                dst * point_bytes,
                len * point_bytes,
            );
            self.encoder.copy_buffer_to_buffer(
                &chunk.colors,
                src * color_bytes,
                &self.batch.colors,
                dst * color_bytes,
                len * color_bytes,
            );
            from += n;
            self.filled += n;
            if self.filled == capacity {
                self.flush(frame, progress)?;
            }
        }
        Ok(())
    }

    /// Draws what the batch holds into `frame`.
    fn flush(
        &mut self,
        frame: &mut RasterFrame<'_>,
        progress: &ProgressBar,
    ) -> Result<(), RasterError> {
        if self.filled == 0 {
            return Ok(());
        }
        // The copies reach the queue before the batch's draw, which submits its own work; the
        // next copies follow that draw.
        let ctx = &self.rasterizer.ctx;
        let full = std::mem::replace(
            &mut self.encoder,
            ctx.device.create_command_encoder(&Default::default()),
        );
        ctx.queue.submit([full.finish()]);
        self.batch.len = self.filled;
        frame.draw(&self.batch, progress)?;
        self.filled = 0;
        Ok(())
    }
}
