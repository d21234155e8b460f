// Compute pass shading an eye's deferred keys (splat_key.wgsl) once a chunk is drawn, one
// invocation per pixel: for lit shadings, each pixel is shaded once, by its nearest hit.
// Driven by src/raster/splat_shade.rs. Prepended: everything imposter.wgsl needs, and
// imposter.wgsl itself (its pixel_cast and shade_hit).

// The eye's keys as u32 pairs (x = payload, y = !distance bits), so this stage needs no
// 64-bit support; the chunk's atomics are done when it runs.
@group(0) @binding(3) var<storage, read_write> splat_keys: array<vec2<u32>>;

@compute @workgroup_size(SHADE_WORKGROUP_SIDE, SHADE_WORKGROUP_SIDE)
fn shade_keys(@builtin(global_invocation_id) gid: vec3<u32>) {
    let width = u32(params.image_size.x);
    if gid.x >= width || gid.y >= u32(params.image_size.y) {
        return;
    }
    let i = gid.y * width + gid.x;
    let key = splat_keys[i];
    // Nothing here, or shaded already (alpha 255 in the payload's top byte).
    if key.y == 0u || (key.x >> 24u) != 0u {
        return;
    }
    let index = MAX_KEY_INDEX - key.x;
    let t = bitcast<f32>(~key.y);
    let seen = pixel_cast(vec2<f32>(gid.xy) + 0.5, index);
    let r = seen.ray;
    let hit = r.origin + t * r.dir;
    let s = shade_hit(index, r, t, hit, (hit - seen.center) / seen.radius);
    splat_keys[i].x = pack4x8unorm(s.color);
}
