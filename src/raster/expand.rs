//! The expand compute pipeline (`shaders/expand.wgsl`): turns each point of a batch into
//! proxy triangles of one eye, or splats it (`shaders/splat.wgsl`), counting into the
//! statistics.

use bytemuck::{Pod, Zeroable};

use super::constants::EXPAND_WORKGROUP;
use super::pixel_trig::PIXEL_TRIG;
use super::shaders::{self, CHUNK, IMAGE_BOUNDS, PARAMS, SPHERE, SPHERE_BOUNDS};
use super::splat;

/// `shaders/expand.wgsl`.
const EXPAND: &str = include_str!("../../shaders/expand.wgsl");

/// One proxy vertex as the expand pass writes it and the imposter pipeline reads it (WGSL
/// `ExpandedVertex`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ExpandedVertex {
    /// Unwrapped equirect position, pixels.
    pub position: [f32; 2],
    /// Billboard coordinates in [-1, 1]^2, `pack2x16snorm`.
    pub uv: u32,
    /// Point index in the chunk, `| FORCE_RAYCAST` to ray cast it whatever the imposter.
    pub point: u32,
}

/// Indirect draw arguments (WGSL `DrawArgs`) before an expand pass: one instance of no
/// vertices yet (the pass counts them in).
pub fn empty_draw_args() -> wgpu::util::DrawIndirectArgs {
    wgpu::util::DrawIndirectArgs {
        vertex_count: 0,
        instance_count: 1,
        first_vertex: 0,
        first_instance: 0,
    }
}

/// Source of the expand module; `splat` appends the compute splat (the device must have
/// 64-bit atomics), else its stand-in.
pub fn source(splat: bool) -> String {
    shaders::compose(&[
        PARAMS,
        PIXEL_TRIG,
        CHUNK,
        SPHERE_BOUNDS,
        IMAGE_BOUNDS,
        EXPAND,
        SPHERE,
        &splat::expand_part(splat),
    ])
}

/// The buffers one expand dispatch binds.
pub struct ExpandBuffers<'a> {
    /// `Params` uniform.
    pub params: &'a wgpu::Buffer,
    /// The chunk's points.
    pub points: &'a wgpu::Buffer,
    /// [`ExpandedVertex`] output.
    pub vertices: &'a wgpu::Buffer,
    /// Indirect draw arguments (vertex count).
    pub draw_args: &'a wgpu::Buffer,
    /// Per-eye `EyeStats`.
    pub stats: &'a wgpu::Buffer,
    /// The eye's keys (bound only when the pipeline splats).
    pub splat_keys: &'a wgpu::Buffer,
    /// The chunk's colours (bound only when the pipeline splats, which shades).
    pub colors: &'a wgpu::Buffer,
}

/// The expand pipeline and its bind group layout.
pub struct ExpandPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    splat: bool,
}

impl ExpandPipeline {
    /// Compiles the pipeline from `src` (a [`source`] module); `splat` when the module
    /// includes the compute splat (needs 64-bit atomics).
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>, splat: bool) -> Self {
        use wgpu::BufferBindingType::{Storage, Uniform};
        let entry = |binding, ty| shaders::buffer_layout(binding, wgpu::ShaderStages::COMPUTE, ty);
        let rw = Storage { read_only: false };
        let mut entries = vec![
            entry(0, Uniform),
            entry(1, Storage { read_only: true }),
            entry(2, rw),
            entry(3, rw),
            entry(4, rw),
        ];
        if splat {
            entries.extend([entry(5, rw), entry(6, Storage { read_only: true })]);
        }
        let (layout, pipeline) =
            shaders::compute_pipeline(device, "expand", src, "expand", &entries);
        ExpandPipeline {
            layout,
            pipeline,
            splat,
        }
    }

    /// Binds `buffers` for [`ExpandPipeline::dispatch`].
    pub fn bind(&self, device: &wgpu::Device, buffers: &ExpandBuffers<'_>) -> wgpu::BindGroup {
        let b = buffers;
        let mut entries = vec![
            shaders::bind(0, b.params),
            shaders::bind(1, b.points),
            shaders::bind(2, b.vertices),
            shaders::bind(3, b.draw_args),
            shaders::bind(4, b.stats),
        ];
        if self.splat {
            entries.extend([shaders::bind(5, b.splat_keys), shaders::bind(6, b.colors)]);
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("expand"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records the expansion of `count` points (the batch of the bound `Params`); `trig`
    /// binds the pixel trigonometry.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        trig: &wgpu::BindGroup,
        count: u32,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("expand"),
            timestamp_writes,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_bind_group(1, trig, &[]);
        pass.dispatch_workgroups(count.div_ceil(EXPAND_WORKGROUP), 1, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::super::shaders::{field_offsets, wgsl_struct_layout};
    use super::*;

    #[test]
    fn the_vertex_and_draw_records_match_the_wgsl_structs() {
        let source = source(false);
        let rust = field_offsets!(ExpandedVertex: position, uv, point);
        let size = size_of::<ExpandedVertex>() as u32;
        assert_eq!(wgsl_struct_layout(&source, "ExpandedVertex"), (rust, size));
        let rust = field_offsets!(wgpu::util::DrawIndirectArgs: vertex_count, instance_count,
            first_vertex, first_instance);
        let size = size_of::<wgpu::util::DrawIndirectArgs>() as u32;
        assert_eq!(wgsl_struct_layout(&source, "DrawArgs"), (rust, size));
    }
}
