//! One frame in progress on the GPU: targets cleared once, any number of point chunks drawn
//! into them, then read back. [`Rasterizer::render_uploaded`] draws an uploaded scene's chunks
//! through it; the out-of-core path ([`super::RasterSink`]) draws chunks as they are decoded,
//! so the whole cloud never has to be resident.

use std::time::Instant;

use indicatif::ProgressBar;

use crate::frame::{Frame, Rendered};
use crate::projection::View;
use crate::render::{Imposter, Proxy, RenderSettings};

use super::error::RasterError;
use super::params::{Params, max_vertices_per_point};
use super::pipelines::{EXPAND_WORKGROUP, VERTEX_BYTES};
use super::rasterizer::{FrameTiming, RasterStats, Rasterizer, TimingSource};
use super::targets::{EyeTargets, map_read};

const STATS_PER_EYE: usize = 8;
const MAX_EYES: usize = 2;

/// Points (centre relative to the camera centre and radius) and their base colours on the GPU.
pub(crate) struct GpuChunk {
    /// `[x, y, z, radius]` per point, f32.
    pub points: wgpu::Buffer,
    /// Packed sRGB `r | g << 8 | b << 16` per point.
    pub colors: wgpu::Buffer,
    /// Points in use (the buffers may hold more).
    pub len: u32,
    /// Points the buffers can hold.
    pub capacity: u32,
}

impl GpuChunk {
    /// Allocates buffers for `capacity` points.
    pub fn new(rasterizer: &Rasterizer, capacity: u32) -> Result<Self, RasterError> {
        let ctx = &rasterizer.ctx;
        let capacity = capacity.max(1);
        ctx.scoped("allocating point buffers", || {
            let make = |label, size| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            GpuChunk {
                points: make("points", capacity as u64 * 16),
                colors: make("colors", capacity as u64 * 4),
                len: 0,
                capacity,
            }
        })
    }

    /// Writes `points` and `colors` (equal lengths, at most `capacity`) to the start of the
    /// buffers.
    pub fn write(
        &mut self,
        rasterizer: &Rasterizer,
        points: &[[f32; 4]],
        colors: &[u32],
    ) -> Result<(), RasterError> {
        if points.len() != colors.len() || points.len() > self.capacity as usize {
            return Err(RasterError::Settings(format!(
                "{} points and {} colours do not fit a chunk of {}",
                points.len(),
                colors.len(),
                self.capacity
            )));
        }
        let ctx = &rasterizer.ctx;
        ctx.scoped("uploading points", || {
            ctx.queue
                .write_buffer(&self.points, 0, bytemuck::cast_slice(points));
            ctx.queue
                .write_buffer(&self.colors, 0, bytemuck::cast_slice(colors));
        })?;
        self.len = points.len() as u32;
        Ok(())
    }
}

/// Point `i` of `scene` as the GPU holds it: centre relative to the camera centre `c` (in the
/// scene's frame), and radius.
pub(crate) fn packed_point(scene: &crate::Scene, i: usize, c: glam::DVec3) -> [f32; 4] {
    let p = scene.positions[i].as_dvec3() - c;
    [p.x as f32, p.y as f32, p.z as f32, scene.radii.get(i)]
}

/// A base colour as the GPU holds it.
pub(crate) fn packed_color(c: [u8; 3]) -> u32 {
    c[0] as u32 | (c[1] as u32) << 8 | (c[2] as u32) << 16
}

/// A frame being drawn: per-eye targets, splat keys and the expand/draw work buffers, sized
/// for chunks of up to `max_chunk_points` points.
pub struct RasterFrame<'r> {
    rasterizer: &'r Rasterizer,
    settings: RenderSettings,
    views: Vec<View>,
    targets: Vec<EyeTargets>,
    splat: bool,
    splat_limit: u32,
    splat_keys: wgpu::Buffer,
    params_buf: wgpu::Buffer,
    vertices: wgpu::Buffer,
    args: wgpu::Buffer,
    stats_buf: wgpu::Buffer,
    vertex_capacity: u32,
    batch: u32,
    query: Option<wgpu::QuerySet>,
    started: Option<Instant>,
    batches: u64,
}

impl Rasterizer {
    /// Starts a frame under `settings` whose chunks hold at most `max_chunk_points` points:
    /// allocates and clears the targets. Draw chunks with [`RasterFrame::draw`], then
    /// [`RasterFrame::finish`].
    pub fn begin_frame(
        &self,
        settings: &RenderSettings,
        max_chunk_points: u64,
    ) -> Result<RasterFrame<'_>, RasterError> {
        check_settings(settings)?;
        let ctx = &self.ctx;
        let device = &ctx.device;
        let views = settings.views();
        let img = settings.image;
        let targets = views
            .iter()
            .map(|_| EyeTargets::new(ctx, img.width, img.height))
            .collect::<Result<Vec<_>, _>>()?;

        let splat_bytes = img.width as u64 * img.height as u64 * 8;
        let splat = ctx.int64_atomics
            && self.splat_limit > 0
            && settings.proxy == Proxy::Bounds
            && settings.imposter == Imposter::Raycast
            && splat_bytes
                <= ctx
                    .limits
                    .max_buffer_size
                    .min(ctx.limits.max_storage_buffer_binding_size);
        let splat_limit = if splat { self.splat_limit } else { 0 };
        // One key buffer, eye after eye; a placeholder binding when the splat is off.
        let splat_keys = ctx.scoped("allocating splat buffers", || {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("splat keys"),
                size: if splat { splat_bytes } else { 8 },
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })?;

        let per_point = max_vertices_per_point(settings.proxy);
        let vertex_bytes_max = ctx
            .limits
            .max_buffer_size
            .min(ctx.limits.max_storage_buffer_binding_size)
            .min(128 << 20)
            // wgpu zero-fills a fresh buffer before its first use, every frame: no larger
            // than the biggest chunk needs. (Smaller still would cost more batches, and each
            // batch's submit and wait costs far more than the fill on lavapipe.)
            .min(max_chunk_points.max(1) * per_point * VERTEX_BYTES);
        let vertex_capacity = vertex_bytes_max / VERTEX_BYTES;
        let max_groups = ctx.limits.max_compute_workgroups_per_dimension as u64;
        let batch = (vertex_capacity / per_point)
            .min(max_groups * EXPAND_WORKGROUP as u64)
            .min(self.batch_limit.map_or(u64::MAX, u64::from))
            .min(u32::MAX as u64)
            .max(1);
        let vertex_capacity = (batch * per_point).min(vertex_capacity) as u32;
        if (vertex_capacity as u64) < per_point {
            return Err(RasterError::Limit {
                what: "one point's proxy vertices".into(),
                needed: per_point * VERTEX_BYTES,
                limit: vertex_bytes_max,
            });
        }

        let (params_buf, vertices, args, stats_buf) =
            ctx.scoped("allocating work buffers", || {
                let make = |label, size, usage| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                use wgpu::BufferUsages as U;
                (
                    make(
                        "params",
                        std::mem::size_of::<Params>() as u64,
                        U::UNIFORM | U::COPY_DST,
                    ),
                    make(
                        "vertices",
                        vertex_capacity as u64 * VERTEX_BYTES,
                        U::STORAGE | U::VERTEX,
                    ),
                    make("draw args", 16, U::STORAGE | U::INDIRECT | U::COPY_DST),
                    make(
                        "stats",
                        (STATS_PER_EYE * MAX_EYES * 4) as u64,
                        U::STORAGE | U::COPY_SRC | U::COPY_DST,
                    ),
                )
            })?;

        // GPU timestamps: the start of the first expand pass and the end of the frame.
        let query = ctx.timestamps.then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });

        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&stats_buf, 0, None);
        encoder.clear_buffer(&splat_keys, 0, None);
        for t in &targets {
            t.clear(&mut encoder);
        }
        ctx.queue.submit([encoder.finish()]);

        Ok(RasterFrame {
            rasterizer: self,
            settings: *settings,
            views,
            targets,
            splat,
            splat_limit,
            splat_keys,
            params_buf,
            vertices,
            args,
            stats_buf,
            vertex_capacity,
            batch: batch as u32,
            query,
            started: None,
            batches: 0,
        })
    }
}

/// Rejects settings the rasterizer cannot draw.
fn check_settings(settings: &RenderSettings) -> Result<(), RasterError> {
    let img = settings.image;
    if img.width == 0 || img.height == 0 || img.width != 2 * img.height {
        return Err(RasterError::Settings(format!(
            "image {}x{} is not a 2:1 equirectangular size",
            img.width, img.height
        )));
    }
    if let Proxy::Static(n) = settings.proxy
        && !(1..=64).contains(&n)
    {
        return Err(RasterError::Settings(format!(
            "static tessellation level {n} is outside 1..=64"
        )));
    }
    Ok(())
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

impl<'r> RasterFrame<'r> {
    /// The rasterizer drawing this frame.
    pub fn rasterizer(&self) -> &'r Rasterizer {
        self.rasterizer
    }

    /// Points per expand/draw batch.
    pub fn batch_points(&self) -> u32 {
        self.batch
    }

    /// Number of views (eyes) drawn.
    pub fn eyes(&self) -> usize {
        self.views.len()
    }

    /// Expands and draws `chunk` for every eye, then merges its splatted spheres; `progress`
    /// advances by the points drawn, once per eye.
    pub(crate) fn draw(
        &mut self,
        chunk: &GpuChunk,
        progress: &ProgressBar,
    ) -> Result<(), RasterError> {
        if chunk.len == 0 {
            return Ok(());
        }
        let r = self.rasterizer;
        let ctx = &r.ctx;
        let device = &ctx.device;
        let keys = &self.splat_keys;
        let (expand_bg, draw_bg, resolve_bg) = ctx.scoped("binding a chunk", || {
            let mut entries = vec![
                entry(0, &self.params_buf),
                entry(1, &chunk.points),
                entry(3, &self.vertices),
                entry(4, &self.args),
                entry(5, &self.stats_buf),
            ];
            if ctx.int64_atomics {
                entries.push(entry(6, keys));
            }
            let expand_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("expand"),
                layout: &r.pipelines.expand.get_bind_group_layout(0),
                entries: &entries,
            });
            let resolve_bg = self.splat.then(|| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("splat resolve"),
                    layout: &r.pipelines.resolve.get_bind_group_layout(0),
                    entries: &[
                        entry(0, &self.params_buf),
                        entry(1, &chunk.points),
                        entry(2, &chunk.colors),
                        entry(3, keys),
                    ],
                })
            });
            let draw_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("imposters"),
                layout: &r.pipelines.imposter.get_bind_group_layout(0),
                entries: &[
                    entry(0, &self.params_buf),
                    entry(1, &chunk.points),
                    entry(2, &chunk.colors),
                ],
            });
            (expand_bg, draw_bg, resolve_bg)
        })?;
        self.started.get_or_insert_with(Instant::now);
        // Eye by eye, so that one splat key buffer serves both: its keys index this chunk's
        // points for this eye and are merged (and cleared) before the next.
        for (eye, (view, target)) in self.views.iter().zip(&self.targets).enumerate() {
            let mut first = 0u32;
            while first < chunk.len {
                let count = (chunk.len - first).min(self.batch);
                let params = Params::new(
                    view,
                    &self.settings,
                    eye as u32,
                    (first, count),
                    self.vertex_capacity,
                )
                .with_splat_limit(self.splat_limit);
                ctx.queue
                    .write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&params));
                ctx.queue
                    .write_buffer(&self.args, 0, bytemuck::cast_slice(&[0u32, 1, 0, 0]));
                let mut encoder = device.create_command_encoder(&Default::default());
                let first_step = self.batches == 0;
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("expand"),
                        timestamp_writes: self.query.as_ref().filter(|_| first_step).map(|q| {
                            wgpu::ComputePassTimestampWrites {
                                query_set: q,
                                beginning_of_pass_write_index: Some(0),
                                end_of_pass_write_index: None,
                            }
                        }),
                    });
                    pass.set_pipeline(&r.pipelines.expand);
                    pass.set_bind_group(0, &expand_bg, &[]);
                    pass.dispatch_workgroups(count.div_ceil(EXPAND_WORKGROUP), 1, 1);
                }
                {
                    let mut pass = target.begin_pass(&mut encoder, false, None);
                    pass.set_pipeline(&r.pipelines.imposter);
                    pass.set_bind_group(0, &draw_bg, &[]);
                    pass.set_vertex_buffer(0, self.vertices.slice(..));
                    pass.draw_indirect(&self.args, 0);
                }
                ctx.queue.submit([encoder.finish()]);
                // Keep the queue short so progress means something and memory stays flat.
                ctx.wait("drawing imposters")?;
                progress.inc(count as u64);
                self.batches += 1;
                first += count;
            }
            if let Some(bg) = &resolve_bg {
                let params = Params::new(
                    view,
                    &self.settings,
                    eye as u32,
                    (0, 0),
                    self.vertex_capacity,
                );
                ctx.queue
                    .write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&params));
                let mut encoder = device.create_command_encoder(&Default::default());
                {
                    let mut pass = target.begin_pass(&mut encoder, false, None);
                    pass.set_pipeline(&r.pipelines.resolve);
                    pass.set_bind_group(0, bg, &[]);
                    pass.draw(0..3, 0..1);
                }
                encoder.clear_buffer(keys, 0, None);
                ctx.queue.submit([encoder.finish()]);
                ctx.wait("resolving splatted spheres")?;
            }
        }
        Ok(())
    }

    /// Ends the frame: reads back the images, the counts and the time the drawing took.
    pub fn finish(self) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        let ctx = &self.rasterizer.ctx;
        let device = &ctx.device;
        if let Some(q) = self.query.as_ref().filter(|_| self.batches > 0) {
            // An empty pass after the last draw stamps the end of the frame.
            let mut encoder = device.create_command_encoder(&Default::default());
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("frame end"),
                timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: None,
                    end_of_pass_write_index: Some(1),
                }),
            }));
            ctx.queue.submit([encoder.finish()]);
        }
        ctx.wait("drawing imposters")?;
        let wall = self.started.map_or(0.0, |s| s.elapsed().as_secs_f64());
        let gpu = match &self.query {
            Some(q) if self.batches > 0 => self.rasterizer.read_timestamps(q)?,
            _ => None,
        };
        let timing = match gpu {
            Some(seconds) => FrameTiming {
                seconds,
                source: TimingSource::GpuTimestamps,
            },
            None => FrameTiming {
                seconds: wall,
                source: TimingSource::WallClock,
            },
        };

        let read = ctx.scoped("reading back statistics", || {
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stats read-back"),
                size: (STATS_PER_EYE * MAX_EYES * 4) as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.stats_buf, 0, &read, 0, None);
            ctx.queue.submit([encoder.finish()]);
            read
        })?;
        let raw = map_read(ctx, &read, "reading back statistics")?;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&raw);
        let eyes = self.views.len();
        let sum =
            |k: usize| -> u64 { (0..eyes).map(|e| words[e * STATS_PER_EYE + k] as u64).sum() };
        if sum(4) > 0 {
            return Err(RasterError::Gpu {
                while_doing: "expanding proxies".into(),
                message: format!("{} proxies overflowed the vertex buffer", sum(4)),
            });
        }
        let stats = RasterStats {
            culled: sum(0),
            drawn: sum(1),
            special: sum(2),
            seam_copies: sum(3),
            splatted: sum(6),
            vertices: sum(5),
            batches: self.batches,
        };
        // The work buffers are no longer needed, and each eye's textures go as soon as its
        // frame is read back: the peak while reading stays near one eye's read-back.
        drop((self.splat_keys, self.vertices, self.query));
        let mut frames: Vec<Frame> = self
            .targets
            .into_iter()
            .map(|t| t.read(ctx))
            .collect::<Result<_, _>>()?;
        let rendered = if frames.len() == 2 {
            let right = frames.pop().expect("two frames");
            let left = frames.pop().expect("two frames");
            Rendered::Stereo { left, right }
        } else {
            Rendered::Mono(frames.pop().expect("one frame"))
        };
        Ok((rendered, stats, timing))
    }
}
