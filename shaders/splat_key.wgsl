// The keyed path's per-pixel record, shared by the compute splat (splat.wgsl), the keyed
// fragment stage (imposter_key.wgsl) and the deferred shading (splat_shade.wgsl), kept with a
// 64-bit atomicMax: !distance bits << 32 | payload. A cleared (zero) key means "no hit", and
// the largest key is the nearest hit whatever the order of the writes. The payload is
// - shaded: the hit's RGBA8 colour, alpha 255 (its top byte); unlit hits are shaded at once,
//   and src/raster/key_targets.rs decodes these;
// - deferred: MAX_KEY_INDEX - the point's index within its chunk (top byte 0), for lit
//   shadings, which splat_shade.wgsl turns into shaded keys once a chunk is drawn, so a pixel
//   is shaded once however many spheres were cast at it.
// At equal distances a shaded key (an earlier chunk's) beats a deferred one, and a lower index
// beats a higher one: the lowest index wins, as in the ray tracer; two unlit hits at the same
// distance keep the larger colour. Prepended: shade_hit.

fn shaded_key(t: f32, color: vec4<f32>) -> u64 {
    return (u64(~bitcast<u32>(t)) << 32u) | u64(pack4x8unorm(color));
}

fn deferred_key(t: f32, idx: u32) -> u64 {
    return (u64(~bitcast<u32>(t)) << 32u) | u64(MAX_KEY_INDEX - idx);
}

// The key of ray `r` hitting point `index` (centre `center` relative to C, `radius`) at `t`.
fn hit_key(index: u32, r: Ray, t: f32, center: vec3<f32>, radius: f32) -> u64 {
    if shading_of(params) != SHADING_UNLIT {
        return deferred_key(t, index);
    }
    let hit = r.origin + t * r.dir;
    return shaded_key(t, shade_hit(index, r, t, hit, (hit - center) / radius).color);
}
