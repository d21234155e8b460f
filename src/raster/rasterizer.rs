//! The rasterizer: one device and its compiled pipelines, reused across frames. Frames
//! ([`super::RasterFrame`]) borrow it.

use super::context::GpuContext;
use super::error::RasterError;
use super::expand::ExpandPipeline;
use super::imposter::ImposterPipeline;
use super::pipeline_cache::{CacheStatus, PipelineCache};
use super::sizing::{DeviceCaps, Knobs, points_per_chunk};
use super::splat::{DEFAULT_SPLAT_LIMIT, ResolvePipeline};

/// A GPU imposter-sphere rasterizer bound to one device; reusable across renders.
pub struct Rasterizer {
    pub(crate) ctx: GpuContext,
    pub(crate) expand: ExpandPipeline,
    pub(crate) imposter: ImposterPipeline,
    pub(crate) resolve: ResolvePipeline,
    knobs: Knobs,
    pipeline_cache: CacheStatus,
}

impl Rasterizer {
    /// Creates the device and compiles the pipelines, through the on-disk pipeline cache
    /// ([`super::pipeline_cache`]) when the backend has one.
    pub fn new() -> Result<Self, RasterError> {
        let ctx = GpuContext::new()?;
        let device = &ctx.device;
        let sources = [
            super::expand::source(ctx.int64_atomics),
            super::imposter::source(),
            super::splat::resolve_source(),
        ];
        let sources: Vec<&str> = sources.iter().map(String::as_str).collect();
        let mut cache =
            PipelineCache::open(device, &ctx.adapter_info, ctx.pipeline_cache, &sources);
        let (expand, imposter, resolve) = ctx.scoped("compiling the rasterizer shaders", || {
            let c = cache.cache.as_ref();
            (
                ExpandPipeline::new(device, ctx.int64_atomics, c),
                ImposterPipeline::new(device, c),
                ResolvePipeline::new(device, c),
            )
        })?;
        cache.save();
        Ok(Rasterizer {
            ctx,
            expand,
            imposter,
            resolve,
            knobs: Knobs {
                splat_limit: DEFAULT_SPLAT_LIMIT,
                batch_limit: None,
            },
            pipeline_cache: cache.status().clone(),
        })
    }

    /// Caps the points per expand/draw batch (default: as many as the vertex buffer holds).
    /// Public for tests: smaller batches exercise the batched path; results must not change.
    pub fn set_batch_limit(&mut self, points: Option<u32>) {
        self.knobs.batch_limit = points;
    }

    /// Sets the largest sphere (pixels per side of its bounds) that the compute splat ray
    /// casts instead of drawing; 0 draws every sphere. The splat runs only for ray-cast
    /// imposters on analytic bounds, on devices with 64-bit atomics; results must not change.
    pub fn set_splat_limit(&mut self, pixels: u32) {
        self.knobs.splat_limit = pixels;
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
