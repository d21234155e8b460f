//! A compute kernel over the shared WGSL math (`shaders/probe.wgsl`), so tests can check the
//! GPU `project`, `ray`, pole merge, `intersect_sphere`, `shade`, `sphere_bounds`,
//! `image_ray` and `image_bounds` against the f64 Rust functions.

use bytemuck::{Pod, Zeroable};

use crate::projection::View;
use crate::projection::image_bounds::{MAX_RECTS, Margins};
use crate::render::{RenderSettings, Shading};

use super::error::RasterError;
use super::params::Params;
use super::rasterizer::Rasterizer;
use super::shaders;
use super::targets::map_read;

/// `shaders/probe.wgsl`.
pub const PROBE: &str = include_str!("../../shaders/probe.wgsl");

/// Source of the probe kernel: the math it checks, then `probe.wgsl`.
pub fn source() -> String {
    shaders::compose(&[
        shaders::PARAMS,
        shaders::SPHERE_BOUNDS,
        shaders::IMAGE_BOUNDS,
        shaders::SPHERE,
        shaders::SHADING,
        PROBE,
    ])
}

/// The margins `shaders/image_bounds.wgsl` adds (`ANGLE_MARGIN`, `PIXEL_MARGIN`), for the f64
/// twin.
pub fn bounds_margins() -> Margins {
    Margins {
        angle: f64::from(super::constants::ANGLE_MARGIN),
        pixel: f64::from(super::constants::PIXEL_MARGIN),
    }
}

/// vec4 slots the kernel writes per item.
const OUT_SLOTS: usize = 15;

/// One probe item: the inputs of every function the kernel evaluates. Positions are relative
/// to the camera centre C, as on the GPU.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ProbeItem {
    /// Point for `project`.
    pub point: [f32; 3],
    /// `(lam, phi)` for `ray` and the merge factor (at `phi`).
    pub angles: [f32; 2],
    /// Ray origin for `intersect_sphere`.
    pub ray_origin: [f32; 3],
    /// Unit ray direction for `intersect_sphere`.
    pub ray_dir: [f32; 3],
    /// Sphere centre and radius for `intersect_sphere` and `sphere_bounds`.
    pub sphere: [f32; 4],
    /// `shade` mode.
    pub shading: Shading,
    /// `shade` base colour (sRGB).
    pub base: [u8; 3],
    /// `shade` unit normal facing the viewer.
    pub normal: [f32; 3],
    /// `shade` hit point.
    pub hit: [f32; 3],
    /// `shade` eye (the ray's origin).
    pub eye: [f32; 3],
    /// Image position (pixels) for `image_ray` in the settings' image.
    pub pixel: [f32; 2],
}

/// WGSL `ProbeItem` (vec4 slots only).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ItemSlots([[f32; 4]; 10]);

impl ProbeItem {
    fn slots(&self) -> ItemSlots {
        let v = |a: [f32; 3], w: f32| [a[0], a[1], a[2], w];
        let mode = match self.shading {
            Shading::Unlit => 0.0,
            Shading::Phong => 1.0,
            Shading::Normal => 2.0,
        };
        ItemSlots([
            v(self.point, 0.0),
            [self.angles[0], self.angles[1], 0.0, 0.0],
            v(self.ray_origin, 0.0),
            v(self.ray_dir, 0.0),
            self.sphere,
            v(self.base.map(f32::from), mode),
            v(self.normal, 0.0),
            v(self.hit, 0.0),
            v(self.eye, 0.0),
            [self.pixel[0], self.pixel[1], 0.0, 0.0],
        ])
    }
}

/// What the GPU computed for one probe item.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeResult {
    /// `project(point)`: (lam, phi), or `None` when it has no projection.
    pub projected: Option<(f32, f32)>,
    /// `pole_merging_factor(phi)` at the item's input latitude.
    pub merge: f32,
    /// `ray(lam, phi)`: origin relative to C.
    pub ray_origin: [f32; 3],
    /// `ray(lam, phi)`: unit direction.
    pub ray_dir: [f32; 3],
    /// `intersect_sphere(ray, sphere)`: the hit distance, or `None`.
    pub hit_t: Option<f32>,
    /// `shade(...)`: sRGB byte values (as the fragment stage writes them, before `/ 255`).
    pub shaded: [f32; 3],
    /// `sphere_bounds(sphere)`: `(lam, phi)` low corner.
    pub bounds_lo: [f32; 2],
    /// `sphere_bounds(sphere)`: `(lam, phi)` high corner.
    pub bounds_hi: [f32; 2],
    /// `sphere_bounds(sphere)`: the special flag.
    pub bounds_special: bool,
    /// `image_ray(pixel)` in the settings' image: origin relative to C and direction, or
    /// `None` where the projection shows nothing.
    pub image_ray: Option<([f32; 3], [f32; 3])>,
    /// `image_bounds(sphere)` in the settings' image: `(lo.x, lo.y, hi.x, hi.y)` pixels of
    /// the first `rect_count` entries.
    pub rects: [[f32; 4]; MAX_RECTS],
    /// Rectangles `image_bounds` returned.
    pub rect_count: usize,
}

impl Rasterizer {
    /// Runs the probe kernel for `view` (lights from `settings`' camera) on each of `items`.
    pub fn probe_math(
        &self,
        view: &View,
        settings: &RenderSettings,
        items: &[ProbeItem],
    ) -> Result<Vec<ProbeResult>, RasterError> {
        if items.is_empty() {
            return Err(RasterError::Settings(
                "probe needs at least one item".into(),
            ));
        }
        let ctx = &self.ctx;
        let device = &ctx.device;
        let n = items.len();
        let slots: Vec<ItemSlots> = items.iter().map(ProbeItem::slots).collect();
        let out_bytes = (16 * OUT_SLOTS * n) as u64;
        let params = Params::new(view, settings, 0, (0, n as u32), 0);
        let (pipeline, out, read, bind) = ctx.scoped("running the probe kernel", || {
            let module = shaders::module(device, "probe.wgsl", source());
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("probe"),
                layout: None,
                module: &module,
                entry_point: Some("probe"),
                compilation_options: Default::default(),
                cache: None,
            });
            let make = |label, size: u64, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                })
            };
            use wgpu::BufferUsages as U;
            let params_buf = make(
                "probe params",
                std::mem::size_of::<Params>() as u64,
                U::STORAGE | U::COPY_DST,
            );
            ctx.queue
                .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
            let items_buf = make(
                "probe items",
                std::mem::size_of_val(slots.as_slice()) as u64,
                U::STORAGE | U::COPY_DST,
            );
            ctx.queue
                .write_buffer(&items_buf, 0, bytemuck::cast_slice(&slots));
            let out = make("probe out", out_bytes, U::STORAGE | U::COPY_SRC);
            let read = make("probe read", out_bytes, U::COPY_DST | U::MAP_READ);
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("probe"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: params_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: items_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: out.as_entire_binding(),
                    },
                ],
            });
            (pipeline, out, read, bind)
        })?;
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, None);
        ctx.queue.submit([encoder.finish()]);
        let raw = map_read(ctx, &read, "reading back the probe")?;
        let v: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&raw);
        Ok((0..n)
            .map(|i| {
                let s = &v[OUT_SLOTS * i..OUT_SLOTS * (i + 1)];
                let (a, o, d, c, b) = (s[0], s[1], s[2], s[3], s[4]);
                ProbeResult {
                    projected: (a[2] != 0.0).then_some((a[0], a[1])),
                    merge: a[3],
                    ray_origin: [o[0], o[1], o[2]],
                    ray_dir: [d[0], d[1], d[2]],
                    hit_t: (c[3] > 0.0).then_some(c[3]),
                    shaded: [c[0], c[1], c[2]],
                    bounds_lo: [b[0], b[1]],
                    bounds_hi: [b[2], b[3]],
                    bounds_special: s[5][0] != 0.0,
                    image_ray: (s[5][2] != 0.0)
                        .then_some(([s[6][0], s[6][1], s[6][2]], [s[7][0], s[7][1], s[7][2]])),
                    rects: std::array::from_fn(|k| s[8 + k]),
                    rect_count: s[5][1] as usize,
                }
            })
            .collect())
    }
}
