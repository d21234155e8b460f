//! The imposter render pipeline (`shaders/imposter.wgsl`): rasterizes the expanded proxies of
//! one eye and shades each fragment as the sphere it stands for, into render targets or, keyed
//! (`shaders/imposter_key.wgsl`), into its pixel's key (see [`super::splat`]).

use super::expand::ExpandedVertex;
use super::pixel_trig::PIXEL_TRIG;
use super::shaders::{self, CHUNK, PARAMS, SHADING, SPHERE};
use super::splat::SPLAT_KEY;
use super::targets;

/// `shaders/imposter.wgsl`.
pub const IMPOSTER: &str = include_str!("../../shaders/imposter.wgsl");
/// `shaders/shade_hit.wgsl`: the shading of a hit, shared with the deferred shading.
pub const SHADE_HIT: &str = include_str!("../../shaders/shade_hit.wgsl");
/// `shaders/imposter_key.wgsl`: the keyed fragment stage.
const IMPOSTER_KEY: &str = include_str!("../../shaders/imposter_key.wgsl");

/// Source of the imposter module; with `int64_atomics`, the keyed fragment stage too.
pub fn source(int64_atomics: bool) -> String {
    let mut parts = vec![
        PARAMS, PIXEL_TRIG, CHUNK, SHADING, SPHERE, SHADE_HIT, IMPOSTER,
    ];
    if int64_atomics {
        parts.extend([SPLAT_KEY, IMPOSTER_KEY]);
    }
    shaders::compose(&parts)
}

/// The imposter pipeline and its bind group layout.
pub struct ImposterPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ImposterPipeline {
    /// Compiles the pipeline from `src`: shading into [`targets::EyeTargets`], or `keyed`,
    /// keeping nearest-hit keys (the module must have the keyed stage).
    pub fn new(device: &wgpu::Device, src: &shaders::PipelineSource<'_>, keyed: bool) -> Self {
        use wgpu::ShaderStages as S;
        // The keyed vertex stage fetches each sphere and its colour for its fragments.
        let chunk_stages = if keyed {
            S::VERTEX_FRAGMENT
        } else {
            S::FRAGMENT
        };
        let mut entries = shaders::chunk_layout(S::VERTEX_FRAGMENT, chunk_stages);
        if keyed {
            let keys = wgpu::BufferBindingType::Storage { read_only: false };
            entries.push(shaders::buffer_layout(3, S::FRAGMENT, keys));
        }
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("imposter"),
            entries: &entries,
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
                entry_point: Some(if keyed { "vs_key" } else { "vs" }),
                compilation_options: shaders::options(src.constants),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: size_of::<ExpandedVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: (!keyed).then(targets::depth_test),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: src.module,
                entry_point: Some(if keyed { "fs_key" } else { "fs" }),
                compilation_options: shaders::options(src.constants),
                targets: if keyed {
                    &targets::KEYED_TARGETS
                } else {
                    &targets::COLOR_TARGETS
                },
            }),
            multiview_mask: None,
            cache: src.cache,
        });
        ImposterPipeline { layout, pipeline }
    }

    /// Binds the `Params` buffer, a chunk's points and colours, and for a keyed pipeline the
    /// keys.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        points: &wgpu::Buffer,
        colors: &wgpu::Buffer,
        keys: Option<&wgpu::Buffer>,
    ) -> wgpu::BindGroup {
        let chunk = [params, points, colors];
        shaders::bind_chunk(device, "imposter", &self.layout, chunk, keys)
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
