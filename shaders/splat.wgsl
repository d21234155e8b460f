// Compute splat: a small sphere is ray cast here, pixel by pixel over its bounds, instead of
// being rasterized; each hit keeps the nearest hit of its pixel as a key (splat_key.wgsl).
// The rays, the intersection and the key are the keyed fragment stage's (imposter_key.wgsl),
// so the result is the same per pixel. Needs SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX.
// Appended to the expand module by src/raster/splat.rs, after splat_key.
//
// Two entry points per batch: `expand_splat` ray casts every sphere it can and lists the
// rest (too large, special, or with no projected centre); `expand_listed`, dispatched
// indirectly over that list, gives them to expand.wgsl's `expand_raycast_bounds` to be
// drawn. With the drawing code out of the splat's dispatch, frames on llvmpipe measured
// faster. Both skip spheres hidden whole by nearer ones (occlusion.wgsl). An ODS pair's
// first eye dispatches `expand_splat_pair` in place of `expand_splat`, for both eyes; each
// eye then dispatches `expand_listed`. The pair splat leaves the spheres of more than
// WIDE_PIXELS pixels to `splat_wide_pair`, dispatched indirectly before `expand_listed`,
// which casts each with a workgroup: in one invocation a wide sphere would hold the other
// lanes of its SIMD vector idle for its whole loop (on llvmpipe, 8 spheres a vector).

// The eye's keys.
@group(0) @binding(5) var<storage, read_write> splat_keys: array<atomic<u64>>;
@group(0) @binding(6) var<storage, read> colors: array<u32>;

// The spheres left to draw, their count and point indices from the start, and the wide
// spheres of a pair splat, their count and indices from the end (a batch's points in all; the
// counts are cleared before each batch); and the indirect dispatch arguments of
// `expand_listed` and `splat_wide_pair` (each cleared to (0, 1, 1)), bound to the splat's
// dispatch only.
struct ListedPoints {
    count: atomic<u32>,
    wide: atomic<u32>,
    points: array<u32>,
}
struct ListedGroups {
    x: atomic<u32>,
    y: u32,
    z: u32,
    wide_x: atomic<u32>,
    wide_y: u32,
    wide_z: u32,
}

// Pixels of a pair's sphere above which `splat_wide_pair` casts it.
const WIDE_PIXELS: i32 = 32;
// `splat_wide_pair`'s invocations per sphere: one SIMD vector of llvmpipe on AVX2.
const WIDE_LANES: u32 = 8u;
// Most workgroups `splat_wide_pair` is dispatched (a dimension's limit); each takes every
// so-many-th wide sphere.
const MAX_WIDE_GROUPS: u32 = 65535u;
@group(0) @binding(7) var<storage, read_write> listed: ListedPoints;
@group(0) @binding(8) var<storage, read_write> listed_groups: ListedGroups;

// The other eye of an ODS pair, for `expand_splat_pair`: its keys and occlusion tiles. The
// other dispatches bind their own eye's here again.
@group(0) @binding(10) var<storage, read_write> pair_keys: array<atomic<u64>>;
@group(0) @binding(11) var<storage, read_write> pair_tile_far: array<atomic<u32>>;

// Which eye's keys and tiles: the dispatch's own (`params.eye`) or the other of its pair.
const SLOT_OWN: u32 = 0u;
const SLOT_PAIR: u32 = 1u;

// Tile `i` of eye `slot`. Callers pass a constant, so the other branch folds away.
fn tile_far_of(slot: u32, i: u32) -> u32 {
    if slot == SLOT_PAIR {
        return atomicLoad(&pair_tile_far[i]);
    }
    return atomicLoad(&tile_far[i]);
}

// What `splat_point` did with a sphere.
const SPLAT_NOTHING: u32 = 0u;
const SPLAT_DONE: u32 = 1u;
const SPLAT_LISTED: u32 = 2u;
const SPLAT_HIDDEN: u32 = 3u;

@compute @workgroup_size(EXPAND_WORKGROUP)
fn expand_splat(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.batch_count {
        return;
    }
    let idx = params.batch_first + gid.x;
    let done = splat_point(point_sphere(idx), idx);
    if done == SPLAT_DONE {
        count(STAT_SPLATTED, 1u);
    } else if done == SPLAT_HIDDEN {
        count(STAT_OCCLUDED, 1u);
    } else if done == SPLAT_LISTED {
        list_point(idx);
    }
}

// The ODS pair's splat, in place of `expand_splat` for both eyes: the eyes' views differ only
// in the sign of the eye (src/raster/raster_frame.rs checks it), so one dispatch ray casts
// each sphere for both, loading a pixel's table entries once, and each eye keeps its own
// bounds, tiles, keys and counts: its keys are bit for bit those of `expand_splat`. A sphere
// that either eye draws is listed for both; `expand_listed` then runs once per eye.
@compute @workgroup_size(EXPAND_WORKGROUP)
fn expand_splat_pair(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.batch_count {
        return;
    }
    let idx = params.batch_first + gid.x;
    let p = point_sphere(idx);
    let px = pair_pixels(p);
    if !px.ok || too_large(px.a) || too_large(px.b) {
        list_point(idx);
        return;
    }
    let hide = pair_hidden(p, px);
    count(select(STAT_SPLATTED, STAT_OCCLUDED, hide.x), 1u);
    count_eye(1u - params.eye, select(STAT_SPLATTED, STAT_OCCLUDED, hide.y), 1u);
    if all(hide) {
        return;
    }
    let runs = pair_runs(px.a, px.b, hide);
    if runs.len * (runs.rows.y - runs.rows.x + 1) > WIDE_PIXELS {
        count(STAT_WIDE, 1u);
        list_wide(idx);
    } else {
        splat_pair_pixels(p, other_eye(p), px.a, runs, hide, idx, 0, 1);
    }
}

// The wide spheres `expand_splat_pair` listed, a workgroup each: its lanes share each row's
// columns. The keys are those `expand_splat_pair` would have cast, and the tiles are as it
// saw them (`expand_listed`, which raises them, runs after), so each eye is hidden as there.
@compute @workgroup_size(WIDE_LANES)
fn splat_wide_pair(@builtin(workgroup_id) group: vec3<u32>,
                   @builtin(num_workgroups) groups: vec3<u32>,
                   @builtin(local_invocation_index) lane: u32) {
    let n = atomicLoad(&listed.wide);
    let end = arrayLength(&listed.points);
    for (var s = group.x; s < n; s += groups.x) {
        let idx = listed.points[end - 1u - s];
        let p = point_sphere(idx);
        let px = pair_pixels(p);
        let hide = pair_hidden(p, px);
        splat_pair_pixels(p, other_eye(p), px.a, pair_runs(px.a, px.b, hide), hide, idx,
                          i32(lane), i32(WIDE_LANES));
    }
}

// Sphere `p` seen by the other eye of its pair.
fn other_eye(p: PointSphere) -> PointSphere {
    var q = p;
    q.view.eye_sign = -p.view.eye_sign;
    return q;
}

// Both eyes' pixels of a pair's sphere (bounds_pixels): `a` of `p`'s eye, `b` of the other;
// not ok where either is not ordinary.
struct PairPixels {
    ok: bool,
    a: vec4<i32>,
    b: vec4<i32>,
}

fn pair_pixels(p: PointSphere) -> PairPixels {
    let q = other_eye(p);
    let both = ordinary_bounds(p);
    let o = eye_pixels(both, p.view.eye_sign);
    var oq: OrdinaryPixels;
    if q.view.model == MODEL_PARALLEL {
        // A parallel eye sees from its own camera.
        oq = ordinary_pixels(q);
    } else {
        oq = eye_pixels(both, q.view.eye_sign);
    }
    return PairPixels(o.ok && oq.ok, o.px, oq.px);
}

// Whether each eye's tiles hide the sphere: both eyes' rays start within the same reach of
// C, square to their directions.
fn pair_hidden(p: PointSphere, px: PairPixels) -> vec2<bool> {
    let near = nearest_possible(p);
    return vec2<bool>(hidden_by_tiles(SLOT_OWN, px.a, near),
                      hidden_by_tiles(SLOT_PAIR, px.b, near));
}

@compute @workgroup_size(EXPAND_WORKGROUP)
fn expand_listed(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&listed.count) {
        return;
    }
    let idx = listed.points[gid.x];
    let p = point_sphere(idx);
    let o = ordinary_pixels(p);
    if !o.ok {
        expand_raycast_bounds(p, idx);
        return;
    }
    // An ordinary sphere is tested against the tiles, drawn as its bounds (as
    // `expand_raycast_bounds` would, from the same bounds), then covers them.
    if hidden_by_tiles(SLOT_OWN, o.px, nearest_possible(p)) {
        count(STAT_OCCLUDED, 1u);
        return;
    }
    emit_rect(o.rect, idx);
    cover_tiles(p, o.px);
}

// A sphere's analytic bounds in the full equirect and their pixels (`bounds_pixels`); not ok
// where the sphere is not ordinary: its centre has no projection or it is special.
struct OrdinaryPixels {
    ok: bool,
    rect: Rect,
    px: vec4<i32>,
}

fn ordinary_pixels(p: PointSphere) -> OrdinaryPixels {
    return eye_pixels(ordinary_bounds(p), p.view.eye_sign);
}

// `p`'s shared_bounds, `ok` where it is ordinary (not special): an ODS view's two eyes share
// it.
struct OrdinaryBounds {
    ok: bool,
    bounds: SharedBounds,
}

// Bounds that are not special imply a projected centre (the ball lies off the viewing
// cylinder, beyond every circle radius), so `has_projection` is not asked: it costs a merge
// factor and an atan2 per point.
fn ordinary_bounds(p: PointSphere) -> OrdinaryBounds {
    let none = OrdinaryBounds(false, SharedBounds(full_rect(), vec2<f32>(0.0), true));
    if projection_of(params).kind != PROJ_EQUIRECT_FULL {
        return none;
    }
    let b = shared_bounds(p.view, p.centre, p.radius);
    return OrdinaryBounds(!b.special, b);
}

// The pixels of the eye of sign `e` from its ordinary bounds `o`.
fn eye_pixels(o: OrdinaryBounds, e: f32) -> OrdinaryPixels {
    if !o.ok {
        return OrdinaryPixels(false, full_rect(), vec4<i32>(0));
    }
    let rect = eye_bounds(o.bounds, e).rect;
    return OrdinaryPixels(true, rect, bounds_pixels(rect));
}

// Appends point `idx` to the list, counting a workgroup of `expand_listed` per
// EXPAND_WORKGROUP points.
fn list_point(idx: u32) {
    let slot = atomicAdd(&listed.count, 1u);
    if slot % EXPAND_WORKGROUP == 0u {
        atomicAdd(&listed_groups.x, 1u);
    }
    listed.points[slot] = idx;
}

// Appends point `idx` to the wide spheres, from the list's end, counting a workgroup of
// `splat_wide_pair` per sphere up to MAX_WIDE_GROUPS.
fn list_wide(idx: u32) {
    let slot = atomicAdd(&listed.wide, 1u);
    if slot < MAX_WIDE_GROUPS {
        atomicAdd(&listed_groups.wide_x, 1u);
    }
    listed.points[arrayLength(&listed.points) - 1u - slot] = idx;
}

// Ray casts point `idx`'s sphere `p` when `expand_raycast_bounds` would draw its bounds (the
// keyed path's only proxy) and they are small enough; SPLAT_LISTED when it is to be drawn,
// SPLAT_NOTHING when it has no pixel in the image, SPLAT_HIDDEN when nearer spheres hide it.
fn splat_point(p: PointSphere, idx: u32) -> u32 {
    let view = p.view;
    let s = p.centre;
    let radius = p.radius;
    let proj = projection_of(params);
    if proj.kind == PROJ_EQUIRECT_FULL {
        let o = ordinary_pixels(p);
        if !o.ok {
            return SPLAT_LISTED;
        }
        let px = o.px;
        if too_large(px) {
            return SPLAT_LISTED;
        }
        if hidden_by_tiles(SLOT_OWN, px, nearest_possible(p)) {
            return SPLAT_HIDDEN;
        }
        splat_pixels(view, px, s, radius, idx);
        return SPLAT_DONE;
    }
    // A centre without projection makes the bounds special (see `ordinary_bounds`).
    if proj.kind != PROJ_MAP && sphere_bounds(view, s, radius).special {
        return SPLAT_LISTED;
    }
    let rects = image_bounds(view, proj, params.image_size, s, radius);
    if rects.n == 0u {
        return SPLAT_NOTHING;
    }
    if !try_splat_rects(view, rects, s, radius, idx) {
        return SPLAT_LISTED;
    }
    return SPLAT_DONE;
}

// Whether pixels `px` (bounds_pixels) span too many pixels a side to be splatted.
fn too_large(px: vec4<i32>) -> bool {
    let limit = i32(params.splat_limit);
    return px.z - px.x >= limit || px.w - px.y >= limit;
}

// Pixel centres (x0, y0)..(x1, y1) (columns unwrapped, rows clipped to the image) inside
// analytic bounds `r` (without margin), as the rasterizer samples them.
fn bounds_pixels(r: Rect) -> vec4<i32> {
    let size = params.image_size;
    var lo = r.lo - vec2<f32>(ANGLE_MARGIN);
    var hi = r.hi + vec2<f32>(ANGLE_MARGIN);
    lo.y = max(lo.y, -FRAC_PI_2);
    hi.y = min(hi.y, FRAC_PI_2);
    let tl = position_of_angles_unwrapped(size, vec2<f32>(lo.x, hi.y));
    let br = position_of_angles_unwrapped(size, vec2<f32>(hi.x, lo.y));
    return vec4<i32>(vec4<f32>(ceil(tl.x - 0.5), max(ceil(tl.y - 0.5), 0.0), floor(br.x - 0.5),
                               min(floor(br.y - 0.5), size.y - 1.0)));
}

// Unwrapped column `x` in the image, for x within one width of it (bounds_pixels' columns
// are: a box's longitudes lie within 2 pi of 0). Not `%`: llvmpipe divides integers one lane
// at a time.
fn wrap_column(x: i32) -> i32 {
    let w = i32(params.image_size.x);
    return select(select(x, x - w, x >= w), x + w, x < 0);
}

// Ray casts sphere (s, radius) at pixels `px` (bounds_pixels).
fn splat_pixels(view: View, px: vec4<i32>, s: vec3<f32>, radius: f32, idx: u32) {
    let w = i32(params.image_size.x);
    let payload = sphere_payload(idx);
    for (var y = px.y; y <= px.w; y++) {
        for (var x = px.x; x <= px.z; x++) {
            let xw = wrap_column(x);
            let r = table_pixel_ray(view, vec2<u32>(u32(xw), u32(y)));
            let t = intersect_sphere(r, s, radius);
            if t > 0.0 {
                atomicMax(&splat_keys[u32(y * w + xw)], hit_key(t, payload));
            }
        }
    }
}

// Where a pair's sphere is cast, row by row: one run of columns where the eyes' columns meet
// (far spheres: each pixel's table entries serve both), else each eye's own (near ones, whose
// eyes' boxes lie apart). `b` is the other eye's pixels, its columns on `a`'s side of the
// seam; a hidden eye's run is empty (last < first).
struct PairRuns {
    b: vec4<i32>,
    run_a: vec2<i32>,
    run_b: vec2<i32>,
    // Columns of run_a, and of both runs.
    len_a: i32,
    len: i32,
    // First and last row.
    rows: vec2<i32>,
}

fn pair_runs(a: vec4<i32>, b_own: vec4<i32>, hide: vec2<bool>) -> PairRuns {
    let w = i32(params.image_size.x);
    // b's columns a turn over where they lie across the seam from a's (a parallel eye's box
    // can, seen from its own camera; an ODS pair's come from one box). Without it the box
    // would span the image: slower, not wrong.
    let turn = select(select(0, w, b_own.x + w / 2 < a.x), -w, b_own.x - w / 2 > a.x);
    let b = b_own + vec4<i32>(turn, 0, turn, 0);
    let none = vec2<i32>(0, -1);
    var run_a = select(a.xz, none, hide.x);
    var run_b = select(b.xz, none, hide.y);
    if run_a.x <= run_a.y && run_b.x <= run_b.y && run_b.x <= run_a.y + 1
        && run_a.x <= run_b.y + 1 {
        run_a = vec2<i32>(min(run_a.x, run_b.x), max(run_a.y, run_b.y));
        run_b = none;
    }
    let len_a = max(run_a.y - run_a.x + 1, 0);
    let len = len_a + max(run_b.y - run_b.x + 1, 0);
    return PairRuns(b, run_a, run_b, len_a, len, vec2<i32>(min(a.y, b.y), max(a.w, b.w)));
}

// Ray casts sphere `p` at pixels `a` and `q` (the same sphere seen by the other eye) at
// `runs.b`, except for an eye in `hide`: of each row's columns, those from `lane` in steps of
// `lanes` (0 and 1: all).
fn splat_pair_pixels(p: PointSphere, q: PointSphere, a: vec4<i32>, runs: PairRuns,
                     hide: vec2<bool>, idx: u32, lane: i32, lanes: i32) {
    let w = i32(params.image_size.x);
    let payload = sphere_payload(idx);
    for (var y = runs.rows.x; y <= runs.rows.y; y++) {
        for (var k = lane; k < runs.len; k += lanes) {
            let x = select(runs.run_b.x + (k - runs.len_a), runs.run_a.x + k, k < runs.len_a);
            let xw = wrap_column(x);
            let at = table_pixel_trig(vec2<u32>(u32(xw), u32(y)));
            let i = u32(y * w + xw);
            let t = intersect_sphere(ray_of_merge(p.view, at.trig, at.merge), p.centre,
                                     p.radius);
            if t > 0.0 && !hide.x && inside_pixels(a, x, y) {
                atomicMax(&splat_keys[i], hit_key(t, payload));
            }
            let u = intersect_sphere(ray_of_merge(q.view, at.trig, at.merge), q.centre,
                                     q.radius);
            if u > 0.0 && !hide.y && inside_pixels(runs.b, x, y) {
                atomicMax(&pair_keys[i], hit_key(u, payload));
            }
        }
    }
}

// Whether pixel (x, y) (column unwrapped as px's) lies in pixels `px`.
fn inside_pixels(px: vec4<i32>, x: i32, y: i32) -> bool {
    return x >= px.x && x <= px.z && y >= px.y && y <= px.w;
}

// Ray casts the pixels of `rects` (image_bounds, clipped to the image) with their own
// projection's rays when each spans at most `params.splat_limit` pixels per side; false when
// one is too large (draw them instead).
fn try_splat_rects(view: View, rects: PixelRects, s: vec3<f32>, radius: f32, idx: u32) -> bool {
    let limit = params.splat_limit;
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
