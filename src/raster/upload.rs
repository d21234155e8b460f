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
    /// Its points in runs of one cell each, chunk by chunk in order.
    cells: Vec<Cell>,
}

/// A run of a chunk's points that share one cell of the chunk's box, and their box of
/// spheres relative to the points' origin: a gathered frame skips a cell hidden whole.
#[derive(Debug, Clone, Copy)]
struct Cell {
    chunk: usize,
    start: u32,
    end: u32,
    lo: DVec3,
    hi: DVec3,
}

/// Cells along each axis of a chunk's box (at most 16: a cell's key is a `u16`).
const CELLS_PER_AXIS: usize = 4;
/// Chunks of fewer points stay one cell: a cell costs a test and a copy.
const MIN_POINTS_TO_SPLIT: usize = 4096;

/// Orders `pts` (and `cols` alike) cell by cell of their box's `CELLS_PER_AXIS`³ grid, the
/// order within a cell kept, and returns the runs as cells of chunk `chunk`.
fn sort_into_cells(pts: &mut Vec<GpuPoint>, cols: &mut Vec<u32>, chunk: usize) -> Vec<Cell> {
    let centre = |p: &GpuPoint| Vec3::from(p.position);
    let (lo, hi) = pts.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), p| (a.min(centre(p)), b.max(centre(p))),
    );
    let n = if pts.len() >= MIN_POINTS_TO_SPLIT {
        CELLS_PER_AXIS
    } else {
        1
    };
    let scale = Vec3::splat(n as f32) / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let cell_of = |p: &GpuPoint| {
        let t = ((centre(p) - lo) * scale)
            .floor()
            .clamp(Vec3::ZERO, Vec3::splat((n - 1) as f32));
        (t.x as usize * n + t.y as usize) * n + t.z as usize
    };
    // A counting sort, stable: the points and colours are scattered once into their cells'
    // places (two bytes of key a point beside the copies, for up to 16³ cells).
    let keys: Vec<u16> = pts.iter().map(|p| cell_of(p) as u16).collect();
    let mut starts = vec![0usize; n * n * n + 1];
    for &k in &keys {
        starts[usize::from(k) + 1] += 1;
    }
    for k in 0..n * n * n {
        starts[k + 1] += starts[k];
    }
    let mut at = starts.clone();
    let mut sorted_pts = pts.clone();
    let mut sorted_cols = cols.clone();
    for (i, &k) in keys.iter().enumerate() {
        let slot = &mut at[usize::from(k)];
        sorted_pts[*slot] = pts[i];
        sorted_cols[*slot] = cols[i];
        *slot += 1;
    }
    *pts = sorted_pts;
    *cols = sorted_cols;
    starts
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            let (lo, hi) = sphere_box(&pts[w[0]..w[1]]);
            Cell {
                chunk,
                start: w[0] as u32,
                end: w[1] as u32,
                lo,
                hi,
            }
        })
        .collect()
}

/// The box of the spheres `pts` (centres plus radii), in f64.
fn sphere_box(pts: &[GpuPoint]) -> (DVec3, DVec3) {
    pts.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(a, b), p| {
            let (centre, r) = (Vec3::from(p.position).as_dvec3(), f64::from(p.radius));
            (a.min(centre - r), b.max(centre + r))
        },
    )
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
        let mut cells = Vec::new();
        while start < scene.len() {
            let end = (start + per_chunk).min(scene.len());
            let mut pts: Vec<GpuPoint> = (start..end).map(|i| GpuPoint::of(scene, i, c)).collect();
            let mut cols: Vec<u32> = colors[start..end].iter().copied().map(pack_color).collect();
            cells.extend(sort_into_cells(&mut pts, &mut cols, chunks.len()));
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
            extent: cells
                .iter()
                .map(|c| (c.lo, c.hi))
                .reduce(|(a, b), (lo, hi)| (a.min(lo), b.max(hi))),
            cells,
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
            // Runs of cells in view, each copied at once.
            let shift = piece.points_origin - camera;
            let mut run: Option<(usize, u32, u32)> = None;
            for cell in &piece.cells {
                let shown = !tiles
                    .as_ref()
                    .is_some_and(|t| t.hide(cell.lo + shift, cell.hi + shift));
                let n = u64::from(cell.end - cell.start);
                if !shown {
                    hidden.1 += n;
                    progress.inc(n * eyes);
                    continue;
                }
                gathered += n;
                run = match run {
                    Some((chunk, start, end)) if chunk == cell.chunk && end == cell.start => {
                        Some((chunk, start, cell.end))
                    }
                    other => {
                        if let Some((chunk, start, end)) = other {
                            batch.add(&piece.chunks[chunk], start..end, &mut frame, progress)?;
                        }
                        Some((cell.chunk, cell.start, cell.end))
                    }
                };
            }
            if let Some((chunk, start, end)) = run {
                batch.add(&piece.chunks[chunk], start..end, &mut frame, progress)?;
            }
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

    /// Copies `chunk`'s points `range` into the batch, drawing it into `frame` each time it
    /// fills.
    fn add(
        &mut self,
        chunk: &GpuChunk,
        range: std::ops::Range<u32>,
        frame: &mut RasterFrame<'_>,
        progress: &ProgressBar,
    ) -> Result<(), RasterError> {
        let point_bytes = size_of::<GpuPoint>() as u64;
        let color_bytes = size_of::<u32>() as u64;
        let capacity = self.batch.capacity;
        let mut from = range.start;
        while from < range.end {
            let n = (range.end - from).min(capacity - self.filled);
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
