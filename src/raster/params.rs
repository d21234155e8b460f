//! The uniform block of `shaders/params.wgsl`, filled from a [`View`] and the settings.

use bytemuck::{Pod, Zeroable};

use crate::projection::{OdsOffset, PoleMerge, View};
use crate::render::shading::{Shading, lights};
use crate::render::{Imposter, Proxy, RenderSettings};

/// Near and far distances (metres) of the logarithmic depth `log(t/near)/log(far/near)`:
/// a Depth32Float then orders hits to about 2e-6 relative distance over 13 decades.
pub const DEPTH_NEAR: f32 = 1e-6;
/// See [`DEPTH_NEAR`].
pub const DEPTH_FAR: f32 = 1e7;

/// Largest tessellation level `dynamic` may choose.
pub const MAX_DYNAMIC_LEVEL: u32 = 16;

/// Mirror of WGSL `Params` (vec4 slots only).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Params {
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    north: [f32; 4],
    south: [f32; 4],
    image: [f32; 4],
    light0: [f32; 4],
    light1: [f32; 4],
    modes: [u32; 4],
    modes2: [u32; 4],
    modes3: [u32; 4],
}

fn merge_slot(p: PoleMerge) -> (u32, [f32; 4]) {
    match p {
        PoleMerge::Off => (0, [0.0; 4]),
        PoleMerge::Marrinan {
            start_deg,
            end_deg,
            exponent,
        } => (1, [start_deg as f32, end_deg as f32, exponent as f32, 0.0]),
        PoleMerge::Cycles { from_deg, to_deg } => (2, [from_deg as f32, to_deg as f32, 0.0, 0.0]),
    }
}

/// Tessellation level of a static proxy (1 for quad and bounds).
pub fn static_level(proxy: Proxy) -> u32 {
    match proxy {
        Proxy::Static(n) => n.max(1),
        _ => 1,
    }
}

/// Worst-case vertices one point can emit under `proxy` (two seam copies of its grid).
pub fn max_vertices_per_point(proxy: Proxy) -> u64 {
    let n = match proxy {
        Proxy::Bounds | Proxy::Quad => 1,
        Proxy::Static(n) => n.max(1) as u64,
        Proxy::Dynamic => MAX_DYNAMIC_LEVEL as u64,
    };
    12 * n * n
}

impl Params {
    /// Parameters for `view` (eye number `eye`), the batch of `count` points from `first` in
    /// the bound point buffer, and a vertex buffer of `vertex_capacity` vertices.
    pub fn new(
        view: &View,
        settings: &RenderSettings,
        eye: u32,
        (first, count): (u32, u32),
        vertex_capacity: u32,
    ) -> Self {
        let b = view.basis();
        let v4 = |v: glam::DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
        let (nk, north) = merge_slot(view.merging.north);
        let (sk, south) = merge_slot(view.merging.south);
        let ls = lights(&settings.camera);
        let c = settings.camera.center;
        let light = |i: usize| {
            let p = ls[i].position.as_dvec3() - c;
            [p.x as f32, p.y as f32, p.z as f32, ls[i].intensity]
        };
        let offset = match view.offset {
            OdsOffset::Exact => 0,
            OdsOffset::Paper => 1,
        };
        let proxy = match settings.proxy {
            Proxy::Bounds => 0,
            Proxy::Quad => 1,
            Proxy::Static(_) => 2,
            Proxy::Dynamic => 3,
        };
        let imposter = match settings.imposter {
            Imposter::Raycast => 0,
            Imposter::Sprite => 1,
        };
        let shading = match settings.shading {
            Shading::Unlit => 0,
            Shading::Phong => 1,
            Shading::Normal => 2,
        };
        Params {
            forward: v4(b.forward, view.eye_sign),
            right: v4(b.right, view.half_ipd),
            up: v4(b.up, 0.0),
            north,
            south,
            image: [
                settings.image.width as f32,
                settings.image.height as f32,
                DEPTH_NEAR,
                DEPTH_FAR,
            ],
            light0: light(0),
            light1: light(1),
            modes: [nk, sk, offset, proxy],
            modes2: [imposter, shading, static_level(settings.proxy), count],
            modes3: [vertex_capacity, MAX_DYNAMIC_LEVEL, eye, first],
        }
    }
}

impl Params {
    /// Sets the compute splat's largest sphere, in pixels per side of its bounds (0: off).
    pub fn with_splat_limit(mut self, pixels: u32) -> Self {
        self.up[3] = pixels as f32;
        self
    }
}
