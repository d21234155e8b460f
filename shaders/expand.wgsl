// Compute pass: expands each point of a chunk into proxy triangles in one eye's equirect
// image (pixel units, longitude unwrapped; proxies crossing the seam are written twice).
// Driven by src/raster/expand.rs. Prepended: the constants prelude, camera, equirect,
// pole_merge, ods, depth_map, projection, params, chunk, sphere_bounds, image_bounds; appended:
// sphere, and on devices with 64-bit atomics splat_key and splat, whose entry points splat
// small spheres and pass the others to `expand_raycast_bounds`.

@group(0) @binding(0) var<storage, read> params: Params;
@group(0) @binding(1) var<storage, read> points: array<GpuPoint>;
@group(0) @binding(2) var<storage, read_write> vertices: array<ExpandedVertex>;
@group(0) @binding(3) var<storage, read_write> draw_args: DrawArgs;
// One `EyeStats` (src/raster/stats.rs) per eye, indexed by the STAT_* constants.
@group(0) @binding(4) var<storage, read_write> stats: array<atomic<u32>>;

// One proxy vertex, laid out as `ExpandedVertex` in src/raster/expand.rs: unwrapped pixel
// position, billboard coordinates (pack2x16snorm) and point index (| FORCE_RAYCAST).
struct ExpandedVertex {
    position: vec2<f32>,
    uv: u32,
    point: u32,
}

// Arguments of the indirect draw, as wgpu's `DrawIndirectArgs`.
struct DrawArgs {
    vertex_count: atomic<u32>,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

fn count(k: u32, n: u32) {
    count_eye(params.eye, k, n);
}

fn count_eye(eye: u32, k: u32, n: u32) {
    atomicAdd(&stats[eye * STATS_PER_EYE + k], n);
}

fn encode(p: vec2<f32>, uv: vec2<f32>, idx: u32) -> ExpandedVertex {
    return ExpandedVertex(p, pack2x16snorm(uv), idx);
}

// Reserves `n` vertices; returns the first, or 0xffffffff on overflow (counted).
fn reserve(n: u32) -> u32 {
    let base = atomicAdd(&draw_args.vertex_count, n);
    if base + n > params.vertex_capacity {
        atomicSub(&draw_args.vertex_count, n);
        count(STAT_OVERFLOW, 1u);
        return 0xffffffffu;
    }
    count(STAT_VERTICES, n);
    return base;
}

// Writes the quad (p00, p10, p11, p01) as two triangles at `at`, shifted by `dx` pixels.
fn write_quad(at: u32, p: array<vec2<f32>, 4>, uv: array<vec2<f32>, 4>, dx: f32, idx: u32) {
    let s = vec2<f32>(dx, 0.0);
    vertices[at + 0u] = encode(p[0] + s, uv[0], idx);
    vertices[at + 1u] = encode(p[1] + s, uv[1], idx);
    vertices[at + 2u] = encode(p[2] + s, uv[2], idx);
    vertices[at + 3u] = encode(p[0] + s, uv[0], idx);
    vertices[at + 4u] = encode(p[2] + s, uv[2], idx);
    vertices[at + 5u] = encode(p[3] + s, uv[3], idx);
}

// Seam copies of a proxy spanning pixels [x0, x1]: shifts (0, +W and/or -W) to draw it with.
fn seam_shifts(x0: f32, x1: f32, w: f32) -> vec3<f32> {
    // (count, first extra shift, second extra shift)
    var n = 1.0;
    var a = 0.0;
    var c = 0.0;
    if x0 < 0.0 {
        a = w;
        n += 1.0;
    }
    if x1 > w {
        if n > 1.0 {
            c = -w;
        } else {
            a = -w;
        }
        n += 1.0;
    }
    return vec3<f32>(n, a, c);
}

fn emit_rect(r: Rect, idx: u32) {
    let size = params.image_size;
    var lo = r.lo - vec2<f32>(ANGLE_MARGIN);
    var hi = r.hi + vec2<f32>(ANGLE_MARGIN);
    if hi.x - lo.x >= TAU {
        lo.x = -PI;
        hi.x = PI;
    }
    lo.y = max(lo.y, -FRAC_PI_2);
    hi.y = min(hi.y, FRAC_PI_2);
    let c = 0.5 * (lo.x + hi.x);
    let shift = wrap_longitude(c) - c;
    lo.x += shift;
    hi.x += shift;
    let tl = position_of_angles_unwrapped(size, vec2<f32>(lo.x, hi.y));
    let br = position_of_angles_unwrapped(size, vec2<f32>(hi.x, lo.y));
    let p = array<vec2<f32>, 4>(tl, vec2<f32>(br.x, tl.y), br, vec2<f32>(tl.x, br.y));
    let uv = array<vec2<f32>, 4>(vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, 1.0), vec2<f32>(1.0, -1.0),
                                 vec2<f32>(-1.0, -1.0));
    let copies = seam_shifts(tl.x, br.x, size.x);
    let n = u32(copies.x);
    let base = reserve(6u * n);
    if base == 0xffffffffu {
        return;
    }
    write_quad(base, p, uv, 0.0, idx);
    if n > 1u {
        write_quad(base + 6u, p, uv, copies.y, idx);
        count(STAT_SEAM, 1u);
    }
    if n > 2u {
        write_quad(base + 12u, p, uv, copies.z, idx);
    }
    count(STAT_DRAWN, 1u);
}

// Writes each rectangle (pixels, clipped to the image) as a quad.
fn emit_pixel_rects(rects: PixelRects, idx: u32) {
    if rects.n == 0u {
        return;
    }
    let base = reserve(6u * rects.n);
    if base == 0xffffffffu {
        return;
    }
    let uv = array<vec2<f32>, 4>(vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, 1.0), vec2<f32>(1.0, -1.0),
                                 vec2<f32>(-1.0, -1.0));
    // A local copy: arrays are indexed dynamically through memory.
    var rs = rects;
    for (var k = 0u; k < rs.n; k++) {
        let tl = rs.lo[k];
        let br = rs.hi[k];
        let p = array<vec2<f32>, 4>(tl, vec2<f32>(br.x, tl.y), br, vec2<f32>(tl.x, br.y));
        write_quad(base + 6u * k, p, uv, 0.0, idx);
    }
    count(STAT_DRAWN, 1u);
}

// Bounds proxies with ray-cast fragments (in every projection but the full equirect, the only
// kind the sizing allows): the sphere's analytic bounds, forced to ray cast where it is
// special or its centre has no projection.
fn expand_raycast_bounds(p: PointSphere, idx: u32) {
    if projection_of(params).kind != PROJ_EQUIRECT_FULL {
        expand_projected(p.view, p.centre, p.radius, idx);
        return;
    }
    // Only whether the centre projects, not where: skip the ODS solve.
    var flags = 0u;
    if !has_projection(p.view, p.centre) {
        count(STAT_CULLED, 1u);
        flags = FORCE_RAYCAST;
    }
    let bounds = sphere_bounds(p.view, p.centre, p.radius);
    if bounds.special || flags != 0u {
        count(STAT_SPECIAL, 1u);
        flags = FORCE_RAYCAST;
    }
    emit_rect(bounds.rect, idx | flags);
}

// Every projection but the full equirect: the sphere's pixel rectangles.
fn expand_projected(view: View, s: vec3<f32>, radius: f32, idx: u32) {
    let proj = projection_of(params);
    var flags = 0u;
    if proj.kind != PROJ_MAP {
        if !has_projection(view, s) {
            count(STAT_CULLED, 1u);
            flags = FORCE_RAYCAST;
        }
        if flags != 0u || sphere_bounds(view, s, radius).special {
            count(STAT_SPECIAL, 1u);
            flags = FORCE_RAYCAST;
        }
    }
    let rects = image_bounds(view, proj, params.image_size, s, radius);
    emit_pixel_rects(rects, idx | flags);
}

struct Billboard {
    center: vec3<f32>,
    u: vec3<f32>,
    v: vec3<f32>,
    lam_c: f32,
}

// Grid vertex (a, b) in [-1, 1]^2 of the billboard, projected to unwrapped pixels; z = 0 when
// it has no projection.
fn billboard_vertex(view: View, bb: Billboard, a: f32, b: f32) -> vec3<f32> {
    let q = project(view, bb.center + a * bb.u + b * bb.v);
    if !q.ok {
        return vec3<f32>(0.0);
    }
    let lam = bb.lam_c + wrap_longitude(q.angles.x - bb.lam_c);
    return vec3<f32>(position_of_angles_unwrapped(params.image_size, vec2<f32>(lam, q.angles.y)), 1.0);
}

// Tessellation level after Algorithm 1 of Marrinan & Papka, adapted: a straight proxy edge of
// L px at latitude phi bows by about L^2 tan|phi| / (8 P) px from the curve it stands for
// (P = pixels per radian); split edges until the bow is under 1/4 px.
fn dynamic_level(view: View, bb: Billboard, phi_c: f32) -> u32 {
    let p00 = billboard_vertex(view, bb, -1.0, -1.0).xy;
    let p10 = billboard_vertex(view, bb, 1.0, -1.0).xy;
    let p01 = billboard_vertex(view, bb, -1.0, 1.0).xy;
    let p11 = billboard_vertex(view, bb, 1.0, 1.0).xy;
    let edge = max(max(distance(p00, p10), distance(p01, p11)),
                   max(distance(p00, p01), distance(p10, p11)));
    let pixels_per_radian = params.image_size.y / PI;
    let bow = sqrt(tan(min(abs(phi_c), 1.5)) / (2.0 * pixels_per_radian));
    let level = u32(ceil(edge * bow));
    return clamp(level, 1u, MAX_DYNAMIC_LEVEL);
}

// Projects the billboard's (n+1)^2 grid; writes it (with seam copies) or returns false when a
// vertex has no projection.
fn emit_billboard(view: View, bb: Billboard, n: u32, idx: u32) -> bool {
    let w = params.image_size.x;
    var x0 = 3.4e38;
    var x1 = -3.4e38;
    let step = 2.0 / f32(n);
    for (var j = 0u; j <= n; j++) {
        for (var i = 0u; i <= n; i++) {
            let q = billboard_vertex(view, bb, -1.0 + step * f32(i), -1.0 + step * f32(j));
            if q.z == 0.0 {
                return false;
            }
            x0 = min(x0, q.x);
            x1 = max(x1, q.x);
        }
    }
    let copies = seam_shifts(x0, x1, w);
    let ncopies = u32(copies.x);
    let per_copy = 6u * n * n;
    let base = reserve(per_copy * ncopies);
    if base == 0xffffffffu {
        return true;
    }
    let shifts = array<f32, 3>(0.0, copies.y, copies.z);
    for (var j = 0u; j < n; j++) {
        for (var i = 0u; i < n; i++) {
            let a0 = -1.0 + step * f32(i);
            let b0 = -1.0 + step * f32(j);
            let a1 = a0 + step;
            let b1 = b0 + step;
            let p = array<vec2<f32>, 4>(
                billboard_vertex(view, bb, a0, b1).xy, billboard_vertex(view, bb, a1, b1).xy,
                billboard_vertex(view, bb, a1, b0).xy, billboard_vertex(view, bb, a0, b0).xy);
            let uv = array<vec2<f32>, 4>(vec2<f32>(a0, b1), vec2<f32>(a1, b1), vec2<f32>(a1, b0),
                                         vec2<f32>(a0, b0));
            let cell = 6u * (j * n + i);
            for (var c = 0u; c < ncopies; c++) {
                write_quad(base + c * per_copy + cell, p, uv, shifts[c], idx);
            }
        }
    }
    if ncopies > 1u {
        count(STAT_SEAM, 1u);
    }
    count(STAT_DRAWN, 1u);
    return true;
}

@compute @workgroup_size(EXPAND_WORKGROUP)
fn expand(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.batch_count {
        return;
    }
    expand_point(params.batch_first + gid.x);
}

// Point `idx` of the chunk as a sphere: its centre relative to C, radius and view.
struct PointSphere {
    centre: vec3<f32>,
    radius: f32,
    view: View,
}

fn point_sphere(idx: u32) -> PointSphere {
    let pt = points[idx];
    let s = pt.position - params.camera_offset;
    return PointSphere(s, pt.radius, sphere_view(params, s));
}

// Writes the proxy of point `idx` of the chunk, in any proxy mode. The keyed path's
// dispatches (splat.wgsl) call `expand_raycast_bounds` alone: an entry point that reaches the
// billboards' code takes lavapipe about five times as long to compile, though the pipeline
// constants fold it away.
fn expand_point(idx: u32) {
    let p = point_sphere(idx);
    let s = p.centre;
    let radius = p.radius;
    let view = p.view;
    let raycast = imposter_of(params) == IMPOSTER_RAYCAST;
    let proxy = proxy_of(params);
    if projection_of(params).kind != PROJ_EQUIRECT_FULL || (raycast && proxy == PROXY_BOUNDS) {
        expand_raycast_bounds(p, idx);
        return;
    }
    let centre = project(view, s);
    if !centre.ok {
        count(STAT_CULLED, 1u);
        if !raycast {
            return;
        }
    }
    let bounds = sphere_bounds(view, s, radius);
    if bounds.special || !centre.ok {
        count(STAT_SPECIAL, 1u);
        emit_rect(bounds.rect, idx | FORCE_RAYCAST);
        return;
    }
    if proxy == PROXY_BOUNDS {
        emit_rect(bounds.rect, idx);
        return;
    }
    // Billboard facing C, half-size `radius` (the paper's imposter).
    let dir = normalize(s);
    let u = normalize(cross(dir, view.basis.up));
    let v = cross(u, dir);
    let bb = Billboard(s, radius * u, radius * v, centre.angles.x);
    var n = 1u;
    if proxy == PROXY_STATIC {
        n = params.static_level;
    } else if proxy != PROXY_QUAD {
        n = dynamic_level(view, bb, centre.angles.y);
    }
    if !emit_billboard(view, bb, n, idx) {
        count(STAT_SPECIAL, 1u);
        emit_rect(bounds.rect, idx | FORCE_RAYCAST);
    }
}
