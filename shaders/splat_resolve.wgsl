// Render pass merging the compute splat's nearest hits into one eye's targets. Driven by
// src/raster/splat.rs. Prepended: everything imposter.wgsl needs, and imposter.wgsl itself
// (its shade_pixel and FragmentOut).

// Splat keys per pixel, as written by the compute splat (see splat.wgsl): x = !point index,
// y = !distance bits; (0, 0) = nothing splatted. Read as u32 pairs so this stage needs no
// 64-bit support.
@group(0) @binding(3) var<storage, read> splat_keys: array<vec2<u32>>;

// A triangle covering the whole image.
@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.5, 1.0);
}

// Resolves the nearest splatted sphere of each pixel into the targets; the depth test keeps
// whichever of it and the rasterized proxies is nearer.
@fragment
fn fs_resolve(@builtin(position) position: vec4<f32>) -> FragmentOut {
    let width = u32(params.image_size.x);
    let key = splat_keys[u32(position.y) * width + u32(position.x)];
    if key.x == 0u && key.y == 0u {
        discard;
    }
    let s = shade_pixel(position.xy, ~key.x | FORCE_RAYCAST, vec2<f32>(0.0));
    if !s.hit {
        discard;
    }
    return FragmentOut(s.color, s.distance, s.depth);
}
