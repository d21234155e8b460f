// Mirrors src/projection/image_bounds.rs: the pixel rectangles of a sphere's image in any
// projection but the full equirect (which expand.wgsl draws from its longitude/latitude box
// directly). Needs camera, equirect, pole_merge, ods, projection and sphere_bounds.

const MAX_RECTS: u32 = 6u;

// Up to MAX_RECTS rectangles of continuous image positions (pixels, y down), clipped to the
// image.
struct PixelRects {
    n: u32,
    lo: array<vec2<f32>, 6>,
    hi: array<vec2<f32>, 6>,
}

// Adds [lo, hi] grown by PIXEL_MARGIN and clipped to the image, unless empty.
fn push_rect(out: ptr<function, PixelRects>, size: vec2<f32>, lo: vec2<f32>, hi: vec2<f32>) {
    let a = max(lo - vec2<f32>(PIXEL_MARGIN), vec2<f32>(0.0));
    let b = min(hi + vec2<f32>(PIXEL_MARGIN), size);
    if a.x <= b.x && a.y <= b.y && (*out).n < MAX_RECTS {
        (*out).lo[(*out).n] = a;
        (*out).hi[(*out).n] = b;
        (*out).n += 1u;
    }
}

// The cone from C holding every hit direction: xyz unit axis in rig components, w half-angle
// grown by ANGLE_MARGIN; w < 0 when some ray origin may lie in the sphere.
fn cone_of(view: View, s: vec3<f32>, radius: f32) -> vec4<f32> {
    var h = 0.0;
    if view.eye_sign != 0.0 {
        h = view.half_ipd;
    }
    let d = length(s);
    let ball = radius + h;
    if d <= ball * (1.0 + 1e-5) + 1e-6 {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    let b = view.basis;
    let axis = vec3<f32>(dot(s, b.right), dot(s, b.forward), dot(s, b.up)) / d;
    return vec4<f32>(axis, asin_accurate(min(ball / d, 1.0)) + ANGLE_MARGIN);
}

// Hammer plane coordinates (x, y), y up, of longitude `lam` in [-pi, pi], latitude `phi`.
fn hammer_xy(lam: f32, phi: f32) -> vec2<f32> {
    let sp = sin(phi);
    let cp = cos(phi);
    let sh = sin(0.5 * lam);
    let ch = cos(0.5 * lam);
    let k = sqrt(1.0 + cp * ch);
    return vec2<f32>(2.0 * SQRT_2 * cp * sh / k, SQRT_2 * sp / k);
}

// Box (u, v) in [0, 1]^2, v down, of the Hammer image of [l0, l1] x [p0, p1]: corners and
// the crossings of phi = 0 (x) and lam = 0 (y). Returns (lo, hi) as (u0, v0, u1, v1).
fn hammer_box(l0: f32, l1: f32, p0: f32, p1: f32) -> vec4<f32> {
    let p_mid = clamp(0.0, p0, p1);
    let l_mid = clamp(0.0, l0, l1);
    let x_lo = min(min(hammer_xy(l0, p0).x, hammer_xy(l0, p1).x), hammer_xy(l0, p_mid).x);
    let x_hi = max(max(hammer_xy(l1, p0).x, hammer_xy(l1, p1).x), hammer_xy(l1, p_mid).x);
    let y_lo = min(min(hammer_xy(l0, p0).y, hammer_xy(l1, p0).y), hammer_xy(l_mid, p0).y);
    let y_hi = max(max(hammer_xy(l0, p1).y, hammer_xy(l1, p1).y), hammer_xy(l_mid, p1).y);
    let u0 = (x_lo / (2.0 * SQRT_2) + 1.0) / 2.0;
    let u1 = (x_hi / (2.0 * SQRT_2) + 1.0) / 2.0;
    return vec4<f32>(u0, (1.0 - y_hi / SQRT_2) / 2.0, u1, (1.0 - y_lo / SQRT_2) / 2.0);
}

// The rectangles of longitude/latitude box `r` (margins included) in the equirect,
// cylindrical or Hammer image: [lo.x, hi.x] modulo 2 pi cut to the image's longitudes (at most
// two pieces), each mapped through the projection's monotone formulas.
fn latlong_rects(out: ptr<function, PixelRects>, p: Projection, size: vec2<f32>, r: Rect) {
    var half_w = PI;
    var half_h = FRAC_PI_2;
    if p.kind == PROJ_EQUIRECT {
        half_w = 0.5 * p.a.x;
        half_h = 0.5 * p.a.y;
    } else if p.kind == PROJ_CYLINDRICAL {
        half_h = 0.5 * p.a.y;
    }
    let p0 = max(r.lo.y, -half_h);
    let p1 = min(r.hi.y, half_h);
    if p0 > p1 {
        return;
    }
    let full = r.hi.x - r.lo.x >= TAU;
    let c = 0.5 * (r.lo.x + r.hi.x);
    var shift = 0.0;
    if c < -PI || c >= PI {
        shift = wrap_longitude(c) - c;
    }
    for (var k = -1; k <= 1; k++) {
        var l0 = max(r.lo.x + shift + f32(k) * TAU, -half_w);
        var l1 = min(r.hi.x + shift + f32(k) * TAU, half_w);
        if full {
            if k != 0 {
                continue;
            }
            l0 = -half_w;
            l1 = half_w;
        }
        // A piece that only touches the window's edge holds no pixel centre.
        if l0 >= l1 {
            continue;
        }
        if p.kind == PROJ_HAMMER {
            let b = hammer_box(l0, l1, p0, p1);
            push_rect(out, size, b.xy * size, b.zw * size);
        } else if p.kind == PROJ_CYLINDRICAL {
            let x0 = (l0 / TAU + 0.5) * size.x;
            let x1 = (l1 / TAU + 0.5) * size.x;
            let y0 = 0.5 * (1.0 - tan(p1) / p.a.x) * size.y;
            let y1 = 0.5 * (1.0 - tan(p0) / p.a.x) * size.y;
            push_rect(out, size, vec2<f32>(x0, y0), vec2<f32>(x1, y1));
        } else {
            let x0 = (l0 / (2.0 * half_w) + 0.5) * size.x;
            let x1 = (l1 / (2.0 * half_w) + 0.5) * size.x;
            let y0 = (0.5 - p1 / (2.0 * half_h)) * size.y;
            let y1 = (0.5 - p0 / (2.0 * half_h)) * size.y;
            push_rect(out, size, vec2<f32>(x0, y0), vec2<f32>(x1, y1));
        }
    }
}

// The fisheye rectangle of the cone (axis in rig components, half-angle alpha): the annular
// sector theta in [theta_a - alpha, theta_a + alpha], azimuth psi_a +- asin(sin alpha /
// sin theta_a) (every azimuth when the cone holds F or -F), bounded by its corners and the
// outer arc's axis crossings.
fn fisheye_rect(out: ptr<function, PixelRects>, size: vec2<f32>, axis: vec3<f32>, alpha: f32,
                fov: f32) {
    let half = 0.5 * fov;
    let theta_a = atan2(length(axis.xz), axis.y);
    let s0 = max(theta_a - alpha, 0.0) / half;
    let s1 = min(min(theta_a + alpha, PI) / half, 1.0);
    if s0 > s1 {
        return;
    }
    let sin_a = sin(min(alpha, FRAC_PI_2));
    let sin_t = sin(theta_a);
    var lo = vec2<f32>(-s1);
    var hi = vec2<f32>(s1);
    if sin_a < sin_t * (1.0 - 1e-4) {
        let psi_a = atan2(axis.z, axis.x);
        let beta = asin_accurate(sin_a / sin_t);
        let psi0 = psi_a - beta;
        let psi1 = psi_a + beta;
        let c0 = vec2<f32>(cos(psi0), sin(psi0));
        let c1 = vec2<f32>(cos(psi1), sin(psi1));
        lo = min(min(s0 * c0, s0 * c1), min(s1 * c0, s1 * c1));
        hi = max(max(s0 * c0, s0 * c1), max(s1 * c0, s1 * c1));
        for (var k = 0; k < 4; k++) {
            let psi = f32(k) * FRAC_PI_2;
            let t = psi - psi0;
            if t - TAU * floor(t / TAU) <= psi1 - psi0 {
                let q = s1 * vec2<f32>(cos(psi), sin(psi));
                lo = min(lo, q);
                hi = max(hi, q);
            }
        }
    }
    let a = vec2<f32>(0.5 * (lo.x + 1.0) * size.x, 0.5 * (1.0 - hi.y) * size.y);
    let b = vec2<f32>(0.5 * (hi.x + 1.0) * size.x, 0.5 * (1.0 - lo.y) * size.y);
    push_rect(out, size, a, b);
}

// Range of the face coordinate d.B / d.A over the pixels of face (A, B, C) that see the cone
// (ka = k.A, kb = k.B): tan of the cone's longitudes about C, atan2(kb, ka) +- asin(sin_a /
// hypot(ka, kb)) (every angle when the cone holds +-C), cut to [-pi/4, pi/4]; z = 0 when
// they miss it.
fn face_range(ka: f32, kb: f32, sin_a: f32) -> vec3<f32> {
    let rho = length(vec2<f32>(ka, kb));
    if sin_a >= rho * (1.0 - 1e-4) {
        return vec3<f32>(-1.0, 1.0, 1.0);
    }
    let psi = atan2(kb, ka);
    let beta = asin_accurate(sin_a / rho);
    let quarter = 0.25 * PI;
    let lo = psi - beta;
    let hi = psi + beta;
    let c = 0.5 * (lo + hi);
    var shift = 0.0;
    if c < -PI || c >= PI {
        shift = wrap_longitude(c) - c;
    }
    var a = 3.4e38;
    var b = -3.4e38;
    for (var k = -1; k <= 1; k++) {
        let l0 = max(lo + shift + f32(k) * TAU, -quarter);
        let l1 = min(hi + shift + f32(k) * TAU, quarter);
        if l0 < l1 {
            a = min(a, l0);
            b = max(b, l1);
        }
    }
    if a >= b {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(max(tan(a), -1.0), min(tan(b), 1.0), 1.0);
}

// The cube-map rectangles of the cone: per face in front of the cone's far side, the
// face_range of each face coordinate.
fn cubemap_rects(out: ptr<function, PixelRects>, size: vec2<f32>, axis: vec3<f32>,
                 alpha: f32) {
    let sin_a = sin(min(alpha, FRAC_PI_2));
    for (var k = 0u; k < 6u; k++) {
        let face = cube_face(k);
        let ka = dot(axis, face[0]);
        if ka < -sin_a {
            continue;
        }
        let a = face_range(ka, dot(axis, face[1]), sin_a);
        let b = face_range(ka, dot(axis, face[2]), sin_a);
        if a.z == 0.0 || b.z == 0.0 {
            continue;
        }
        let x0 = (f32(k) + 0.5 * (a.x + 1.0)) / 6.0 * size.x;
        let x1 = (f32(k) + 0.5 * (a.y + 1.0)) / 6.0 * size.x;
        push_rect(out, size, vec2<f32>(x0, 0.5 * (1.0 - b.y) * size.y),
                  vec2<f32>(x1, 0.5 * (1.0 - b.x) * size.y));
    }
}

// The map's square around `s` (relative to C): pixels whose vertical ray passes within
// `radius` of it.
fn map_rect(out: ptr<function, PixelRects>, p: Projection, size: vec2<f32>, s: vec3<f32>,
            radius: f32) {
    let x0 = (s.x - radius - p.a.x) / p.a.z * size.x;
    let x1 = (s.x + radius - p.a.x) / p.a.z * size.x;
    let y0 = (p.a.y - (s.y + radius)) / p.a.w * size.y;
    let y1 = (p.a.y - (s.y - radius)) / p.a.w * size.y;
    push_rect(out, size, vec2<f32>(x0, y0), vec2<f32>(x1, y1));
}

// Pixel rectangles holding every pixel whose ray (this view) hits the sphere (s relative to
// C, radius), margins included; none when no pixel can see it.
fn image_bounds(view: View, p: Projection, size: vec2<f32>, s: vec3<f32>, radius: f32)
    -> PixelRects {
    var out: PixelRects;
    out.n = 0u;
    if p.kind == PROJ_MAP {
        map_rect(&out, p, size, s, radius);
        return out;
    }
    if p.kind == PROJ_FISHEYE || p.kind == PROJ_CUBEMAP {
        let cone = cone_of(view, s, radius);
        if cone.w < 0.0 {
            push_rect(&out, size, vec2<f32>(0.0), size);
        } else if p.kind == PROJ_FISHEYE {
            fisheye_rect(&out, size, cone.xyz, cone.w, p.a.x);
        } else {
            cubemap_rects(&out, size, cone.xyz, cone.w);
        }
        return out;
    }
    let r = sphere_bounds(view, s, radius).rect;
    let grown = Rect(r.lo - vec2<f32>(ANGLE_MARGIN), r.hi + vec2<f32>(ANGLE_MARGIN));
    latlong_rects(&out, p, size, grown);
    return out;
}
