// Per-(chunk, eye) uniform shared by the expand and imposter pipelines; laid out as
// `src/raster/params.rs` (vec4 slots only, so Rust and WGSL agree without padding rules).

struct Params {
    // xyz forward, w eye sign.
    forward: vec4<f32>,
    // xyz right, w half ipd.
    right: vec4<f32>,
    // xyz up, w compute-splat limit (pixels per side, 0 off).
    up: vec4<f32>,
    // Merge parameters a, b, c of the north and south profiles.
    north: vec4<f32>,
    south: vec4<f32>,
    // width, height, depth near, depth far.
    image: vec4<f32>,
    // Lights relative to C: xyz position, w intensity.
    light0: vec4<f32>,
    light1: vec4<f32>,
    // north kind, south kind, offset (0 exact, 1 paper), proxy (0 bounds, 1 quad, 2 static, 3 dynamic).
    modes: vec4<u32>,
    // imposter (0 raycast, 1 sprite), shading, static level, points in this chunk.
    modes2: vec4<u32>,
    // vertex capacity, maximum dynamic level, eye index, first point of the batch.
    modes3: vec4<u32>,
}

fn view_of(p: Params) -> View {
    let b = Basis(p.forward.xyz, p.right.xyz, p.up.xyz);
    return View(
        b,
        p.forward.w,
        p.right.w,
        PoleMerge(p.modes.x, p.north.x, p.north.y, p.north.z),
        PoleMerge(p.modes.y, p.south.x, p.south.y, p.south.z),
        p.modes.z,
    );
}

fn image_size(p: Params) -> vec2<f32> {
    return p.image.xy;
}
