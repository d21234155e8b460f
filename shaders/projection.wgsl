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

// Longitude and latitude at (u, v), z = 1 inside the ellipse x^2/8 + y^2/2 <= 1, else 0.
fn hammer_angles(u: f32, v: f32) -> vec3<f32> {
    let x = (2.0 * u - 1.0) * 2.0 * SQRT_2;
    let y = (1.0 - 2.0 * v) * SQRT_2;
    if x * x / 8.0 + y * y / 2.0 > 1.0 {
        return vec3<f32>(0.0);
    }
    let z = sqrt(max(1.0 - x * x / 16.0 - y * y / 4.0, 0.0));
    let lam = 2.0 * atan2(z * x, 2.0 * (2.0 * z * z - 1.0));
    let phi = asin_accurate(clamp(z * y, -1.0, 1.0));
    return vec3<f32>(lam, phi, 1.0);
}

// Longitude and latitude at (u, v); `tan_half` = tan(vfov / 2).
fn cylindrical_angles(u: f32, v: f32, tan_half: f32) -> vec2<f32> {
    return vec2<f32>((u - 0.5) * TAU, atan((1.0 - 2.0 * v) * tan_half));
}

// Rig-frame direction at (u, v) of a fisheye of field of view `fov`; w = 1 inside the circle,
// else 0.
fn fisheye_direction(u: f32, v: f32, fov: f32) -> vec4<f32> {
    let x = 2.0 * u - 1.0;
    let y = 1.0 - 2.0 * v;
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

// Rig-frame unit direction at (u, v) of the cube-map strip.
fn cubemap_direction(u: f32, v: f32) -> vec3<f32> {
    let k = min(floor(6.0 * u), 5.0);
    let a = 2.0 * (6.0 * u - k) - 1.0;
    let b = 1.0 - 2.0 * v;
    let face = cube_face(u32(k));
    return normalize(face[0] + a * face[1] + b * face[2]);
}

// Longitude and latitude of rig-frame direction d: lam = atan2(d.R, d.F), phi = asin(d.U)
// through atan2.
fn rig_angles(d: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(atan2(d.x, d.y), atan2(d.z, length(d.xy)));
}

// Longitude and latitude (rig frame) at (u, v); z = 1 where the projection shows something.
// Not for the full equirect (angles_of_position) nor the map.
fn projection_angles(p: Projection, u: f32, v: f32) -> vec3<f32> {
    if p.kind == PROJ_EQUIRECT {
        return vec3<f32>((u - 0.5) * p.a.x, (0.5 - v) * p.a.y, 1.0);
    }
    if p.kind == PROJ_HAMMER {
        return hammer_angles(u, v);
    }
    if p.kind == PROJ_CYLINDRICAL {
        return vec3<f32>(cylindrical_angles(u, v, p.a.x), 1.0);
    }
    if p.kind == PROJ_FISHEYE {
        let d = fisheye_direction(u, v, p.a.x);
        return vec3<f32>(rig_angles(d.xyz), d.w);
    }
    return vec3<f32>(rig_angles(cubemap_direction(u, v)), 1.0);
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
    let a = projection_angles(p, u, v);
    if a.z == 0.0 {
        return ImageRay(Ray(vec3<f32>(0.0), vec3<f32>(0.0)), false);
    }
    return ImageRay(ray(view, a.x, a.y), true);
}
