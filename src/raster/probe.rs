//! A compute kernel over the shared WGSL math (`shaders/probe.wgsl`), so tests can check the
//! GPU `project`, `ray` and pole merge against the f64 Rust functions.

use crate::projection::View;
use crate::render::RenderSettings;

use super::error::RasterError;
use super::params::Params;
use super::rasterizer::Rasterizer;
use super::shaders;
use super::targets::map_read;

/// `shaders/probe.wgsl`.
pub const PROBE: &str = include_str!("../../shaders/probe.wgsl");

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
}

impl Rasterizer {
    /// Runs the probe kernel for `view`: projects each of `points` (relative to the camera
    /// centre) and evaluates the ray and merge factor at each of `angles` (same length).
    pub fn probe_math(
        &self,
        view: &View,
        settings: &RenderSettings,
        points: &[[f32; 3]],
        angles: &[[f32; 2]],
    ) -> Result<Vec<ProbeResult>, RasterError> {
        if points.len() != angles.len() || points.is_empty() {
            return Err(RasterError::Settings(
                "probe needs as many angles as points, at least one".into(),
            ));
        }
        let ctx = &self.ctx;
        let device = &ctx.device;
        let n = points.len();
        let pts: Vec<[f32; 4]> = points.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect();
        let params = Params::new(view, settings, 0, (0, n as u32), 0);
        let (pipeline, out, read, bind) = ctx.scoped("running the probe kernel", || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("probe.wgsl"),
                source: wgpu::ShaderSource::Wgsl(
                    shaders::compose(&[shaders::PARAMS, PROBE]).into(),
                ),
            });
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
            let params_buf = make("probe params", 176, U::UNIFORM | U::COPY_DST);
            ctx.queue
                .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
            let pts_buf = make("probe points", 16 * n as u64, U::STORAGE | U::COPY_DST);
            ctx.queue
                .write_buffer(&pts_buf, 0, bytemuck::cast_slice(&pts));
            let ang_buf = make("probe angles", 8 * n as u64, U::STORAGE | U::COPY_DST);
            ctx.queue
                .write_buffer(&ang_buf, 0, bytemuck::cast_slice(angles));
            let out = make("probe out", 48 * n as u64, U::STORAGE | U::COPY_SRC);
            let read = make("probe read", 48 * n as u64, U::COPY_DST | U::MAP_READ);
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
                        resource: pts_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: ang_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
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
                let (a, o, d) = (v[3 * i], v[3 * i + 1], v[3 * i + 2]);
                ProbeResult {
                    projected: (a[2] != 0.0).then_some((a[0], a[1])),
                    merge: a[3],
                    ray_origin: [o[0], o[1], o[2]],
                    ray_dir: [d[0], d[1], d[2]],
                }
            })
            .collect())
    }
}
