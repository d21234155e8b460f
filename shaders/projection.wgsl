// Mirrors src/projection/image.rs and the per-projection files (hammer.rs, cylindrical.rs,
// fisheye.rs, cubemap.rs, map.rs): the ray of an image position (DESIGN §8). Needs camera,
// equirect and ods. Directions in rig components are (d.R, d.F, d.U).

const SQRT_2: f32 = 1.4142135623730951;

// The image's projection: `kind` a PROJ_* constant and its parameters (radians, metres):
// PROJ_EQUIRECT a = (hfov, vfov); PROJ_CYLINDRICAL a = (tan(vfov / 2), vfov);
// PROJ_FISHEYE a.x = fov; PROJ_MAP a = (x0, y1, x1 - x0, y1 - y0) and b.x = z_top, relative to C.
struct Projection {
    kind: u32,
    a: vec4<f32>,
    b: vec4<f32>,
}

// A pixel's ray; `ok` false where the projection shows nothing.
struct ImageRay {
    ray: Ray,
    ok: bool,
}

// (2u - 1, 1 - 2v) at image position `pos`: 2 pos - size is exact for pixel centres, so one
// rounding, in the division (2u - 1 from a rounded u would lose bits near the centre).
fn centred(pos: vec2<f32>, size: vec2<f32>) -> vec2<f32> {
    return vec2<f32>((2.0 * pos.x - size.x) / size.x, (size.y - 2.0 * pos.y) / size.y);
}

// The angle whose sine and cosine are (s, c) (unit length): atan2, then one Newton step on
// sin(a - a0) = s cos a0 - c sin a0, which brings llvmpipe's atan2 (off by up to ~1e-5 rad)
// to the accuracy of its sin and cos. The latitude feeds the merge factor of the ODS origin.
fn angle_of(s: f32, c: f32) -> f32 {
    let a0 = atan2(s, c);
    return a0 + (s * cos(a0) - c * sin(a0));
}

// A pixel's direction: t = (sin lam, cos lam, sin phi, cos phi) in the rig frame, the
// latitude phi, and whether the projection shows anything there.
struct PixelAngles {
    t: vec4<f32>,
    phi: f32,
    ok: bool,
}

fn no_angles() -> PixelAngles {
    return PixelAngles(vec4<f32>(0.0, 1.0, 0.0, 1.0), 0.0, false);
}

// Longitude and latitude at image position `pos` (pixels; size `size`), inside the ellipse
// x^2/8 + y^2/2 <= 1: lam = 2 atan2(z x, 2 (2 z^2 - 1)), phi = asin(z y), as sines and
// cosines.
fn hammer_angles(pos: vec2<f32>, size: vec2<f32>) -> PixelAngles {
    let c = centred(pos, size);
    let x = c.x * 2.0 * SQRT_2;
    let y = c.y * SQRT_2;
    // 2 z^2 - 1, from x and y rather than from the rounded z.
    let w = 1.0 - x * x / 8.0 - y * y / 2.0;
    if w < 0.0 {
        return no_angles();
    }
    let z = sqrt(0.5 * (1.0 + w));
    // lam / 2 = atan2(z x, 2 w), in [-pi/2, pi/2].
    let n = length(vec2<f32>(z * x, 2.0 * w));
    var sh = 0.0;
    var ch = 1.0;
    if n > 0.0 {
        sh = z * x / n;
        ch = 2.0 * w / n;
    }
    // cos(phi) (sin(lam/2), cos(lam/2)) = (z x / 2, w): cos(phi) = n / 2 without the
    // cancellation of sqrt(1 - sin^2) near the poles.
    let sp = clamp(z * y, -1.0, 1.0);
    let cp = 0.5 * n;
    let t = vec4<f32>(2.0 * sh * ch, (ch - sh) * (ch + sh), sp, cp);
    return PixelAngles(t, angle_of(sp, cp), true);
}

// Longitude and latitude at (u, v); `tan_half` = tan(vfov / 2):
// lam = (u - 0.5) 2 pi, phi = atan((1 - 2v) tan_half).
fn cylindrical_angles(u: f32, v: f32, tan_half: f32) -> PixelAngles {
    let lam = (u - 0.5) * TAU;
    let q = (1.0 - 2.0 * v) * tan_half;
    let c = inverseSqrt(1.0 + q * q);
    return PixelAngles(vec4<f32>(sin(lam), cos(lam), q * c, c), angle_of(q * c, c), true);
}

// Rig-frame direction at image position `pos` of a fisheye of field of view `fov`; w = 1
// inside the circle, else 0.
fn fisheye_direction(pos: vec2<f32>, size: vec2<f32>, fov: f32) -> vec4<f32> {
    let c = centred(pos, size);
    let x = c.x;
    let y = c.y;
    let s = length(vec2<f32>(x, y));
    if s > 1.0 {
        return vec4<f32>(0.0);
    }
    if s == 0.0 {
        return vec4<f32>(0.0, 1.0, 0.0, 1.0);
    }
    let theta = s * 0.5 * fov;
    let st = sin(theta);
    return vec4<f32>(st * x / s, cos(theta), st * y / s, 1.0);
}

// Face axes (forward A, right B, up C) in rig components, strip order front, right, back,
// left, up, down.
fn cube_face(k: u32) -> array<vec3<f32>, 3> {
    let r = vec3<f32>(1.0, 0.0, 0.0);
    let f = vec3<f32>(0.0, 1.0, 0.0);
    let u = vec3<f32>(0.0, 0.0, 1.0);
    var axes = array<vec3<f32>, 3>(-u, r, f);
    switch k {
        case 0u: { axes = array<vec3<f32>, 3>(f, r, u); }
        case 1u: { axes = array<vec3<f32>, 3>(r, -f, u); }
        case 2u: { axes = array<vec3<f32>, 3>(-f, -r, u); }
        case 3u: { axes = array<vec3<f32>, 3>(-r, f, u); }
        case 4u: { axes = array<vec3<f32>, 3>(u, r, -f); }
        default: {}
    }
    return axes;
}

// Rig-frame unit direction at image position `pos` of the cube-map strip: face
// k = floor(6u), a = 2 (6u - k) - 1, b = 1 - 2v.
fn cubemap_direction(pos: vec2<f32>, size: vec2<f32>) -> vec3<f32> {
    let k = min(floor(6.0 * pos.x / size.x), 5.0);
    // 2 (6 pos.x - k W) - W is exact for pixel centres: one rounding, in the division.
    let a = (2.0 * (6.0 * pos.x - k * size.x) - size.x) / size.x;
    let b = centred(pos, size).y;
    let face = cube_face(u32(k));
    return normalize(face[0] + a * face[1] + b * face[2]);
}

// Longitude and latitude of rig-frame direction d (lam = atan2(d.R, d.F), phi = asin(d.U)
// through atan2), as sines and cosines.
fn rig_angles(d: vec3<f32>) -> PixelAngles {
    let rho = length(d.xy);
    let len = length(d);
    var sl = 0.0;
    var cl = 1.0;
    if rho > 0.0 {
        sl = d.x / rho;
        cl = d.y / rho;
    }
    return PixelAngles(vec4<f32>(sl, cl, d.z / len, rho / len), angle_of(d.z / len, rho / len),
                       true);
}

// Longitude and latitude (rig frame) at image position `pos` (u = pos.x / size.x,
// v = pos.y / size.y), as Projection::angles. Not for the full equirect
// (angles_of_position) nor the map.
fn projection_angles(p: Projection, pos: vec2<f32>, size: vec2<f32>) -> PixelAngles {
    let u = pos.x / size.x;
    let v = pos.y / size.y;
    if p.kind == PROJ_EQUIRECT {
        let lam = (u - 0.5) * p.a.x;
        let phi = (0.5 - v) * p.a.y;
        return PixelAngles(vec4<f32>(sin(lam), cos(lam), sin(phi), cos(phi)), phi, true);
    }
    if p.kind == PROJ_HAMMER {
        return hammer_angles(pos, size);
    }
    if p.kind == PROJ_CYLINDRICAL {
        return cylindrical_angles(u, v, p.a.x);
    }
    if p.kind == PROJ_FISHEYE {
        let d = fisheye_direction(pos, size, p.a.x);
        if d.w == 0.0 {
            return no_angles();
        }
        return rig_angles(d.xyz);
    }
    return rig_angles(cubemap_direction(pos, size));
}

// The ray (relative to C) of continuous image position `pos` (pixels) in an image of `size`.
// The full equirect keeps equirect.wgsl's arithmetic; the map's rays are vertical from its
// frame, whatever the view.
fn image_ray(view: View, p: Projection, size: vec2<f32>, pos: vec2<f32>) -> ImageRay {
    if p.kind == PROJ_EQUIRECT_FULL {
        let a = angles_of_position(size, pos);
        return ImageRay(ray(view, a.x, a.y), true);
    }
    let u = pos.x / size.x;
    let v = pos.y / size.y;
    if p.kind == PROJ_MAP {
        let origin = vec3<f32>(p.a.x + u * p.a.z, p.a.y - v * p.a.w, p.b.x);
        return ImageRay(Ray(origin, vec3<f32>(0.0, 0.0, -1.0)), true);
    }
    let a = projection_angles(p, pos, size);
    if !a.ok {
        return ImageRay(Ray(vec3<f32>(0.0), vec3<f32>(0.0)), false);
    }
    return ImageRay(ray_of_trig(view, a.t, a.phi), true);
}
