//! The compute splat: small spheres are ray cast by the expand pass (`shaders/splat.wgsl`,
//! or `splat_off.wgsl` without 64-bit atomics) into one nearest-hit key per pixel, and a
//! full-image render pass (`shaders/splat_resolve.wgsl`) merges the keys into the targets.

use super::imposter::IMPOSTER;
use super::pixel_trig::PIXEL_TRIG;
use super::shaders::{self, CHUNK, PARAMS, SHADING, SPHERE};
use super::targets;

/// `shaders/splat.wgsl`: the splat (64-bit atomics).
const SPLAT: &str = include_str!("../../shaders/splat.wgsl");
/// `shaders/splat_off.wgsl`: its stand-in without 64-bit atomics.
const SPLAT_OFF: &str = include_str!("../../shaders/splat_off.wgsl");
/// `shaders/splat_resolve.wgsl`.
const SPLAT_RESOLVE: &str = include_str!("../../shaders/splat_resolve.wgsl");

/// Default largest sphere the compute splat ray casts, in pixels per side of its bounds;
/// larger ones are drawn.
pub const DEFAULT_SPLAT_LIMIT: u32 = 16;

/// The expand module's splat part: the splat when the device has 64-bit atomics, else a
/// stand-in that splats nothing.
pub fn expand_part(int64_atomics: bool) -> &'static str {
    if int64_atomics { SPLAT } else { SPLAT_OFF }
}

/// Source of the resolve module: the imposter module (for its shading) and the resolve pass.
pub fn resolve_source() -> String {
    shaders::compose(&[
        PARAMS,
        PIXEL_TRIG,
        CHUNK,
        SHADING,
        SPHERE,
        IMPOSTER,
        SPLAT_RESOLVE,
    ])
}

/// Allocates the splat key buffer of `bytes` (one `u64` per pixel of one eye).
pub fn key_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("splat keys"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The resolve pipeline and its bind group layout.
pub struct ResolvePipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ResolvePipeline {
    /// Compiles the pipeline from `src`.
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>) -> Self {
        use wgpu::BufferBindingType::{Storage, Uniform};
        use wgpu::ShaderStages as S;
        let read = Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat resolve"),
            entries: &[
                shaders::buffer_layout(0, S::FRAGMENT, Uniform),
                shaders::buffer_layout(1, S::FRAGMENT, read),
                shaders::buffer_layout(2, S::FRAGMENT, read),
                shaders::buffer_layout(3, S::FRAGMENT, read),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("splat resolve"),
            bind_group_layouts: &[Some(&layout), Some(src.trig)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("splat resolve"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: src.module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: shaders::options(src.constants),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(targets::depth_test()),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: src.module,
                entry_point: Some("fs_resolve"),
                compilation_options: shaders::options(src.constants),
                targets: &targets::COLOR_TARGETS,
            }),
            multiview_mask: None,
            cache: src.cache,
        });
        ResolvePipeline { layout, pipeline }
    }

    /// Binds the `Params` uniform, a chunk's points and colours, and the splat keys.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        points: &wgpu::Buffer,
        colors: &wgpu::Buffer,
        keys: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("splat resolve"),
            layout: &self.layout,
            entries: &[
                shaders::bind(0, params),
                shaders::bind(1, points),
                shaders::bind(2, colors),
                shaders::bind(3, keys),
            ],
        })
    }

    /// Records the full-image pass that merges the keys.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind_group: &wgpu::BindGroup,
        trig: &wgpu::BindGroup,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_bind_group(1, trig, &[]);
        pass.draw(0..3, 0..1);
    }
}
