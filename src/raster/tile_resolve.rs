//! The tile resolve of the keyed path (`shaders/tile_resolve.wgsl`): between batches, raises
//! each occlusion tile of an eye to the distance of its farthest pixel once all its pixels
//! show a hit, so the spheres of later batches are skipped behind what earlier ones drew
//! together, not only behind one large sphere.

use super::constants::RESOLVE_WORKGROUP_SIDE;
use super::shaders::{self, PARAMS};
use super::splat::{TILES, tiles_along};

/// `shaders/tile_resolve.wgsl`.
const TILE_RESOLVE: &str = include_str!("../../shaders/tile_resolve.wgsl");

/// Source of the tile-resolve module.
pub fn source() -> String {
    shaders::compose(&[PARAMS, TILES, TILE_RESOLVE])
}

/// The tile-resolve pipeline and its bind group layout.
pub struct ResolvePipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ResolvePipeline {
    /// Compiles the pipeline from `src` (a [`source`] module).
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>) -> Self {
        use wgpu::BufferBindingType::Storage;
        let entry = |binding, ty| shaders::buffer_layout(binding, wgpu::ShaderStages::COMPUTE, ty);
        let entries = [
            entry(0, Storage { read_only: true }),
            entry(3, Storage { read_only: true }),
            entry(9, Storage { read_only: false }),
        ];
        let (layout, pipeline) =
            shaders::compute_pipeline(device, "tile resolve", src, "resolve_tiles", &entries);
        ResolvePipeline { layout, pipeline }
    }

    /// Binds the `Params` buffer and an eye's keys and occlusion tiles.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        keys: &wgpu::Buffer,
        tiles: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tile resolve"),
            layout: &self.layout,
            entries: &[
                shaders::bind(0, params),
                shaders::bind(3, keys),
                shaders::bind(9, tiles),
            ],
        })
    }

    /// Records the resolve of a `width x height` eye's tiles; `trig` fills bind group 1,
    /// which every rasterizer pipeline lays out.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        trig: &wgpu::BindGroup,
        (width, height): (u32, u32),
    ) {
        // Two dimensions: a wide image has more tiles than one may dispatch in a row.
        let tiles = |n: u32| tiles_along(n).div_ceil(RESOLVE_WORKGROUP_SIDE);
        let groups = [tiles(width), tiles(height)];
        let groups_of = [bind_group, trig];
        shaders::dispatch_compute(encoder, "tile resolve", &self.pipeline, groups_of, groups);
    }
}
