//! WGSL composition and binding helpers. A module is the generated constants prelude, the
//! math files (which mirror `src/projection` and `src/render/shading.rs` file for file) and
//! a pipeline's own files, which that pipeline's Rust module includes.

use super::constants::wgsl_prelude;

/// `shaders/camera.wgsl`.
pub const CAMERA: &str = include_str!("../../shaders/camera.wgsl");
/// `shaders/equirect.wgsl`.
pub const EQUIRECT: &str = include_str!("../../shaders/equirect.wgsl");
/// `shaders/pole_merge.wgsl`.
pub const POLE_MERGE: &str = include_str!("../../shaders/pole_merge.wgsl");
/// `shaders/ods.wgsl`.
pub const ODS: &str = include_str!("../../shaders/ods.wgsl");
/// `shaders/depth_map.wgsl`: each sphere's own ODS radius under `--depth-map`.
pub const DEPTH_MAP: &str = include_str!("../../shaders/depth_map.wgsl");
/// `shaders/sphere_bounds.wgsl`: the box of a sphere's image.
pub const SPHERE_BOUNDS: &str = include_str!("../../shaders/sphere_bounds.wgsl");
/// `shaders/projection.wgsl`: the ray of an image position in each projection.
pub const PROJECTION: &str = include_str!("../../shaders/projection.wgsl");
/// `shaders/image_bounds.wgsl`: the pixel rectangles of a sphere's image.
pub const IMAGE_BOUNDS: &str = include_str!("../../shaders/image_bounds.wgsl");
/// `shaders/params.wgsl`: the per-batch parameters.
pub const PARAMS: &str = include_str!("../../shaders/params.wgsl");
/// `shaders/chunk.wgsl`: the point records.
pub const CHUNK: &str = include_str!("../../shaders/chunk.wgsl");
/// `shaders/shading.wgsl`.
pub const SHADING: &str = include_str!("../../shaders/shading.wgsl");
/// `shaders/sphere.wgsl`: the ray-sphere intersection.
pub const SPHERE: &str = include_str!("../../shaders/sphere.wgsl");

/// The constants prelude and the projection math every pipeline needs (the ODS ray and the
/// ray of an image position), followed by `parts`.
pub fn compose(parts: &[&str]) -> String {
    let mut s = wgsl_prelude();
    for p in [CAMERA, EQUIRECT, POLE_MERGE, ODS, DEPTH_MAP, PROJECTION]
        .iter()
        .chain(parts)
    {
        s.push('\n');
        s.push_str(p);
    }
    s
}

/// A WGSL module named `label`.
pub fn module(device: &wgpu::Device, label: &str, source: String) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// What a rasterizer pipeline is compiled from: its module, the pixel trigonometry's layout
/// (bind group 1), the pipeline constants and the pipeline cache.
pub struct PipelineSource<'a> {
    /// The composed module.
    pub module: &'a wgpu::ShaderModule,
    /// Layout of bind group 1 (`src/raster/pixel_trig.rs`).
    pub trig: &'a wgpu::BindGroupLayout,
    /// Pipeline-overridable constants (`src/raster/specialisation.rs`).
    pub constants: &'a [(&'a str, f64)],
    /// The driver's pipeline cache, when there is one.
    pub cache: Option<&'a wgpu::PipelineCache>,
}

/// Compilation options that set the pipeline-overridable `constants`.
pub fn options<'a>(constants: &'a [(&'a str, f64)]) -> wgpu::PipelineCompilationOptions<'a> {
    wgpu::PipelineCompilationOptions {
        constants,
        ..Default::default()
    }
}

/// Layout entry of the buffer at `binding`, visible to `stages`.
pub fn buffer_layout(
    binding: u32,
    stages: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Layout entries 0 to 2 of a pipeline that reads a chunk: the `Params` buffer (seen by
/// `params_stages`), the points and the colours (seen by `stages`).
pub fn chunk_layout(
    params_stages: wgpu::ShaderStages,
    stages: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    use wgpu::BufferBindingType::Storage;
    let read = Storage { read_only: true };
    vec![
        buffer_layout(0, params_stages, read),
        buffer_layout(1, stages, read),
        buffer_layout(2, stages, read),
    ]
}

/// A bind group for [`chunk_layout`] plus `keys` at binding 3 when given: the `Params`
/// buffer, the chunk's points and colours.
pub fn bind_chunk(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    [params, points, colors]: [&wgpu::Buffer; 3],
    keys: Option<&wgpu::Buffer>,
) -> wgpu::BindGroup {
    let mut entries = vec![bind(0, params), bind(1, points), bind(2, colors)];
    entries.extend(keys.map(|k| bind(3, k)));
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A compute pipeline `label` running `entry_point` of `src`, with bind group 0 laid out by
/// `entries` and the pixel trigonometry as group 1.
pub fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    src: &PipelineSource<'_>,
    entry_point: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    });
    let pipeline = compute_pipeline_with(device, label, src, entry_point, &layout);
    (layout, pipeline)
}

/// A compute pipeline of `src`'s `entry_point` over an existing group-0 `layout` (so the
/// bind groups of another pipeline serve it), with the pixel trigonometry as group 1.
pub fn compute_pipeline_with(
    device: &wgpu::Device,
    label: &str,
    src: &PipelineSource<'_>,
    entry_point: &str,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout), Some(src.trig)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module: src.module,
        entry_point: Some(entry_point),
        compilation_options: options(src.constants),
        cache: src.cache,
    })
}

/// Records one compute pass `label` of `pipeline` over `workgroups`, with `bind_group` as
/// group 0 and the pixel trigonometry `trig` as group 1.
pub fn dispatch_compute(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    [bind_group, trig]: [&wgpu::BindGroup; 2],
    [x, y]: [u32; 2],
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    pass.set_bind_group(1, trig, &[]);
    pass.dispatch_workgroups(x, y, 1);
}

/// `buffer`, whole, at `binding`.
pub fn bind(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// The members of WGSL struct `name` in `source` as (name, byte offset), and its size, as
/// naga lays it out: a Rust mirror must match it.
#[cfg(test)]
pub(crate) fn wgsl_struct_layout(source: &str, name: &str) -> (Vec<(String, u32)>, u32) {
    let module = wgpu::naga::front::wgsl::parse_str(source).expect("WGSL parses");
    let ty = module
        .types
        .iter()
        .map(|(_, t)| t)
        .find(|t| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("struct {name} is not declared"));
    match &ty.inner {
        wgpu::naga::TypeInner::Struct { members, span } => {
            let members = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            (members, *span)
        }
        other => panic!("{name} is {other:?}"),
    }
}

/// The listed fields of a Rust struct as (name, byte offset), to compare with
/// [`wgsl_struct_layout`].
#[cfg(test)]
macro_rules! field_offsets {
    ($t:ty: $($field:ident),* $(,)?) => {
        vec![$((stringify!($field).to_string(), std::mem::offset_of!($t, $field) as u32)),*]
    };
}
#[cfg(test)]
pub(crate) use field_offsets;
