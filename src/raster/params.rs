//! The per-batch parameters of `shaders/params.wgsl` (a read-only storage buffer), filled from a [`View`] and the settings.

use std::f64::consts::{PI, TAU};

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::projection::{EyeModel, MapFrame, OdsOffset, PoleMerge, Projection, View};
use crate::render::shading::{Shading, lights};
use crate::render::{Imposter, Proxy, RenderSettings};

use super::constants::{
    DEPTH_FAR, DEPTH_NEAR, IMPOSTER_RAYCAST, IMPOSTER_SPRITE, MERGE_CYCLES, MERGE_MARRINAN,
    MERGE_OFF, MODEL_ODS, MODEL_PARALLEL, OFFSET_EXACT, OFFSET_PAPER, PROJ_CUBEMAP,
    PROJ_CYLINDRICAL, PROJ_EQUIRECT, PROJ_EQUIRECT_FULL, PROJ_FISHEYE, PROJ_HAMMER, PROJ_MAP,
    PROXY_BOUNDS, PROXY_DYNAMIC, PROXY_QUAD, PROXY_STATIC, SHADING_NORMAL, SHADING_PHONG,
    SHADING_UNLIT,
};

/// One pole's merge profile (WGSL `PoleMerge`): `kind` is a `MERGE_*` constant, `a, b, c`
/// its parameters.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuPoleMerge {
    /// `MERGE_OFF`, `MERGE_MARRINAN` or `MERGE_CYCLES`.
    pub kind: u32,
    /// Marrinan start, Cycles from (degrees).
    pub a: f32,
    /// Marrinan end, Cycles to (degrees).
    pub b: f32,
    /// Marrinan exponent.
    pub c: f32,
}

impl From<PoleMerge> for GpuPoleMerge {
    fn from(p: PoleMerge) -> Self {
        let (kind, [a, b, c]) = match p {
            PoleMerge::Off => (MERGE_OFF, [0.0; 3]),
            PoleMerge::Marrinan {
                start_deg,
                end_deg,
                exponent,
            } => (
                MERGE_MARRINAN,
                [start_deg as f32, end_deg as f32, exponent as f32],
            ),
            PoleMerge::Cycles { from_deg, to_deg } => {
                (MERGE_CYCLES, [from_deg as f32, to_deg as f32, 0.0])
            }
        };
        GpuPoleMerge { kind, a, b, c }
    }
}

/// Mirror of WGSL `Params`, field for field (WGSL host-shareable layout: each `vec3` starts a
/// 16-byte slot and shares it with the scalar after it; `tests` checks the offsets against
/// the WGSL).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// Camera forward.
    pub forward: [f32; 3],
    /// -1 left eye, +1 right eye, 0 mono.
    pub eye_sign: f32,
    /// Camera right.
    pub right: [f32; 3],
    /// Half the interocular distance, metres.
    pub half_ipd: f32,
    /// Camera up.
    pub up: [f32; 3],
    /// Largest sphere the compute splat ray casts, pixels per side of its bounds; 0: off.
    pub splat_limit: f32,
    /// North pole merge profile.
    pub north: GpuPoleMerge,
    /// South pole merge profile.
    pub south: GpuPoleMerge,
    /// Image width and height, pixels.
    pub image_size: [f32; 2],
    /// [`DEPTH_NEAR`].
    pub depth_near: f32,
    /// [`DEPTH_FAR`].
    pub depth_far: f32,
    /// First light, relative to the camera centre.
    pub light0_position: [f32; 3],
    /// First light's intensity.
    pub light0_intensity: f32,
    /// Second light, relative to the camera centre.
    pub light1_position: [f32; 3],
    /// Second light's intensity.
    pub light1_intensity: f32,
    /// `OFFSET_EXACT` or `OFFSET_PAPER`.
    pub ods_offset: u32,
    /// A `PROXY_*` constant.
    pub proxy: u32,
    /// A `IMPOSTER_*` constant.
    pub imposter: u32,
    /// 0 unlit, 1 Phong, 2 normal (`shaders/shading.wgsl`).
    pub shading: u32,
    /// Tessellation level of the static proxy.
    pub static_level: u32,
    /// Points in this batch.
    pub batch_count: u32,
    /// First point of this batch in the bound point buffer.
    pub batch_first: u32,
    /// Vertices the vertex buffer holds.
    pub vertex_capacity: u32,
    /// Eye index (the statistics record it counts into).
    pub eye: u32,
    /// Pads `eye` to the 16-byte slot `camera_offset` starts.
    pub pad: [u32; 3],
    /// The camera centre in the frame of the bound points (zero when they are stored
    /// relative to it, as chunks drawn once are; a scene uploaded once for many camera
    /// positions is stored relative to one fixed point).
    pub camera_offset: [f32; 3],
    /// A `PROJ_*` constant: the image's projection.
    pub projection: u32,
    /// The projection's parameters (`Projection` in `shaders/projection.wgsl`).
    pub projection_a: [f32; 4],
    /// More of them (the map's ray height).
    pub projection_b: [f32; 4],
    /// `MODEL_ODS` or `MODEL_PARALLEL`: where the eye's rays start.
    pub eye_model: u32,
    /// Pads `eye_model` to the 16-byte slot `depth_map_b` starts.
    pub pad_model: [u32; 3],
    /// `--depth-map` breakpoints, packed ([`crate::projection::depth_map::DepthMap::packed_f32`]).
    pub depth_map_b: [[f32; 4]; 2],
    /// `--depth-map` distances, packed.
    pub depth_map_d: [[f32; 4]; 2],
    /// Pairs of the view's depth map; 0 without one.
    pub depth_map_count: u32,
    /// Pads the block to a multiple of 16 bytes.
    pub pad_end: [u32; 3],
}

/// Tessellation level of a static proxy (1 for quad and bounds).
pub fn static_level(proxy: Proxy) -> u32 {
    match proxy {
        Proxy::Static(n) => n.max(1),
        _ => 1,
    }
}

impl Params {
    /// Parameters for `view` (eye number `eye`), the batch of `count` points from `first` in
    /// the bound point buffer, and a vertex buffer of `vertex_capacity` vertices; the splat
    /// is off.
    pub fn new(
        view: &View,
        settings: &RenderSettings,
        eye: u32,
        (first, count): (u32, u32),
        vertex_capacity: u32,
    ) -> Self {
        let b = view.basis();
        let v3 = |v: glam::DVec3| v.as_vec3().to_array();
        let ls = lights(&settings.camera);
        let c = settings.camera.center;
        let light = |i: usize| v3(ls[i].position.as_dvec3() - c);
        let (depth_map_b, depth_map_d) = view
            .depth_map
            .map_or(([[0.0; 4]; 2], [[0.0; 4]; 2]), |m| m.packed_f32());
        Params {
            forward: v3(b.forward),
            eye_sign: view.eye_sign as f32,
            right: v3(b.right),
            half_ipd: view.half_ipd as f32,
            up: v3(b.up),
            splat_limit: 0.0,
            north: view.merging.north.into(),
            south: view.merging.south.into(),
            image_size: [settings.image.width as f32, settings.image.height as f32],
            depth_near: DEPTH_NEAR,
            depth_far: DEPTH_FAR,
            light0_position: light(0),
            light0_intensity: ls[0].intensity,
            light1_position: light(1),
            light1_intensity: ls[1].intensity,
            ods_offset: match view.offset {
                OdsOffset::Exact => OFFSET_EXACT,
                OdsOffset::Paper => OFFSET_PAPER,
            },
            proxy: match settings.proxy {
                Proxy::Bounds => PROXY_BOUNDS,
                Proxy::Quad => PROXY_QUAD,
                Proxy::Static(_) => PROXY_STATIC,
                Proxy::Dynamic => PROXY_DYNAMIC,
            },
            imposter: match settings.imposter {
                Imposter::Raycast => IMPOSTER_RAYCAST,
                Imposter::Sprite => IMPOSTER_SPRITE,
            },
            shading: match settings.shading {
                Shading::Unlit => SHADING_UNLIT,
                Shading::Phong => SHADING_PHONG,
                Shading::Normal => SHADING_NORMAL,
            },
            static_level: static_level(settings.proxy),
            batch_count: count,
            batch_first: first,
            vertex_capacity,
            eye,
            pad: [0; 3],
            camera_offset: [0.0; 3],
            projection: 0,
            projection_a: [0.0; 4],
            projection_b: [0.0; 4],
            eye_model: match view.model {
                EyeModel::Ods => MODEL_ODS,
                EyeModel::Parallel => MODEL_PARALLEL,
            },
            pad_model: [0; 3],
            depth_map_b,
            depth_map_d,
            depth_map_count: view.depth_map.map_or(0, |m| m.len() as u32),
            pad_end: [0; 3],
        }
        .with_projection(&settings.image.projection, settings.camera.center)
    }

    /// These parameters with `projection` (map frames taken relative to the camera centre
    /// `center`).
    fn with_projection(self, projection: &Projection, center: DVec3) -> Self {
        let (kind, a, b) = match *projection {
            p if p.is_full_equirect() => (PROJ_EQUIRECT_FULL, [TAU, PI, 0.0, 0.0], 0.0),
            Projection::Equirect { hfov_deg, vfov_deg } => (
                PROJ_EQUIRECT,
                [hfov_deg.to_radians(), vfov_deg.to_radians(), 0.0, 0.0],
                0.0,
            ),
            Projection::Hammer => (PROJ_HAMMER, [0.0; 4], 0.0),
            Projection::Cylindrical { vfov_deg } => {
                let v = vfov_deg.to_radians();
                (PROJ_CYLINDRICAL, [(0.5 * v).tan(), v, 0.0, 0.0], 0.0)
            }
            Projection::Fisheye { fov_deg } => {
                (PROJ_FISHEYE, [fov_deg.to_radians(), 0.0, 0.0, 0.0], 0.0)
            }
            Projection::Cubemap => (PROJ_CUBEMAP, [0.0; 4], 0.0),
            Projection::Map(frame) => {
                let f = frame.unwrap_or(MapFrame {
                    x0: 0.0,
                    x1: 1.0,
                    y0: 0.0,
                    y1: 1.0,
                    z_top: 0.0,
                });
                (
                    PROJ_MAP,
                    [f.x0 - center.x, f.y1 - center.y, f.x1 - f.x0, f.y1 - f.y0],
                    f.z_top - center.z,
                )
            }
        };
        Params {
            projection: kind,
            projection_a: a.map(|x| x as f32),
            projection_b: [b as f32, 0.0, 0.0, 0.0],
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::shaders::{PARAMS, compose, field_offsets, wgsl_struct_layout};
    use super::*;

    #[test]
    fn params_and_pole_merge_match_the_wgsl_field_for_field() {
        let source = compose(&[PARAMS]);
        let rust = field_offsets!(Params: forward, eye_sign, right, half_ipd, up, splat_limit,
            north, south, image_size, depth_near, depth_far, light0_position, light0_intensity,
            light1_position, light1_intensity, ods_offset, proxy, imposter, shading,
            static_level, batch_count, batch_first, vertex_capacity, eye, camera_offset,
            projection, projection_a, projection_b, eye_model, depth_map_b, depth_map_d,
            depth_map_count);
        // The WGSL struct ends at `depth_map_count` and rounds its size up to 16 bytes; Rust
        // pads.
        assert_eq!(wgsl_struct_layout(&source, "Params"), (rust, 320));
        assert_eq!(size_of::<Params>(), 320);

        let rust = field_offsets!(GpuPoleMerge: kind, a, b, c);
        let size = size_of::<GpuPoleMerge>() as u32;
        assert_eq!(wgsl_struct_layout(&source, "PoleMerge"), (rust, size));
    }
}
