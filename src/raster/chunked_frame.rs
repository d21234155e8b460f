//! Out-of-core rasterizing: scenes that are pieces of one cloud (all relative to the same
//! origin) drawn one after another into one frame through a single reused GPU chunk, so GPU
//! and host memory follow the chunk size, not the point count.

use indicatif::ProgressBar;

use crate::frame::Rendered;
use crate::render::{ColorRule, RenderSettings};
use crate::scene::Scene;

use super::chunk::{GpuChunk, GpuPoint, pack_color};
use super::error::RasterError;
use super::raster_frame::RasterFrame;
use super::rasterizer::Rasterizer;
use super::stats::RasterStats;
use super::timing::FrameTiming;

/// A frame that accepts the cloud piece by piece; see the module docs.
pub struct ChunkedFrame<'r> {
    frame: RasterFrame<'r>,
    chunk: GpuChunk,
    settings: RenderSettings,
    color: ColorRule,
    points: u64,
    // Staging for one GPU chunk, reused.
    positions: Vec<GpuPoint>,
    colors: Vec<u32>,
}

impl Rasterizer {
    /// Starts a frame that will be drawn in pieces of at most `chunk_points` points each
    /// (larger scenes passed to [`ChunkedFrame::draw`] are split). Colours come from `color`,
    /// fixed for the whole cloud so that pieces colour alike.
    pub fn begin_chunked(
        &self,
        settings: &RenderSettings,
        color: ColorRule,
        chunk_points: u32,
    ) -> Result<ChunkedFrame<'_>, RasterError> {
        let chunk_points =
            chunk_points.clamp(1, self.points_per_chunk().min(u32::MAX as u64) as u32);
        let frame = self.begin_frame(settings, chunk_points as u64)?;
        let chunk = GpuChunk::new(&self.ctx, chunk_points)?;
        Ok(ChunkedFrame {
            frame,
            chunk,
            settings: *settings,
            color,
            points: 0,
            positions: Vec::new(),
            colors: Vec::new(),
        })
    }
}

impl ChunkedFrame<'_> {
    /// Points drawn so far.
    pub fn points(&self) -> u64 {
        self.points
    }

    /// Draws `scene` (positions relative to the same origin as every other piece; the camera
    /// centre of the settings is in that frame) into the frame.
    pub fn draw(&mut self, scene: &Scene) -> Result<(), RasterError> {
        let colors = self.color.colors(scene)?;
        let c = self.settings.camera.center;
        let capacity = self.chunk.capacity as usize;
        let mut start = 0;
        while start < scene.len() {
            let end = (start + capacity).min(scene.len());
            self.positions.clear();
            self.positions
                .extend((start..end).map(|i| GpuPoint::of(scene, i, c)));
            self.colors.clear();
            self.colors
                .extend(colors[start..end].iter().copied().map(pack_color));
            let ctx = &self.frame.rasterizer().ctx;
            self.chunk.write(ctx, &self.positions, &self.colors)?;
            self.frame.draw(&self.chunk, &ProgressBar::hidden())?;
            self.points += (end - start) as u64;
            start = end;
        }
        Ok(())
    }

    /// Ends the frame and reads it back.
    pub fn finish(self) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        self.frame.finish()
    }
}

impl crate::stream::ChunkSink for ChunkedFrame<'_> {
    fn draw(&mut self, chunk: &Scene) -> Result<(), crate::stream::StreamError> {
        ChunkedFrame::draw(self, chunk).map_err(crate::stream::StreamError::sink)
    }
}
