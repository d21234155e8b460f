// Per-batch parameters shared by the pipelines, bound as a read-only storage buffer: lavapipe
// compiles a pipeline variant per set of uniform-buffer values that steer branches and keeps
// them all, which an ODS pair (its eyes' signs alternate every dispatch) made grow without end.
// Laid out as `src/raster/params.rs` (a test there checks the offsets). Mode codes are
// constants of the generated prelude.

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

// Pipeline-overridable copies of the mode fields of Params (src/raster/specialisation.rs).
// A pipeline compiled for one mode has the other modes' code folded away, which software
// rasterizers need: llvmpipe runs every branch a fragment could take at the cost of the
// largest. SPEC_ANY, the default (the probe's), reads the buffer instead.
override SPEC_PROJECTION: u32 = SPEC_ANY;
// SPEC_MONO or SPEC_STEREO: whether the eye sign is 0.
override SPEC_EYES: u32 = SPEC_ANY;
override SPEC_MODEL: u32 = SPEC_ANY;
override SPEC_OFFSET: u32 = SPEC_ANY;
// 0 without a depth map, 1 with one.
override SPEC_DEPTH_MAP: u32 = SPEC_ANY;
override SPEC_PROXY: u32 = SPEC_ANY;
override SPEC_IMPOSTER: u32 = SPEC_ANY;
override SPEC_SHADING: u32 = SPEC_ANY;

// `fixed` unless it is SPEC_ANY, else the buffer's `value`.
fn fixed_or(fixed: u32, value: u32) -> u32 {
    return select(fixed, value, fixed == SPEC_ANY);
}

fn proxy_of(p: Params) -> u32 {
    return fixed_or(SPEC_PROXY, p.proxy);
}

fn imposter_of(p: Params) -> u32 {
    return fixed_or(SPEC_IMPOSTER, p.imposter);
}

fn shading_of(p: Params) -> u32 {
    return fixed_or(SPEC_SHADING, p.shading);
}

fn view_of(p: Params) -> View {
    var eye_sign = p.eye_sign;
    if SPEC_EYES == SPEC_MONO {
        eye_sign = 0.0;
    }
    return View(Basis(p.forward, p.right, p.up), eye_sign, p.half_ipd, p.north, p.south,
                fixed_or(SPEC_OFFSET, p.ods_offset), fixed_or(SPEC_MODEL, p.eye_model));
}

// The view the sphere centred at `centre` (relative to C) is seen in: under a depth map its
// own half-ipd r_s = depth_map_ods_radius(ipd/2, rho_c), rho_c the centre's horizontal
// distance from C (DESIGN §9); the eye's view otherwise.
fn sphere_view(p: Params, centre: vec3<f32>) -> View {
    var v = view_of(p);
    if fixed_or(SPEC_DEPTH_MAP, u32(p.depth_map_count > 0u)) != 0u {
        let b = v.basis;
        let rho_c = length(vec2<f32>(dot(centre, b.right), dot(centre, b.forward)));
        v.half_ipd = depth_map_ods_radius(p.depth_map_b, p.depth_map_d, p.depth_map_count,
                                          p.half_ipd, rho_c);
    }
    return v;
}

fn projection_of(p: Params) -> Projection {
    return Projection(fixed_or(SPEC_PROJECTION, p.projection), p.projection_a, p.projection_b);
}
