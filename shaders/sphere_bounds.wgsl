// Mirrors src/projection/sphere_bounds.rs: the longitude/latitude box of a sphere's image in
// one view (docs/SPHERE_BOUNDS.md). Needs camera, equirect, pole_merge and ods.

struct Rect {
    // (lam, phi) corners; lam may leave [-pi, pi).
    lo: vec2<f32>,
    hi: vec2<f32>,
}

struct Bounds {
    rect: Rect,
    special: bool,
}

fn full_rect() -> Rect {
    return Rect(vec2<f32>(-PI, -FRAC_PI_2), vec2<f32>(PI, FRAC_PI_2));
}

fn merge(v: View, phi: f32) -> f32 {
    return pole_merging_factor(v.north, v.south, phi);
}

// Longitude/latitude box of the cone of directions from C to a ball of `radius` around `s`
// (|s| > radius): latitude phi +- asin(radius/|s|), longitude +- asin(radius/rho); a band to
// the pole when the ball meets the vertical axis (radius >= rho).
fn cap_rect(b: Basis, s: vec3<f32>, radius: f32) -> Rect {
    let x = dot(s, b.right);
    let y = dot(s, b.forward);
    let z = dot(s, b.up);
    let rho = length(vec2<f32>(x, y));
    let d = length(s);
    let a = asin_accurate(min(radius / d, 1.0));
    let phi = atan2(z, rho);
    if radius >= rho * (1.0 - 1e-4) {
        if z > 0.0 {
            return Rect(vec2<f32>(-PI, phi - a), vec2<f32>(PI, FRAC_PI_2));
        }
        return Rect(vec2<f32>(-PI, -FRAC_PI_2), vec2<f32>(PI, phi + a));
    }
    let lam = atan2(x, y);
    let half = asin_accurate(radius / rho);
    return Rect(vec2<f32>(lam - half, phi - a), vec2<f32>(lam + half, phi + a));
}

// Conservative box of every (lam, phi) whose ray (this eye) hits the sphere (s, radius).
fn sphere_bounds(v: View, centre: vec3<f32>, radius: f32) -> Bounds {
    return eye_bounds(shared_bounds(v, centre, radius), v.eye_sign);
}

// The part of sphere_bounds an ODS view's two eyes share: the box before the eye's longitude
// offset lam -= e o (o between `offsets.x` and `offsets.y`; both 0 where there is none). A
// parallel eye's is its own.
struct SharedBounds {
    rect: Rect,
    offsets: vec2<f32>,
    special: bool,
}

// The box of the eye of sign `e`.
fn eye_bounds(b: SharedBounds, e: f32) -> Bounds {
    let o1 = e * b.offsets.x;
    let o2 = e * b.offsets.y;
    let lo = vec2<f32>(b.rect.lo.x - max(o1, o2), b.rect.lo.y);
    let hi = vec2<f32>(b.rect.hi.x - min(o1, o2), b.rect.hi.y);
    return Bounds(Rect(lo, hi), b.special);
}

// Exact-inverse argument: a hit X projects to its pixel, lam(X) = lamC(X) - e asin(r/rho(X)),
// tan phi(X) = k tan phiC(X) with k = rho / sqrt(rho^2 - r^2); bound each factor over the ball.
fn shared_bounds(v: View, centre: vec3<f32>, radius: f32) -> SharedBounds {
    var s = centre;
    var h = 0.0;
    if is_parallel_eye(v) {
        // One camera for every ray: the mono box seen from it.
        s = centre - parallel_camera(v);
    } else if v.eye_sign != 0.0 {
        h = v.half_ipd;
    }
    let d = length(s);
    if d <= (radius + h) * (1.0 + 1e-5) + 1e-6 {
        return SharedBounds(full_rect(), vec2<f32>(0.0), true);
    }
    let b = v.basis;
    let rho = length(vec2<f32>(dot(s, b.right), dot(s, b.forward)));
    if h == 0.0 || rho - radius <= h * (1.0 + 1e-3) + 1e-6 {
        // Every ray origin lies within h of C: hit directions lie in the cone of the ball of
        // radius + h.
        let c = cap_rect(b, s, radius + h);
        return SharedBounds(c, vec2<f32>(0.0), h > 0.0 || c.hi.x - c.lo.x >= TAU);
    }
    let mono = cap_rect(b, s, radius);
    let rho_min = rho - radius;
    let rho_max = rho + radius;
    // merge() does not grow with |phi| and |phi(X)| >= |phiC(X)|: the largest circle radius
    // is at the mono range's smallest |phi|.
    var rmax = h;
    if mono.lo.y > 0.0 {
        rmax = h * merge(v, mono.lo.y);
    } else if mono.hi.y < 0.0 {
        rmax = h * merge(v, mono.hi.y);
    }
    let kmax = rho_min / sqrt(rho_min * rho_min - rmax * rmax);
    let phi_lo = min(mono.lo.y, atan(kmax * tan(mono.lo.y)));
    let phi_hi = max(mono.hi.y, atan(kmax * tan(mono.hi.y)));
    let rmin = h * min(merge(v, phi_lo), merge(v, phi_hi));
    let offsets = vec2<f32>(asin_accurate(rmin / rho_max), asin_accurate(rmax / rho_min));
    return SharedBounds(Rect(vec2<f32>(mono.lo.x, phi_lo), vec2<f32>(mono.hi.x, phi_hi)),
                        offsets, false);
}
