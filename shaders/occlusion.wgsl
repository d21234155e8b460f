// Occlusion by tiles, on the keyed path: each tile of an eye (tiles.wgsl) keeps a distance
// within which every pixel of it is known to show a hit, so a sphere whose nearest possible
// point lies beyond that in every tile it touches is skipped whole, leaving the image bit for
// bit the same. The drawn spheres (`expand_listed`) record the tiles inside their
// silhouettes, and between batches tile_resolve.wgsl raises each tile to what its pixels
// show; the splat and the drawn spheres of later batches and chunks test against them.
// Appended to the expand module after splat.wgsl and tiles.wgsl.

// How far from C the rays of view `v` start: half the IPD for a stereo eye, 0 for mono.
fn ray_origin_reach(v: View) -> f32 {
    if v.eye_sign != 0.0 {
        return v.half_ipd;
    }
    return 0.0;
}

// Distance below which no ray of `p`'s view meets it, less a rounding margin. Every ray
// starts within h of C, so no hit is nearer than |centre| - radius - h. An ODS ray also
// starts square to its direction u, so its hit lies at least centre.u - radius along it, and
// u is within the cone of the ball of radius + h around the centre, seen from C.
fn nearest_possible(p: PointSphere) -> f32 {
    let h = ray_origin_reach(p.view);
    let d = length(p.centre);
    var near = d - p.radius - h;
    let sin_cone = (p.radius + h) / d;
    if h > 0.0 && p.view.model != MODEL_PARALLEL && sin_cone < 1.0 {
        near = max(near, d * sqrt(1.0 - sin_cone * sin_cone) - p.radius);
    }
    return near - 1e-4 * (d + p.radius + h);
}

// Unwrapped columns [x0, x1] wrapped into [0, W): (first, last) of one range, then of a
// second past the seam (empty, first > last, when there is none).
fn wrapped_columns(x0: i32, x1: i32) -> vec4<i32> {
    let w = i32(params.image_size.x);
    if x1 - x0 + 1 >= w {
        return vec4<i32>(0, w - 1, 1, 0);
    }
    let a = wrap_column(x0);
    let b = a + (x1 - x0);
    if b < w {
        return vec4<i32>(a, b, 1, 0);
    }
    return vec4<i32>(a, w - 1, 0, b - w);
}

// True when every tile of eye `slot` (SLOT_OWN or SLOT_PAIR) that pixels `px` (x0, y0, x1,
// y1; columns unwrapped) touch shows a hit nearer than `near` at each of its pixels.
fn hidden_by_tiles(slot: u32, px: vec4<i32>, near: f32) -> bool {
    if near <= 0.0 || px.w < px.y || px.z < px.x {
        return false;
    }
    let key = ~bitcast<u32>(near);
    let across = tiles_across();
    let cols = wrapped_columns(px.x, px.z);
    let ty0 = u32(px.y) / TILE_SIDE;
    let ty1 = u32(px.w) / TILE_SIDE;
    for (var part = 0; part < 2; part++) {
        let first = select(cols.z, cols.x, part == 0);
        let last = select(cols.w, cols.y, part == 0);
        if first > last {
            continue;
        }
        let tx0 = u32(first) / TILE_SIDE;
        let tx1 = u32(last) / TILE_SIDE;
        for (var ty = ty0; ty <= ty1; ty++) {
            for (var tx = tx0; tx <= tx1; tx++) {
                if tile_far_of(slot, ty * across + tx) <= key {
                    return false;
                }
            }
        }
    }
    return true;
}

// Tiles [t0, t1] of an axis of `n` pixels whose pixels all lie in [a, b]: (first, last).
fn whole_tiles(a: i32, b: i32, n: i32) -> vec2<i32> {
    let side = i32(TILE_SIDE);
    var last = b / side;
    if min(last * side + side - 1, n - 1) > b {
        last -= 1;
    }
    return vec2<i32>((a + side - 1) / side, last);
}

// Records that sphere `p`, drawn over pixels `px` (x0, y0, x1, y1; columns unwrapped), is hit
// at every pixel of the tiles inside its silhouette, and within what distance. Per tile, take
// the ray origin o0 of its first pixel: the others' origins lie within
// delta = h (dlam + |dmerge|) of it (an ODS origin is e h merge(phi) times a unit vector
// turning with the longitude). A ray whose
// direction's line from o0 passes within radius - delta of the centre then passes within the
// radius from its own origin, in front of it: it hits, at most |centre - o0| + delta away.
// That is tested at the tile's corner pixels: over a small longitude-latitude box the angle
// to a direction is largest at a corner.
fn cover_tiles(p: PointSphere, px: vec4<i32>) {
    let h = ray_origin_reach(p.view);
    if px.w < px.y || px.z < px.x {
        return;
    }
    let across = tiles_across();
    let side = i32(TILE_SIDE);
    let size = vec2<i32>(params.image_size);
    let rows = whole_tiles(px.y, px.w, size.y);
    let cols = wrapped_columns(px.x, px.z);
    // Longitude between a tile's first and last pixel columns.
    let dlam = f32(TILE_SIDE) * TAU / params.image_size.x;
    for (var part = 0; part < 2; part++) {
        let first = select(cols.z, cols.x, part == 0);
        let last = select(cols.w, cols.y, part == 0);
        if first > last {
            continue;
        }
        let tiles = whole_tiles(first, last, size.x);
        for (var ty = rows.x; ty <= rows.y; ty++) {
            let y0 = ty * side;
            let y1 = min(y0 + side - 1, size.y - 1);
            let delta = h * (dlam + merge_spread(y0, y1));
            for (var tx = tiles.x; tx <= tiles.y; tx++) {
                let x0 = tx * side;
                let x1 = min(x0 + side - 1, size.x - 1);
                let first = table_pixel_ray(p.view, vec2<u32>(u32(x0), u32(y0)));
                let c = p.centre - first.origin;
                let d = length(c);
                let reach = (p.radius - delta) - (1e-4 * p.radius + 1e-6 * d);
                if reach > 0.0
                    && inside_silhouette(c, reach, first.dir)
                    && inside_silhouette(c, reach, corner_dir(p.view, x1, y0))
                    && inside_silhouette(c, reach, corner_dir(p.view, x0, y1))
                    && inside_silhouette(c, reach, corner_dir(p.view, x1, y1)) {
                    let far = (d + delta) * (1.0 + 1e-4);
                    atomicMax(&tile_far[u32(ty) * across + u32(tx)], ~bitcast<u32>(far));
                }
            }
        }
    }
}

// Row `y`'s pole-merge factor, from the pixel trigonometry.
fn row_merge(y: i32) -> f32 {
    return pixel_trig[u32(params.image_size.x) + u32(y)].z;
}

// How much the pole-merge factor can vary between rows y0 and y1: within a hemisphere it
// does not grow with |phi|, so it lies between theirs; across the equator, between the
// smaller of theirs and 1.
fn merge_spread(y0: i32, y1: i32) -> f32 {
    let m0 = row_merge(y0);
    let m1 = row_merge(y1);
    let rows = i32(params.image_size.y);
    if (2 * y0 + 1 < rows) != (2 * y1 + 1 < rows) {
        return 1.0 - min(m0, m1);
    }
    return abs(m0 - m1);
}

// The ray direction of pixel (x, y).
fn corner_dir(v: View, x: i32, y: i32) -> vec3<f32> {
    return table_pixel_ray(v, vec2<u32>(u32(x), u32(y))).dir;
}

// Whether the line along `dir` passes within `reach` of `c` (the centre relative to the
// line's origin), on its side of the origin.
fn inside_silhouette(c: vec3<f32>, reach: f32, dir: vec3<f32>) -> bool {
    return dot(c, dir) > 0.0 && length(cross(c, dir)) <= reach;
}
