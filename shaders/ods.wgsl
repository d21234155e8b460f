// Mirrors src/projection/ods.rs: the ODS ray and its exact inverse (DESIGN §3).
// Everything is relative to the camera centre C, so f32 keeps sub-millimetre precision.

struct View {
    basis: Basis,
    // -1 left, +1 right, 0 mono.
    eye_sign: f32,
    half_ipd: f32,
    north: PoleMerge,
    south: PoleMerge,
    // OFFSET_EXACT (the exact inverse) or OFFSET_PAPER (the paper's per-vertex offset).
    offset: u32,
    // MODEL_ODS (rays on the viewing circle) or MODEL_PARALLEL (rays from C + e (ipd/2) R).
    model: u32,
}

struct Ray {
    // Relative to C.
    origin: vec3<f32>,
    dir: vec3<f32>,
}

// Projection result: `angles` valid only when `ok`.
struct Projected {
    angles: vec2<f32>,
    ok: bool,
}

// asin through atan2: llvmpipe's asin is off by ~2e-4 rad near 0.5 (Vulkan allows asin the
// error of atan2(x, sqrt(1 - x^2)) only), while its atan2 holds f32 accuracy.
fn asin_accurate(x: f32) -> f32 {
    return atan2(x, sqrt(max((1.0 - x) * (1.0 + x), 0.0)));
}

// f32 bisection halves [0, ipd/2] to below f32 resolution in 24 steps.
const BISECTION_STEPS: i32 = 24;

// Viewing-circle radius r(phi) = (ipd / 2) merge(phi).
fn circle_radius(v: View, phi: f32) -> f32 {
    if v.half_ipd == 0.0 {
        return 0.0;
    }
    return v.half_ipd * pole_merging_factor(v.north, v.south, phi);
}

// True for a parallel camera's eye (every ray starts at `parallel_camera`).
fn is_parallel_eye(v: View) -> bool {
    return v.model == MODEL_PARALLEL && v.eye_sign != 0.0;
}

// The parallel camera of this eye relative to C, e (ipd/2) R (zero for mono).
fn parallel_camera(v: View) -> vec3<f32> {
    return v.eye_sign * v.half_ipd * v.basis.right;
}

// The ray of (lam, phi): origin relative to C and unit direction.
fn ray(v: View, lam: f32, phi: f32) -> Ray {
    let b = v.basis;
    let dir = direction(b, lam, phi);
    if v.eye_sign == 0.0 {
        return Ray(vec3<f32>(0.0), dir);
    }
    if v.model == MODEL_PARALLEL {
        return Ray(parallel_camera(v), dir);
    }
    let sl = sin(lam);
    let cl = cos(lam);
    let side = cl * b.right - sl * b.forward;
    return Ray(v.eye_sign * circle_radius(v, phi) * side, dir);
}

// `ray` from the sines and cosines of the longitude and latitude, t = (sin lam, cos lam,
// sin phi, cos phi), and the latitude `phi` (for the merge factor only): for projections that
// get them algebraically, since f32 atan2 followed by sin and cos would cost ~1e-5 rad.
fn ray_of_trig(v: View, t: vec4<f32>, phi: f32) -> Ray {
    return ray_of_merge(v, t, pole_merging_factor(v.north, v.south, phi));
}

// `ray_of_trig` with the merge factor at the latitude already known (r = (ipd/2) merge).
fn ray_of_merge(v: View, t: vec4<f32>, merge: f32) -> Ray {
    let b = v.basis;
    let dir = t.w * (t.x * b.right + t.y * b.forward) + t.z * b.up;
    if v.eye_sign == 0.0 {
        return Ray(vec3<f32>(0.0), dir);
    }
    if v.model == MODEL_PARALLEL {
        return Ray(parallel_camera(v), dir);
    }
    let side = t.y * b.right - t.x * b.forward;
    return Ray(v.eye_sign * (v.half_ipd * merge) * side, dir);
}

fn latitude_for_radius(rho: f32, z: f32, r: f32) -> f32 {
    return atan2(z, sqrt(max(rho * rho - r * r, 0.0)));
}

// Solves r = r(phi(r)) for horizontal distance `rho` and height `z`; -1 when the point lies
// inside the viewing circle.
fn solve_circle_radius(v: View, rho: f32, z: f32) -> f32 {
    if circle_radius(v, latitude_for_radius(rho, z, rho)) > rho {
        return -1.0;
    }
    if rho == 0.0 {
        return 0.0;
    }
    var r = min(circle_radius(v, atan2(z, rho)), rho);
    for (var k = 0; k < FIXED_POINT_ITERATIONS; k++) {
        let next = min(circle_radius(v, latitude_for_radius(rho, z, r)), rho);
        if abs(next - r) <= 1e-7 * v.half_ipd {
            return next;
        }
        r = next;
    }
    var lo = 0.0;
    var hi = min(rho, v.half_ipd);
    for (var k = 0; k < BISECTION_STEPS; k++) {
        let mid = 0.5 * (lo + hi);
        if circle_radius(v, latitude_for_radius(rho, z, mid)) > mid {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

// Point `p` (relative to C) in the rig frame (right, forward, up) seen from the eye's
// camera: C itself, or a parallel eye's camera.
fn eye_frame(v: View, p: vec3<f32>) -> vec3<f32> {
    var q = p;
    if is_parallel_eye(v) {
        q = p - parallel_camera(v);
    }
    let b = v.basis;
    return vec3<f32>(dot(q, b.right), dot(q, b.forward), dot(q, b.up));
}

// True when `project(v, p)` is ok, without its fixed-point solve: the solve fails only on
// its first test (the point lies inside the viewing circle).
fn has_projection(v: View, p: vec3<f32>) -> bool {
    let e = eye_frame(v, p);
    let x = e.x;
    let y = e.y;
    let z = e.z;
    let rho = length(vec2<f32>(x, y));
    if v.eye_sign == 0.0 || v.half_ipd == 0.0 || v.offset != OFFSET_EXACT
        || v.model == MODEL_PARALLEL {
        return !(rho == 0.0 && z == 0.0);
    }
    return !(circle_radius(v, latitude_for_radius(rho, z, rho)) > rho);
}

// Longitude and latitude of point `p` (relative to C) in this view; not ok when `p` has no
// projection (inside the viewing circle, or at C; for a parallel eye, at its camera).
fn project(v: View, p: vec3<f32>) -> Projected {
    let e = eye_frame(v, p);
    let x = e.x;
    let y = e.y;
    let z = e.z;
    let rho = length(vec2<f32>(x, y));
    let lam_c = atan2(x, y);
    if v.eye_sign == 0.0 || v.half_ipd == 0.0 || v.model == MODEL_PARALLEL {
        if rho == 0.0 && z == 0.0 {
            return Projected(vec2<f32>(0.0), false);
        }
        return Projected(vec2<f32>(lam_c, atan2(z, rho)), true);
    }
    if v.offset == OFFSET_EXACT {
        let r = solve_circle_radius(v, rho, z);
        if r < 0.0 {
            return Projected(vec2<f32>(0.0), false);
        }
        let phi = latitude_for_radius(rho, z, r);
        var dlam = 0.0;
        if r > 0.0 {
            dlam = asin_accurate(min(r / rho, 1.0));
        }
        return Projected(vec2<f32>(wrap_longitude(lam_c - v.eye_sign * dlam), phi), true);
    }
    if rho == 0.0 && z == 0.0 {
        return Projected(vec2<f32>(0.0), false);
    }
    let r = circle_radius(v, atan2(z, rho));
    let phi = atan2(z, length(vec2<f32>(rho, r)));
    var dlam = 0.0;
    if rho > 0.0 {
        dlam = atan(r / rho);
    }
    return Projected(vec2<f32>(wrap_longitude(lam_c - v.eye_sign * dlam), phi), true);
}
