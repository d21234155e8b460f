// The keyed path's per-pixel record, shared by the compute splat (splat.wgsl), the keyed
// fragment stage (imposter_key.wgsl) and the deferred shading (splat_shade.wgsl), kept with a
// 64-bit atomicMax: !distance bits << 32 | payload. A cleared (zero) key means "no hit", and
// the largest key is the nearest hit whatever the order of the writes. The payload is
// - shaded: the RGBA8 colour, alpha 255 (its top byte); unlit hits are shaded at once (their
//   colour is the point's), and src/raster/key_targets.rs decodes these;
// - deferred: MAX_KEY_INDEX - the point's index within its chunk (top byte 0), for lit
//   shadings, which splat_shade.wgsl turns into shaded keys once a chunk is drawn, so a pixel
//   is shaded once however many spheres were cast at it.
// Either way it is the sphere's, not the hit's: the splat fetches it once per sphere. At equal
// distances a shaded key (an earlier chunk's) beats a deferred one, and a lower index beats a
// higher one: the lowest index wins, as in the ray tracer; two unlit hits at the same distance
// keep the larger colour. Each module that includes it declares `params` and `colors`.

// The payload of point `index`'s hits.
fn sphere_payload(index: u32) -> u32 {
    if shading_of(params) != SHADING_UNLIT {
        return MAX_KEY_INDEX - index;
    }
    // As shade_hit shades an unlit hit.
    return pack4x8unorm(vec4<f32>(unpack_color(colors[index]) / 255.0, 1.0));
}

// The key of a hit at distance `t` with `payload`.
fn hit_key(t: f32, payload: u32) -> u64 {
    return (u64(~bitcast<u32>(t)) << 32u) | u64(payload);
}
