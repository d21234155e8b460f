// Mirrors src/projection/equirect.rs: pixels, angles and directions (DESIGN §2).
// `size` is (width, height) in pixels.

const PI: f32 = 3.141592653589793;
const TAU: f32 = 6.283185307179586;
const FRAC_PI_2: f32 = 1.5707963267948966;

// Longitude and latitude of continuous image position `pos`; pixel (i, j) is sampled at
// (i + 0.5, j + 0.5).
fn angles_of_position(size: vec2<f32>, pos: vec2<f32>) -> vec2<f32> {
    let u = pos.x / size.x;
    let v = pos.y / size.y;
    return vec2<f32>((u - 0.5) * TAU, (0.5 - v) * PI);
}

// Image position of (lam, phi) without wrapping `lam`: proxies keep their longitude
// continuous across the seam and are drawn twice instead.
fn position_of_angles_unwrapped(size: vec2<f32>, a: vec2<f32>) -> vec2<f32> {
    return vec2<f32>((a.x / TAU + 0.5) * size.x, (0.5 - a.y / PI) * size.y);
}

// Image position of (lam wrapped into [-pi, pi), phi).
fn position_of_angles(size: vec2<f32>, a: vec2<f32>) -> vec2<f32> {
    return position_of_angles_unwrapped(size, vec2<f32>(wrap_longitude(a.x), a.y));
}

// Wraps a longitude into [-pi, pi).
fn wrap_longitude(lam: f32) -> f32 {
    let x = lam + PI;
    return x - TAU * floor(x / TAU) - PI;
}

// Unit direction of longitude `lam`, latitude `phi` in frame `b`.
fn direction(b: Basis, lam: f32, phi: f32) -> vec3<f32> {
    let sl = sin(lam);
    let cl = cos(lam);
    return cos(phi) * (sl * b.right + cl * b.forward) + sin(phi) * b.up;
}

// Longitude of a vector in frame `b`; 0 for vertical `v`.
fn longitude(b: Basis, v: vec3<f32>) -> f32 {
    return atan2(dot(v, b.right), dot(v, b.forward));
}

// Longitude and latitude of a non-zero vector `v` in frame `b`.
fn angles(b: Basis, v: vec3<f32>) -> vec2<f32> {
    let x = dot(v, b.right);
    let y = dot(v, b.forward);
    let z = dot(v, b.up);
    return vec2<f32>(atan2(x, y), clamp(atan2(z, length(vec2<f32>(x, y))), -FRAC_PI_2, FRAC_PI_2));
}
