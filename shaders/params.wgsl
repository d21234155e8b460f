// Per-batch uniform shared by the pipelines; laid out as `src/raster/params.rs` (a test there
// checks the offsets). Mode codes are constants of the generated prelude.

struct Params {
    forward: vec3<f32>,
    // -1 left, +1 right, 0 mono.
    eye_sign: f32,
    right: vec3<f32>,
    half_ipd: f32,
    up: vec3<f32>,
    // Largest sphere the compute splat ray casts, pixels per side of its bounds (0: off).
    splat_limit: f32,
    north: PoleMerge,
    south: PoleMerge,
    // Width and height, pixels.
    image_size: vec2<f32>,
    // Logarithmic depth range, metres.
    depth_near: f32,
    depth_far: f32,
    // Lights relative to C.
    light0_position: vec3<f32>,
    light0_intensity: f32,
    light1_position: vec3<f32>,
    light1_intensity: f32,
    // OFFSET_EXACT or OFFSET_PAPER.
    ods_offset: u32,
    // PROXY_*.
    proxy: u32,
    // IMPOSTER_*.
    imposter: u32,
    // 0 unlit, 1 phong, 2 normal.
    shading: u32,
    static_level: u32,
    // The batch: points [batch_first, batch_first + batch_count) of the bound point buffer.
    batch_count: u32,
    batch_first: u32,
    vertex_capacity: u32,
    // Eye index: the statistics record the expand pass counts into.
    eye: u32,
    // C in the frame of the bound points (zero when they are stored relative to C).
    camera_offset: vec3<f32>,
    // PROJ_*, and its parameters (see Projection in projection.wgsl).
    projection: u32,
    projection_a: vec4<f32>,
    projection_b: vec4<f32>,
    // MODEL_ODS or MODEL_PARALLEL: where the eye's rays start.
    eye_model: u32,
    // `--depth-map` breakpoints B and distances D, packed as depth_map.wgsl takes them;
    // `depth_map_count` pairs, 0 without a map.
    depth_map_b: array<vec4<f32>, 2>,
    depth_map_d: array<vec4<f32>, 2>,
    depth_map_count: u32,
}

fn view_of(p: Params) -> View {
    return View(Basis(p.forward, p.right, p.up), p.eye_sign, p.half_ipd, p.north, p.south,
                p.ods_offset, p.eye_model);
}

// The view the sphere centred at `centre` (relative to C) is seen in: under a depth map its
// own half-ipd r_s = depth_map_ods_radius(ipd/2, rho_c), rho_c the centre's horizontal
// distance from C (DESIGN §9); the eye's view otherwise.
fn sphere_view(p: Params, centre: vec3<f32>) -> View {
    var v = view_of(p);
    if p.depth_map_count > 0u {
        let b = v.basis;
        let rho_c = length(vec2<f32>(dot(centre, b.right), dot(centre, b.forward)));
        v.half_ipd = depth_map_ods_radius(p.depth_map_b, p.depth_map_d, p.depth_map_count,
                                          p.half_ipd, rho_c);
    }
    return v;
}

fn projection_of(p: Params) -> Projection {
    return Projection(p.projection, p.projection_a, p.projection_b);
}
