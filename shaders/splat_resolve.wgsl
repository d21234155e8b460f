// Render pass merging the compute splat's nearest hits into one eye's targets. Driven by
// src/raster/splat.rs. Prepended: everything imposter.wgsl needs, and imposter.wgsl itself
// (its shade_hit and FragmentOut).

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
    // The key holds the hit's distance: the splat's intersection, bit for bit, so nothing is
    // intersected again (and unlit shading needs neither the ray nor the point).
    let index = ~key.x;
    let t = bitcast<f32>(~key.y);
    let pt = points[index];
    let center = pt.position - params.camera_offset;
    let r = pixel_ray(sphere_view(params, center), vec2<u32>(position.xy)).ray;
    let hit = r.origin + t * r.dir;
    let s = shade_hit(index, r, t, hit, (hit - center) / pt.radius);
    return FragmentOut(s.color, s.distance, s.depth);
}
