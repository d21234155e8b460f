//! The expand compute pipeline (`shaders/expand.wgsl`): turns each point of a batch into
//! proxy triangles of one eye, counting into the statistics. On the keyed path it is two
//! dispatches (`shaders/splat.wgsl`): one splats the small spheres and lists the rest, the
//! second, indirect, expands the listed ones. An ODS pair's eyes share the first
//! (`expand_splat_pair`): one dispatch splats each sphere for both.

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

/// Source of the expand module; `splat` appends the compute splat's entry points (the device
/// must have 64-bit atomics).
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
    /// `Params` buffer.
    pub params: &'a wgpu::Buffer,
    /// The chunk's points.
    pub points: &'a wgpu::Buffer,
    /// [`ExpandedVertex`] output.
    pub vertices: &'a wgpu::Buffer,
    /// Indirect draw arguments (vertex count).
    pub draw_args: &'a wgpu::Buffer,
    /// Per-eye `EyeStats`.
    pub stats: &'a wgpu::Buffer,
    /// On the keyed path: the eye's keys, the chunk's colours (the splat shades) and the
    /// list of points the splat leaves to draw.
    pub keyed: Option<KeyedBuffers<'a>>,
}

/// What the splat binds besides the expand pass's buffers.
pub struct KeyedBuffers<'a> {
    /// The eye's keys.
    pub keys: &'a wgpu::Buffer,
    /// The eye's occlusion tiles.
    pub tiles: &'a wgpu::Buffer,
    /// The chunk's colours.
    pub colors: &'a wgpu::Buffer,
    /// The other eye of the frame's pair, its keys; a mono frame's eye binds its own again.
    pub pair_keys: &'a wgpu::Buffer,
    /// The other eye's occlusion tiles (or the eye's own).
    pub pair_tiles: &'a wgpu::Buffer,
    /// WGSL `ListedPoints`: the count and indices of the points left to draw.
    pub listed: &'a wgpu::Buffer,
    /// The second dispatch's arguments (WGSL `ListedGroups`), apart from the list: a dispatch
    /// may not both write a buffer and read it as its arguments.
    pub listed_groups: &'a wgpu::Buffer,
}

/// The expand pipeline and its bind group layout; on the keyed path, the splat's two.
pub struct ExpandPipeline {
    layout: wgpu::BindGroupLayout,
    /// `expand`, or on the keyed path `expand_splat`, or for ODS pairs `expand_splat_pair`.
    pipeline: wgpu::ComputePipeline,
    /// Whether `pipeline` splats both eyes of a pair.
    pairs: bool,
    /// On the keyed path, `expand_listed` and its layout.
    listed: Option<(wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
    /// For ODS pairs, `splat_wide_pair` (bound as `expand_listed`): the spheres the pair
    /// splat leaves as too wide for one invocation, each cast by a workgroup.
    wide: Option<wgpu::ComputePipeline>,
}

/// An expand pipeline's bind groups for one eye and chunk.
pub struct ExpandBindings {
    main: wgpu::BindGroup,
    /// On the keyed path, the listed points' dispatch.
    listed: Option<wgpu::BindGroup>,
}

impl ExpandPipeline {
    /// Compiles the pipelines from `src` (a [`source`] module, with the splat when `keyed`);
    /// with `pairs` (keyed only) the splat serves both eyes of an ODS pair at once.
    pub fn new(
        device: &wgpu::Device,
        src: &shaders::PipelineSource<'_>,
        keyed: bool,
        pairs: bool,
    ) -> Self {
        debug_assert!(keyed || !pairs, "only the keyed path splats pairs");
        use wgpu::BufferBindingType::Storage;
        let entry = |binding, ty| shaders::buffer_layout(binding, wgpu::ShaderStages::COMPUTE, ty);
        let rw = Storage { read_only: false };
        let mut entries = vec![
            entry(0, Storage { read_only: true }),
            entry(1, Storage { read_only: true }),
            entry(2, rw),
            entry(3, rw),
            entry(4, rw),
        ];
        if !keyed {
            let (layout, pipeline) =
                shaders::compute_pipeline(device, "expand", src, "expand", &entries);
            return ExpandPipeline {
                layout,
                pipeline,
                pairs: false,
                listed: None,
                wide: None,
            };
        }
        entries.extend([
            entry(5, rw),
            entry(6, Storage { read_only: true }),
            entry(7, rw),
            entry(9, rw),
            entry(10, rw),
            entry(11, rw),
        ]);
        let listed =
            shaders::compute_pipeline(device, "expand listed", src, "expand_listed", &entries);
        let wide = pairs.then(|| {
            shaders::compute_pipeline_with(
                device,
                "splat wide pair",
                src,
                "splat_wide_pair",
                &listed.0,
            )
        });
        entries.push(entry(8, rw));
        let (label, entry_point) = if pairs {
            ("expand splat pair", "expand_splat_pair")
        } else {
            ("expand splat", "expand_splat")
        };
        let (layout, pipeline) =
            shaders::compute_pipeline(device, label, src, entry_point, &entries);
        ExpandPipeline {
            layout,
            pipeline,
            pairs,
            listed: Some(listed),
            wide,
        }
    }

    /// Whether the splat serves both eyes of an ODS pair: the first eye's batch is
    /// dispatched whole, the second's with `listed_only`.
    pub fn pairs(&self) -> bool {
        self.pairs
    }

    /// Binds `buffers` for [`ExpandPipeline::dispatch`]; on the keyed path they must include
    /// the splat's.
    pub fn bind(&self, device: &wgpu::Device, buffers: &ExpandBuffers<'_>) -> ExpandBindings {
        let b = buffers;
        let mut entries = vec![
            shaders::bind(0, b.params),
            shaders::bind(1, b.points),
            shaders::bind(2, b.vertices),
            shaders::bind(3, b.draw_args),
            shaders::bind(4, b.stats),
        ];
        let group = |label, layout, entries: &[wgpu::BindGroupEntry<'_>]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries,
            })
        };
        let Some((listed_layout, _)) = &self.listed else {
            return ExpandBindings {
                main: group("expand", &self.layout, &entries),
                listed: None,
            };
        };
        let k = b.keyed.as_ref().expect("the keyed path binds keys");
        entries.extend([
            shaders::bind(5, k.keys),
            shaders::bind(6, k.colors),
            shaders::bind(7, k.listed),
            shaders::bind(9, k.tiles),
            shaders::bind(10, k.pair_keys),
            shaders::bind(11, k.pair_tiles),
        ]);
        let listed = group("expand listed", listed_layout, &entries);
        entries.push(shaders::bind(8, k.listed_groups));
        ExpandBindings {
            main: group("expand splat", &self.layout, &entries),
            listed: Some(listed),
        }
    }

    /// Records the expansion of `count` points (the batch of the bound `Params`); `trig`
    /// binds the pixel trigonometry. On the keyed path `listed_groups` (bound, cleared to
    /// [`splat::NO_GROUPS`] with the list's counts to 0) sizes the later dispatches;
    /// `listed_only` records that one alone, for the second eye of a pair, whose spheres the
    /// first eye's splat cast and listed.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &ExpandBindings,
        trig: &wgpu::BindGroup,
        (count, listed_groups): (u32, Option<&wgpu::Buffer>),
        listed_only: bool,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("expand"),
            timestamp_writes: None,
        });
        pass.set_bind_group(1, trig, &[]);
        if !listed_only {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bindings.main, &[]);
            pass.dispatch_workgroups(count.div_ceil(EXPAND_WORKGROUP), 1, 1);
        }
        if let (Some(wide), Some(group), Some(args), false) =
            (&self.wide, &bindings.listed, listed_groups, listed_only)
        {
            // Before `expand_listed`, which raises the tiles the wide spheres test again.
            pass.set_pipeline(wide);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups_indirect(args, splat::WIDE_GROUPS_OFFSET);
        }
        if let (Some((_, pipeline)), Some(group), Some(args)) =
            (&self.listed, &bindings.listed, listed_groups)
        {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups_indirect(args, 0);
        }
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
