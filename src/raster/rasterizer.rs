//! The rasterizer: uploads a scene in chunks, expands and draws each batch per eye through
//! one depth buffer, and reads the frames back.

use std::time::Instant;

use indicatif::ProgressBar;

use crate::frame::{Frame, Rendered};
use crate::render::{RenderSettings, base_colors};
use crate::scene::Scene;

use super::context::GpuContext;
use super::error::RasterError;
use super::params::{Params, max_vertices_per_point};
use super::pipelines::{EXPAND_WORKGROUP, Pipelines, VERTEX_BYTES};
use super::targets::{EyeTargets, map_read};

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

const STATS_PER_EYE: usize = 8;
const MAX_EYES: usize = 2;
/// Default largest sphere the compute splat ray casts, in pixels per side of its bounds;
/// larger ones are drawn.
pub const DEFAULT_SPLAT_LIMIT: u32 = 16;

/// A GPU imposter-sphere rasterizer bound to one device; reusable across renders.
pub struct Rasterizer {
    pub(crate) ctx: GpuContext,
    pipelines: Pipelines,
    batch_limit: Option<u32>,
    splat_limit: u32,
}

/// A scene's points and colours on the GPU, relative to one camera centre.
pub struct UploadedScene {
    chunks: Vec<Chunk>,
    camera_center: glam::DVec3,
    color: crate::render::ColorMode,
    points: u64,
}

struct Chunk {
    points: wgpu::Buffer,
    colors: wgpu::Buffer,
    len: u32,
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

    fn points_per_chunk(&self) -> u64 {
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
            let pts: Vec<[f32; 4]> = (start..end)
                .map(|i| {
                    let p = scene.positions[i].as_dvec3() - c;
                    [p.x as f32, p.y as f32, p.z as f32, scene.radii.get(i)]
                })
                .collect();
            let cols: Vec<u32> = colors[start..end]
                .iter()
                .map(|c| c[0] as u32 | (c[1] as u32) << 8 | (c[2] as u32) << 16)
                .collect();
            let chunk = self.ctx.scoped("uploading points", || {
                let make = |label, bytes: &[u8]| {
                    let buf = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: bytes.len() as u64,
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    self.ctx.queue.write_buffer(&buf, 0, bytes);
                    buf
                };
                Chunk {
                    points: make("points", bytemuck::cast_slice(&pts)),
                    colors: make("colors", bytemuck::cast_slice(&cols)),
                    len: (end - start) as u32,
                }
            })?;
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

    fn check_settings(
        &self,
        uploaded: &UploadedScene,
        settings: &RenderSettings,
    ) -> Result<(), RasterError> {
        if uploaded.camera_center != settings.camera.center || uploaded.color != settings.color {
            return Err(RasterError::Settings(
                "the scene was uploaded for another camera centre or colour mode".into(),
            ));
        }
        let img = settings.image;
        if img.width == 0 || img.height == 0 || img.width != 2 * img.height {
            return Err(RasterError::Settings(format!(
                "image {}x{} is not a 2:1 equirectangular size",
                img.width, img.height
            )));
        }
        if let crate::render::Proxy::Static(n) = settings.proxy
            && !(1..=64).contains(&n)
        {
            return Err(RasterError::Settings(format!(
                "static tessellation level {n} is outside 1..=64"
            )));
        }
        Ok(())
    }

    /// Seconds between the two timestamps of `query`, or `None` when they make no sense.
    fn read_timestamps(&self, query: &wgpu::QuerySet) -> Result<Option<f64>, RasterError> {
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
        self.check_settings(uploaded, settings)?;
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
            && settings.proxy == crate::render::Proxy::Bounds
            && settings.imposter == crate::render::Imposter::Raycast
            && splat_bytes
                <= ctx
                    .limits
                    .max_buffer_size
                    .min(ctx.limits.max_storage_buffer_binding_size);
        let splat_limit = if splat { self.splat_limit } else { 0 };
        // One key buffer per eye; a placeholder binding when the splat is off for this render.
        let splat_keys = ctx.scoped("allocating splat buffers", || {
            views
                .iter()
                .map(|_| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("splat keys"),
                        size: if splat { splat_bytes } else { 8 },
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                })
                .collect::<Vec<_>>()
        })?;

        let per_point = max_vertices_per_point(settings.proxy);
        let largest_chunk = uploaded
            .chunks
            .iter()
            .map(|c| c.len as u64)
            .max()
            .unwrap_or(1);
        let vertex_bytes_max = ctx
            .limits
            .max_buffer_size
            .min(ctx.limits.max_storage_buffer_binding_size)
            .min(128 << 20)
            // wgpu zero-fills a fresh buffer before its first use, every frame: no larger
            // than the biggest chunk needs. (Smaller still would cost more batches, and each
            // batch's submit and wait costs far more than the fill on lavapipe.)
            .min(largest_chunk.max(1) * per_point * VERTEX_BYTES);
        let vertex_capacity = vertex_bytes_max / VERTEX_BYTES;
        let max_groups = ctx.limits.max_compute_workgroups_per_dimension as u64;
        let batch = (vertex_capacity / per_point)
            .min(max_groups * EXPAND_WORKGROUP as u64)
            .min(self.batch_limit.map_or(u64::MAX, u64::from))
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

        // GPU timestamps: the start of the first expand pass and the end of the last draw.
        let query = self.ctx.timestamps.then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });
        let total_steps = uploaded
            .chunks
            .iter()
            .map(|c| c.len.div_ceil(batch as u32) as u64)
            .sum::<u64>()
            * views.len() as u64;
        let mut step = 0u64;

        let started = Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&stats_buf, 0, None);
        for keys in &splat_keys {
            encoder.clear_buffer(keys, 0, None);
        }
        for t in &targets {
            t.clear(&mut encoder);
        }
        ctx.queue.submit([encoder.finish()]);

        progress.set_length(uploaded.points * views.len() as u64);
        let mut batches = 0u64;
        for chunk in &uploaded.chunks {
            let (expand_bgs, draw_bg, resolve_bgs) = ctx.scoped("binding a chunk", || {
                fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
                    wgpu::BindGroupEntry {
                        binding,
                        resource: buffer.as_entire_binding(),
                    }
                }
                let expand_bgs: Vec<_> = splat_keys
                    .iter()
                    .map(|keys| {
                        let mut entries = vec![
                            entry(0, &params_buf),
                            entry(1, &chunk.points),
                            entry(3, &vertices),
                            entry(4, &args),
                            entry(5, &stats_buf),
                        ];
                        if ctx.int64_atomics {
                            entries.push(entry(6, keys));
                        }
                        device.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some("expand"),
                            layout: &self.pipelines.expand.get_bind_group_layout(0),
                            entries: &entries,
                        })
                    })
                    .collect();
                let resolve_bgs: Vec<_> = splat_keys
                    .iter()
                    .filter(|_| splat)
                    .map(|keys| {
                        device.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some("splat resolve"),
                            layout: &self.pipelines.resolve.get_bind_group_layout(0),
                            entries: &[
                                entry(0, &params_buf),
                                entry(1, &chunk.points),
                                entry(2, &chunk.colors),
                                entry(3, keys),
                            ],
                        })
                    })
                    .collect();
                let draw_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("imposters"),
                    layout: &self.pipelines.imposter.get_bind_group_layout(0),
                    entries: &[
                        entry(0, &params_buf),
                        entry(1, &chunk.points),
                        entry(2, &chunk.colors),
                    ],
                });
                (expand_bgs, draw_bg, resolve_bgs)
            })?;
            let mut first = 0u32;
            while first < chunk.len {
                let count = (chunk.len - first).min(batch as u32);
                for (eye, (view, target)) in views.iter().zip(&targets).enumerate() {
                    let params =
                        Params::new(view, settings, eye as u32, (first, count), vertex_capacity)
                            .with_splat_limit(splat_limit);
                    ctx.queue
                        .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
                    ctx.queue
                        .write_buffer(&args, 0, bytemuck::cast_slice(&[0u32, 1, 0, 0]));
                    let mut encoder = device.create_command_encoder(&Default::default());
                    // With the splat, the last resolve pass ends the frame instead.
                    let (first_step, last_step) = (step == 0, step + 1 == total_steps && !splat);
                    step += 1;
                    {
                        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                            label: Some("expand"),
                            timestamp_writes: query.as_ref().filter(|_| first_step).map(|q| {
                                wgpu::ComputePassTimestampWrites {
                                    query_set: q,
                                    beginning_of_pass_write_index: Some(0),
                                    end_of_pass_write_index: None,
                                }
                            }),
                        });
                        pass.set_pipeline(&self.pipelines.expand);
                        pass.set_bind_group(0, &expand_bgs[eye], &[]);
                        pass.dispatch_workgroups(count.div_ceil(EXPAND_WORKGROUP), 1, 1);
                    }
                    {
                        let writes = query.as_ref().filter(|_| last_step).map(|q| {
                            wgpu::RenderPassTimestampWrites {
                                query_set: q,
                                beginning_of_pass_write_index: None,
                                end_of_pass_write_index: Some(1),
                            }
                        });
                        let mut pass = target.begin_pass(&mut encoder, false, writes);
                        pass.set_pipeline(&self.pipelines.imposter);
                        pass.set_bind_group(0, &draw_bg, &[]);
                        pass.set_vertex_buffer(0, vertices.slice(..));
                        pass.draw_indirect(&args, 0);
                    }
                    ctx.queue.submit([encoder.finish()]);
                    // Keep the queue short so progress means something and memory stays flat.
                    ctx.wait("drawing imposters")?;
                    progress.inc(count as u64);
                    batches += 1;
                }
                first += count;
            }
            // Splat keys index this chunk's points: merge them before the next chunk.
            for (eye, ((view, target), bg)) in
                views.iter().zip(&targets).zip(&resolve_bgs).enumerate()
            {
                let params = Params::new(view, settings, eye as u32, (0, 0), vertex_capacity);
                ctx.queue
                    .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
                let last = std::ptr::eq(chunk, uploaded.chunks.last().expect("a chunk"))
                    && eye + 1 == views.len();
                let mut encoder = device.create_command_encoder(&Default::default());
                {
                    let writes =
                        query
                            .as_ref()
                            .filter(|_| last)
                            .map(|q| wgpu::RenderPassTimestampWrites {
                                query_set: q,
                                beginning_of_pass_write_index: None,
                                end_of_pass_write_index: Some(1),
                            });
                    let mut pass = target.begin_pass(&mut encoder, false, writes);
                    pass.set_pipeline(&self.pipelines.resolve);
                    pass.set_bind_group(0, bg, &[]);
                    pass.draw(0..3, 0..1);
                }
                encoder.clear_buffer(&splat_keys[eye], 0, None);
                ctx.queue.submit([encoder.finish()]);
                ctx.wait("resolving splatted spheres")?;
            }
        }
        ctx.wait("drawing imposters")?;
        let wall = started.elapsed().as_secs_f64();
        let gpu = match &query {
            Some(q) if total_steps > 0 => self.read_timestamps(q)?,
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

        let raw = map_read(
            ctx,
            &{
                let read = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("stats read-back"),
                    size: (STATS_PER_EYE * MAX_EYES * 4) as u64,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                });
                let mut encoder = device.create_command_encoder(&Default::default());
                encoder.copy_buffer_to_buffer(&stats_buf, 0, &read, 0, None);
                ctx.queue.submit([encoder.finish()]);
                read
            },
            "reading back statistics",
        )?;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&raw);
        let sum = |k: usize| -> u64 {
            (0..views.len())
                .map(|e| words[e * STATS_PER_EYE + k] as u64)
                .sum()
        };
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
            batches,
        };
        let mut frames: Vec<Frame> = targets
            .iter()
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
