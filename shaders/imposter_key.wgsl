// The keyed stages: a drawn sphere's fragment keeps its pixel's nearest hit as a key
// (splat_key.wgsl), exactly as the compute splat does, instead of writing render targets.
// Ray-cast imposters only. Needs SHADER_INT64_ATOMIC_MIN_MAX. Appended to the imposter module
// by src/raster/imposter.rs, after splat_key.wgsl.

// The eye's keys.
@group(0) @binding(3) var<storage, read_write> splat_keys: array<atomic<u64>>;

struct KeyedVertexOut {
    @builtin(position) position: vec4<f32>,
    // The sphere (centre relative to C, radius) and its hits' payload, fetched once per
    // vertex rather than per fragment: they are the point's.
    @location(0) @interpolate(flat) sphere: vec4<f32>,
    @location(1) @interpolate(flat) payload: u32,
}

@vertex
fn vs_key(@location(0) xy: vec2<f32>, @location(2) point: u32) -> KeyedVertexOut {
    let index = point & ~FORCE_RAYCAST;
    let pt = points[index];
    let centre = pt.position - params.camera_offset;
    return KeyedVertexOut(clip_position(xy), vec4<f32>(centre, pt.radius),
                          sphere_payload(index));
}

@fragment
fn fs_key(in: KeyedVertexOut) {
    let centre = in.sphere.xyz;
    let pixel = pixel_ray(sphere_view(params, centre), vec2<u32>(in.position.xy));
    if !pixel.ok {
        return;
    }
    let t = intersect_sphere(pixel.ray, centre, in.sphere.w);
    if t > 0.0 {
        let px = vec2<u32>(in.position.xy);
        let width = u32(params.image_size.x);
        atomicMax(&splat_keys[px.y * width + px.x], hit_key(t, in.payload));
    }
}
