// Compute splat: a small sphere is ray cast here, pixel by pixel over its bounds, instead of
// being rasterized; each hit keeps the nearest hit of its pixel as a key (splat_key.wgsl).
// The rays, the intersection and the key are the keyed fragment stage's (imposter_key.wgsl),
// so the result is the same per pixel. Needs SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX.
// Appended to the expand pipeline by src/raster/splat.rs, after splat_key.

// The eye's keys.
@group(0) @binding(5) var<storage, read_write> splat_keys: array<atomic<u64>>;
@group(0) @binding(6) var<storage, read> colors: array<u32>;
// Ray casts `r` (analytic bounds, without margin) pixel by pixel when it spans at most
// `params.splat_limit` pixels per side; false when it is too large (draw it instead).
fn try_splat(view: View, r: Rect, s: vec3<f32>, radius: f32, idx: u32) -> bool {
    let limit = params.splat_limit;
    if limit <= 0.0 {
        return false;
    }
    let size = params.image_size;
    var lo = r.lo - vec2<f32>(ANGLE_MARGIN);
    var hi = r.hi + vec2<f32>(ANGLE_MARGIN);
    lo.y = max(lo.y, -FRAC_PI_2);
    hi.y = min(hi.y, FRAC_PI_2);
    let tl = position_of_angles_unwrapped(size, vec2<f32>(lo.x, hi.y));
    let br = position_of_angles_unwrapped(size, vec2<f32>(hi.x, lo.y));
    // Pixel centres (x + 0.5, y + 0.5) inside [tl, br], as the rasterizer samples them.
    let fx0 = ceil(tl.x - 0.5);
    let fx1 = floor(br.x - 0.5);
    let fy0 = max(ceil(tl.y - 0.5), 0.0);
    let fy1 = min(floor(br.y - 0.5), size.y - 1.0);
    if fx1 - fx0 >= limit || fy1 - fy0 >= limit {
        return false;
    }
    let w = i32(size.x);
    let x0 = i32(fx0);
    let x1 = i32(fx1);
    let payload = sphere_payload(idx);
    for (var y = i32(fy0); y <= i32(fy1); y++) {
        for (var x = x0; x <= x1; x++) {
            let xw = ((x % w) + w) % w;
            let r = table_pixel_ray(view, vec2<u32>(u32(xw), u32(y)));
            let t = intersect_sphere(r, s, radius);
            if t > 0.0 {
                atomicMax(&splat_keys[u32(y * w + xw)], hit_key(t, payload));
            }
        }
    }
    return true;
}

// Ray casts the pixels of `rects` (image_bounds, clipped to the image) with their own
// projection's rays when each spans at most `params.splat_limit` pixels per side; false when
// one is too large (draw them instead).
fn try_splat_rects(view: View, rects: PixelRects, s: vec3<f32>, radius: f32, idx: u32) -> bool {
    let limit = params.splat_limit;
    if limit <= 0.0 {
        return false;
    }
    let size = params.image_size;
    // A local copy: arrays are indexed dynamically through memory.
    var rs = rects;
    for (var k = 0u; k < rs.n; k++) {
        let span = floor(rs.hi[k] - 0.5) - ceil(rs.lo[k] - 0.5);
        if span.x >= limit || span.y >= limit {
            return false;
        }
    }
    let w = i32(size.x);
    let payload = sphere_payload(idx);
    for (var k = 0u; k < rs.n; k++) {
        // Pixel centres (x + 0.5, y + 0.5) inside the rectangle, as the rasterizer samples them.
        let x0 = i32(ceil(rs.lo[k].x - 0.5));
        let x1 = min(i32(floor(rs.hi[k].x - 0.5)), w - 1);
        let y0 = i32(ceil(rs.lo[k].y - 0.5));
        let y1 = min(i32(floor(rs.hi[k].y - 0.5)), i32(size.y) - 1);
        for (var y = max(y0, 0); y <= y1; y++) {
            for (var x = max(x0, 0); x <= x1; x++) {
                let pixel = pixel_ray(view, vec2<u32>(u32(x), u32(y)));
                if !pixel.ok {
                    continue;
                }
                let t = intersect_sphere(pixel.ray, s, radius);
                if t > 0.0 {
                    atomicMax(&splat_keys[u32(y * w + x)], hit_key(t, payload));
                }
            }
        }
    }
    return true;
}
