//! The imposter render pipeline (`shaders/imposter.wgsl`): rasterizes the expanded proxies of
//! one eye and shades each fragment as the sphere it stands for.

use super::expand::ExpandedVertex;
use super::pixel_trig::PIXEL_TRIG;
use super::shaders::{self, CHUNK, PARAMS, SHADING, SPHERE};
use super::targets;

/// `shaders/imposter.wgsl`.
pub const IMPOSTER: &str = include_str!("../../shaders/imposter.wgsl");

/// Source of the imposter module.
pub fn source() -> String {
    shaders::compose(&[PARAMS, PIXEL_TRIG, CHUNK, SHADING, SPHERE, IMPOSTER])
}

/// The imposter pipeline and its bind group layout.
pub struct ImposterPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ImposterPipeline {
    /// Compiles the pipeline from `src`.
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>) -> Self {
        use wgpu::BufferBindingType::{Storage, Uniform};
        use wgpu::ShaderStages as S;
        let read = Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("imposter"),
            entries: &[
                shaders::buffer_layout(0, S::VERTEX_FRAGMENT, Uniform),
                shaders::buffer_layout(1, S::FRAGMENT, read),
                shaders::buffer_layout(2, S::FRAGMENT, read),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("imposter"),
            bind_group_layouts: &[Some(&layout), Some(src.trig)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x2, 1 => Uint32, 2 => Uint32];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("imposter"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: src.module,
                entry_point: Some("vs"),
                compilation_options: shaders::options(src.constants),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: size_of::<ExpandedVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(targets::depth_test()),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: src.module,
                entry_point: Some("fs"),
                compilation_options: shaders::options(src.constants),
                targets: &targets::COLOR_TARGETS,
            }),
            multiview_mask: None,
            cache: src.cache,
        });
        ImposterPipeline { layout, pipeline }
    }

    /// Binds the `Params` uniform and a chunk's points and colours.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        points: &wgpu::Buffer,
        colors: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("imposter"),
            layout: &self.layout,
            entries: &[
                shaders::bind(0, params),
                shaders::bind(1, points),
                shaders::bind(2, colors),
            ],
        })
    }

    /// Records the draw of the `vertices` the expand pass counted into `draw_args`.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind_group: &wgpu::BindGroup,
        trig: &wgpu::BindGroup,
        vertices: &wgpu::Buffer,
        draw_args: &wgpu::Buffer,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_bind_group(1, trig, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.draw_indirect(draw_args, 0);
    }
}
