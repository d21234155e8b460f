// The keyed path's per-pixel record, shared by the compute splat (splat.wgsl) and the keyed
// fragment stage (imposter_key.wgsl): (!distance bits << 32 | shaded RGBA8), kept with a 64-bit
// atomicMax. A cleared (zero) key means "no hit", the largest key is the nearest hit (ties to
// the larger colour, whatever the order of the writes), and the key is the pixel's final
// colour and distance: src/raster/key_targets.rs decodes it. Prepended: shade_hit.

fn hit_key(t: f32, color: vec4<f32>) -> u64 {
    return (u64(~bitcast<u32>(t)) << 32u) | u64(pack4x8unorm(color));
}

// The key of ray `r` hitting point `index` (centre `center` relative to C, `radius`) at `t`.
fn shaded_key(index: u32, r: Ray, t: f32, center: vec3<f32>, radius: f32) -> u64 {
    let hit = r.origin + t * r.dir;
    return hit_key(t, shade_hit(index, r, t, hit, (hit - center) / radius).color);
}
