//! The deferred shading of the keyed path (`shaders/splat_shade.wgsl`): under a lit shading
//! the splat and the keyed draws keep each pixel's nearest hit as a point index
//! (`shaders/splat_key.wgsl`), and this compute pass shades each such pixel once, after each
//! chunk, into its key's colour.

use super::constants::SHADE_WORKGROUP_SIDE;
use super::imposter::{IMPOSTER, SHADE_HIT};
use super::pixel_trig::PIXEL_TRIG;
use super::shaders::{self, CHUNK, PARAMS, SHADING, SPHERE};

/// `shaders/splat_shade.wgsl`.
const SPLAT_SHADE: &str = include_str!("../../shaders/splat_shade.wgsl");

/// Source of the deferred-shading module: the imposter module (for its pixel rays and
/// shading) and the pass.
pub fn source() -> String {
    shaders::compose(&[
        PARAMS,
        PIXEL_TRIG,
        CHUNK,
        SHADING,
        SPHERE,
        SHADE_HIT,
        IMPOSTER,
        SPLAT_SHADE,
    ])
}

/// The deferred-shading pipeline and its bind group layout.
pub struct ShadePipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ShadePipeline {
    /// Compiles the pipeline from `src`.
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>) -> Self {
        use wgpu::ShaderStages as S;
        let mut entries = shaders::chunk_layout(S::COMPUTE, S::COMPUTE);
        let keys = wgpu::BufferBindingType::Storage { read_only: false };
        entries.push(shaders::buffer_layout(3, S::COMPUTE, keys));
        let (layout, pipeline) =
            shaders::compute_pipeline(device, "deferred shading", src, "shade_keys", &entries);
        ShadePipeline { layout, pipeline }
    }

    /// Binds the `Params` buffer, a chunk's points and colours, and an eye's keys.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        points: &wgpu::Buffer,
        colors: &wgpu::Buffer,
        keys: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let chunk = [params, points, colors];
        shaders::bind_chunk(device, "deferred shading", &self.layout, chunk, Some(keys))
    }

    /// Records the pass over a `width x height` eye.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        trig: &wgpu::BindGroup,
        (width, height): (u32, u32),
    ) {
        let groups = [
            width.div_ceil(SHADE_WORKGROUP_SIDE),
            height.div_ceil(SHADE_WORKGROUP_SIDE),
        ];
        let groups_of = [bind_group, trig];
        shaders::dispatch_compute(
            encoder,
            "deferred shading",
            &self.pipeline,
            groups_of,
            groups,
        );
    }
}
