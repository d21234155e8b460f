//! The expand compute pipeline and the imposter render pipeline.

use super::context::GpuContext;
use super::error::RasterError;
use super::shaders;

/// Colour target: sRGB bytes stored as they are.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Distance target: metres along the ray.
pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Depth-test buffer (logarithmic depth written by the fragment stage).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Bytes per expanded vertex: position (2 x f32), packed billboard coordinates, point index.
pub const VERTEX_BYTES: u64 = 16;
/// Invocations per expand workgroup (matches `@workgroup_size` in expand.wgsl).
pub const EXPAND_WORKGROUP: u32 = 256;

/// Both pipelines.
pub struct Pipelines {
    /// Point expansion.
    pub expand: wgpu::ComputePipeline,
    /// Imposter rasterization.
    pub imposter: wgpu::RenderPipeline,
    /// Full-image pass merging the compute splat's nearest hits into the targets.
    pub resolve: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Compiles the shaders and builds both pipelines.
    pub fn new(ctx: &GpuContext) -> Result<Self, RasterError> {
        let device = &ctx.device;
        ctx.scoped("compiling the rasterizer shaders", || {
            let expand_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("expand.wgsl"),
                source: wgpu::ShaderSource::Wgsl(shaders::expand_source(ctx.int64_atomics).into()),
            });
            let imposter_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("imposter.wgsl"),
                source: wgpu::ShaderSource::Wgsl(shaders::imposter_source().into()),
            });
            let expand = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("expand"),
                layout: None,
                module: &expand_module,
                entry_point: Some("expand"),
                compilation_options: Default::default(),
                cache: None,
            });
            let attributes = wgpu::vertex_attr_array![0 => Float32x2, 1 => Uint32, 2 => Uint32];
            let imposter = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("imposter"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &imposter_module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: VERTEX_BYTES,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(depth_test()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &imposter_module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(COLOR_FORMAT.into()), Some(DISTANCE_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            });
            let resolve = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("splat resolve"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &imposter_module,
                    entry_point: Some("vs_fullscreen"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(depth_test()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &imposter_module,
                    entry_point: Some("fs_resolve"),
                    compilation_options: Default::default(),
                    targets: &[Some(COLOR_FORMAT.into()), Some(DISTANCE_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            });
            Pipelines {
                expand,
                imposter,
                resolve,
            }
        })
    }
}

/// Nearest fragment wins; both render pipelines write the logarithmic depth they test.
fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}
