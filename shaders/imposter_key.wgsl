// The keyed fragment stage: a drawn sphere's fragment keeps its pixel's nearest hit as a key
// (splat_key.wgsl), exactly as the compute splat does, instead of writing render targets.
// Ray-cast imposters only. Needs SHADER_INT64_ATOMIC_MIN_MAX. Appended to the imposter module
// by src/raster/imposter.rs, after splat_key.wgsl.

// The eye's keys.
@group(0) @binding(3) var<storage, read_write> splat_keys: array<atomic<u64>>;

@fragment
fn fs_key(in: VertexOut) {
    let index = in.point & ~FORCE_RAYCAST;
    let seen = pixel_cast(in.position.xy, index);
    if !seen.ok {
        return;
    }
    let t = intersect_sphere(seen.ray, seen.center, seen.radius);
    if t > 0.0 {
        let pixel = vec2<u32>(in.position.xy);
        let width = u32(params.image_size.x);
        atomicMax(&splat_keys[pixel.y * width + pixel.x], hit_key(t, sphere_payload(index)));
    }
}
