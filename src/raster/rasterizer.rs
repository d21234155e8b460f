//! The rasterizer: one device, its shader modules and the pipelines compiled from them,
//! reused across frames. Frames ([`super::RasterFrame`]) borrow it.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::constants::SHADING_UNLIT;
use super::context::GpuContext;
use super::error::RasterError;
use super::expand::ExpandPipeline;
use super::frame_buffers::Spare;
use super::imposter::ImposterPipeline;
use super::lock::lock;
use super::pipeline_cache::{CacheStatus, PipelineCache};
use super::pixel_trig;
use super::shaders;
use super::sizing::{DeviceCaps, Knobs, points_per_chunk};
use super::specialisation::Specialisation;
use super::splat::{DEFAULT_PAIR_SPLAT_LIMIT, DEFAULT_SPLAT_LIMIT};
use super::splat_shade::ShadePipeline;
use super::tile_resolve::ResolvePipeline;
use crate::frame::Rendered;

/// The pipelines a frame draws with, compiled for one [`Specialisation`] and path.
pub(crate) struct Pipelines {
    pub(crate) spec: Specialisation,
    pub(crate) expand: ExpandPipeline,
    /// Keyed on the keyed path ([`super::splat`]), else shading into render targets.
    pub(crate) imposter: ImposterPipeline,
    /// On the keyed path under a lit shading only.
    pub(crate) shade: Option<ShadePipeline>,
    /// On the keyed path only.
    pub(crate) resolve: Option<ResolvePipeline>,
}

/// The shader modules every specialisation is compiled from.
struct Modules {
    expand: wgpu::ShaderModule,
    imposter: wgpu::ShaderModule,
    shade: wgpu::ShaderModule,
    resolve: wgpu::ShaderModule,
}

/// A GPU imposter-sphere rasterizer bound to one device; reusable across renders.
pub struct Rasterizer {
    pub(crate) ctx: GpuContext,
    modules: Modules,
    /// Layout of the pixel trigonometry every pipeline binds as group 1.
    pub(crate) trig_layout: wgpu::BindGroupLayout,
    /// Pipelines compiled so far, by the modes they serve and whether they are keyed: only
    /// the modes a run draws.
    pipelines: Mutex<HashMap<(Specialisation, bool), Arc<Pipelines>>>,
    cache: Mutex<PipelineCache>,
    /// The last frame's buffers, for the next frame of its shape.
    pub(crate) spare: Mutex<Spare>,
    knobs: Knobs,
    pipeline_cache: CacheStatus,
}

impl Rasterizer {
    /// Creates the device and its shader modules and opens the on-disk pipeline cache
    /// ([`super::pipeline_cache`]) when the backend has one. Pipelines are compiled when a
    /// frame first needs them.
    pub fn new() -> Result<Self, RasterError> {
        let ctx = GpuContext::new()?;
        let device = &ctx.device;
        let sources = [
            super::expand::source(ctx.int64_atomics),
            super::imposter::source(ctx.int64_atomics),
            super::splat_shade::source(),
            super::tile_resolve::source(),
        ];
        let hashed: Vec<&str> = sources.iter().map(String::as_str).collect();
        let cache = PipelineCache::open(device, &ctx.adapter_info, ctx.pipeline_cache, &hashed);
        let [expand, imposter, shade, resolve] = sources;
        let (modules, trig_layout) = ctx.scoped("loading the rasterizer shaders", || {
            let modules = Modules {
                expand: shaders::module(device, "expand.wgsl", expand),
                imposter: shaders::module(device, "imposter.wgsl", imposter),
                shade: shaders::module(device, "splat_shade.wgsl", shade),
                resolve: shaders::module(device, "tile_resolve.wgsl", resolve),
            };
            (modules, pixel_trig::layout(device))
        })?;
        let pipeline_cache = cache.status().clone();
        Ok(Rasterizer {
            ctx,
            modules,
            trig_layout,
            pipelines: Mutex::new(HashMap::new()),
            cache: Mutex::new(cache),
            spare: Mutex::new(Spare::default()),
            knobs: Knobs {
                splat_limit: DEFAULT_SPLAT_LIMIT,
                pair_splat_limit: DEFAULT_PAIR_SPLAT_LIMIT,
                batch_limit: None,
                skip_hidden_pieces: true,
            },
            pipeline_cache,
        })
    }

    /// The pipelines for `spec`, `keyed` or not, compiled (and the pipeline cache saved) on
    /// first use.
    pub(crate) fn pipelines(
        &self,
        spec: Specialisation,
        keyed: bool,
    ) -> Result<Arc<Pipelines>, RasterError> {
        let mut compiled = lock(&self.pipelines);
        if let Some(p) = compiled.get(&(spec, keyed)) {
            return Ok(p.clone());
        }
        let mut cache = lock(&self.cache);
        let device = &self.ctx.device;
        let constants = spec.constants();
        let m = &self.modules;
        let pipelines = self.ctx.scoped("compiling the rasterizer shaders", || {
            let src = |module| shaders::PipelineSource {
                module,
                trig: &self.trig_layout,
                constants: &constants,
                cache: cache.cache.as_ref(),
            };
            Pipelines {
                spec,
                expand: ExpandPipeline::new(
                    device,
                    &src(&m.expand),
                    keyed,
                    keyed && spec.splats_pairs(),
                ),
                imposter: ImposterPipeline::new(device, &src(&m.imposter), keyed),
                shade: (keyed && spec.shading != SHADING_UNLIT)
                    .then(|| ShadePipeline::new(device, &src(&m.shade))),
                resolve: keyed.then(|| ResolvePipeline::new(device, &src(&m.resolve))),
            }
        })?;
        cache.save();
        let pipelines = Arc::new(pipelines);
        compiled.insert((spec, keyed), pipelines.clone());
        Ok(pipelines)
    }

    /// How many sets of pipelines (one per combination of projection, eyes, eye model, ODS
    /// offset, depth map, proxy, imposter and shading, keyed or not) have been compiled so
    /// far.
    pub fn compiled_pipelines(&self) -> usize {
        lock(&self.pipelines).len()
    }

    /// Caps the points per expand/draw batch (default: as many as the vertex buffer holds).
    /// Public for tests: smaller batches exercise the batched path; results must not change.
    pub fn set_batch_limit(&mut self, points: Option<u32>) {
        self.knobs.batch_limit = points;
    }

    /// Whether [`Rasterizer::render_gathered`] skips pieces that nearer ones hide whole (on by
    /// default). Public for tests and benchmarks: results must not change.
    pub fn set_skip_hidden_pieces(&mut self, skip: bool) {
        self.knobs.skip_hidden_pieces = skip;
    }

    /// Sets the largest sphere (pixels per side of its bounds) that the compute splat ray
    /// casts instead of drawing, for one eye's splat and an ODS pair's alike (by default
    /// [`DEFAULT_SPLAT_LIMIT`] and [`DEFAULT_PAIR_SPLAT_LIMIT`]); 0 draws every sphere. The
    /// splat runs only for ray-cast imposters on analytic bounds, on devices with 64-bit
    /// atomics; results must not change.
    pub fn set_splat_limit(&mut self, pixels: u32) {
        self.knobs.splat_limit = pixels;
        self.knobs.pair_splat_limit = pixels;
    }

    /// Keeps the GPU buffers of up to `shapes` frame shapes (image size, eye count) between
    /// frames instead of one, so that frames alternating between shapes do not allocate
    /// afresh; returns the previous allowance. Each kept shape holds its images' memory.
    pub fn keep_frame_shapes(&self, shapes: usize) -> usize {
        Spare::set_shapes(&self.spare, shapes)
    }

    /// Hands back a render's frames once the caller is done with them: the next frames of their
    /// size are read back into their memory. Worth it in loops over many frames; at most two
    /// frames per kept shape ([`Rasterizer::keep_frame_shapes`]) are held.
    pub fn recycle(&self, rendered: Rendered) {
        let frames = match rendered {
            Rendered::Mono(f) => vec![f],
            Rendered::Stereo { left, right } => vec![left, right],
        };
        Spare::recycle(&self.spare, frames);
    }

    /// How many sets of frame buffers this rasterizer has allocated (public for tests, which
    /// check that frames reuse them).
    pub fn frame_buffers_allocated(&self) -> u64 {
        Spare::allocated(&self.spare)
    }

    /// True when this device can run the compute splat (public for tests, which check the
    /// splat against drawing).
    pub fn can_splat(&self) -> bool {
        self.ctx.int64_atomics
    }

    /// What the on-disk pipeline cache did when this rasterizer started.
    pub fn pipeline_cache(&self) -> &CacheStatus {
        &self.pipeline_cache
    }

    /// The adapter's name and backend.
    pub fn adapter_name(&self) -> &str {
        &self.ctx.adapter_name
    }

    /// True on a software adapter (the CPU runs the shaders: lavapipe, llvmpipe).
    pub fn is_software(&self) -> bool {
        self.ctx.adapter_info.device_type == wgpu::DeviceType::Cpu
    }

    /// Widest equirectangular image (pixels per eye) the adapter's textures allow.
    pub fn max_image_width(&self) -> u32 {
        self.ctx.limits.max_texture_dimension_2d
    }

    /// What the device allows, for sizing.
    pub(crate) fn caps(&self) -> DeviceCaps {
        DeviceCaps::new(&self.ctx.limits, self.ctx.int64_atomics)
    }

    /// The batch and splat knobs.
    pub(crate) fn knobs(&self) -> &Knobs {
        &self.knobs
    }

    /// Points one GPU chunk holds on this device.
    pub(crate) fn points_per_chunk(&self) -> u64 {
        points_per_chunk(&self.caps())
    }
}
