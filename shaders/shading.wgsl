// Mirrors src/render/shading.rs (DESIGN §5). Colours are sRGB bytes held in 0..=255 floats.

const AMBIENT: f32 = 0.25;
const SPECULAR: f32 = 0.25;
const SHININESS: f32 = 24.0;

struct Light {
    position: vec3<f32>,
    intensity: f32,
}

fn srgb_to_linear(c8: f32) -> f32 {
    let c = c8 / 255.0;
    if c <= 0.04045 {
        return c / 12.92;
    }
    return pow((c + 0.055) / 1.055, 2.4);
}

// Linear light to an sRGB byte value (as f32, truncated like the Rust `as u8`).
fn linear_to_srgb(l_in: f32) -> f32 {
    let l = clamp(l_in, 0.0, 1.0);
    var c: f32;
    if l <= 0.0031308 {
        c = l * 12.92;
    } else {
        c = 1.055 * pow(l, 1.0 / 2.4) - 0.055;
    }
    return floor(c * 255.0 + 0.5);
}

// Shading modes: SHADING_UNLIT, SHADING_PHONG, SHADING_NORMAL. `base` holds sRGB bytes; returns sRGB bytes.
// `normal_in` faces the viewer and is normalised here, as in the Rust shade().
fn shade(mode: u32, base: vec3<f32>, normal_in: vec3<f32>, hit: vec3<f32>, eye: vec3<f32>,
         l0: Light, l1: Light) -> vec3<f32> {
    let normal = normalize_or_zero(normal_in);
    if mode == SHADING_NORMAL {
        return floor((normal * 0.5 + 0.5) * 255.0 + 0.5);
    }
    if mode != SHADING_PHONG {
        return base;
    }
    let albedo = vec3<f32>(srgb_to_linear(base.x), srgb_to_linear(base.y), srgb_to_linear(base.z));
    let view = normalize_or_zero(eye - hit);
    var diffuse = AMBIENT;
    var specular = 0.0;
    let lights = array<Light, 2>(l0, l1);
    for (var k = 0; k < 2; k++) {
        let l = normalize_or_zero(lights[k].position - hit);
        let n_dot_l = dot(normal, l);
        if n_dot_l > 0.0 {
            diffuse += lights[k].intensity * n_dot_l;
            let reflected = 2.0 * n_dot_l * normal - l;
            specular += lights[k].intensity * pow(max(dot(reflected, view), 0.0), SHININESS);
        }
    }
    let c = albedo * diffuse + vec3<f32>(SPECULAR * specular);
    return vec3<f32>(linear_to_srgb(c.x), linear_to_srgb(c.y), linear_to_srgb(c.z));
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    if len > 0.0 {
        return v / len;
    }
    return vec3<f32>(0.0);
}
