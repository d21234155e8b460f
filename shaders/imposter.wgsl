// Render pass: rasterizes the expanded proxies of one eye and shades each fragment as the
// sphere it stands for. Prepended: camera, equirect, pole_merge, ods, params, shading.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> points: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> colors: array<u32>;

const FORCE_RAYCAST_BIT: u32 = 0x80000000u;

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) point: u32,
}

struct FragmentOut {
    // sRGB bytes / 255 into Rgba8Unorm: the bytes come back unchanged.
    @location(0) color: vec4<f32>,
    // Distance along the ray from its origin, metres.
    @location(1) distance: f32,
    @builtin(frag_depth) depth: f32,
}

@vertex
fn vs(@location(0) xy: vec2<f32>, @location(1) uv: u32, @location(2) point: u32) -> VertexOut {
    let size = image_size(params);
    let clip = vec2<f32>(xy.x / size.x * 2.0 - 1.0, 1.0 - xy.y / size.y * 2.0);
    return VertexOut(vec4<f32>(clip, 0.5, 1.0), unpack2x16snorm(uv), point);
}

// Nearest t > 0 where the ray meets the sphere, or -1. The discriminant comes from the
// perpendicular offset (not b^2 - c) and the near root from c / q, so neither cancels when
// the sphere is small and far (Ray Tracing Gems, ch. 7).
fn intersect_sphere(r: Ray, center: vec3<f32>, radius: f32) -> f32 {
    let oc = r.origin - center;
    let b = dot(oc, r.dir);
    let perp = oc - b * r.dir;
    let disc = radius * radius - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let c = dot(oc, oc) - radius * radius;
    let q = -b - sign(b) * sqrt(disc);
    if b == 0.0 && c == 0.0 {
        return -1.0;
    }
    var t0 = c / q;
    var t1 = q;
    if b == 0.0 {
        t0 = -sqrt(disc);
        t1 = sqrt(disc);
    }
    let near = min(t0, t1);
    let far = max(t0, t1);
    if near > 0.0 {
        return near;
    }
    if far > 0.0 {
        return far;
    }
    return -1.0;
}

@fragment
fn fs(in: VertexOut) -> FragmentOut {
    let index = in.point & ~FORCE_RAYCAST_BIT;
    let pt = points[index];
    let center = pt.xyz;
    let radius = pt.w;
    let view = view_of(params);
    let a = angles_of_position(image_size(params), in.position.xy);
    let r = ray(view, a.x, a.y);
    var t: f32;
    var normal: vec3<f32>;
    var hit: vec3<f32>;
    if params.modes2.x == 0u || (in.point & FORCE_RAYCAST_BIT) != 0u {
        t = intersect_sphere(r, center, radius);
        if t <= 0.0 {
            discard;
        }
        hit = r.origin + t * r.dir;
        normal = (hit - center) / radius;
    } else {
        let rr = dot(in.uv, in.uv);
        if rr > 1.0 {
            discard;
        }
        let dir = normalize(center);
        let u = normalize(cross(dir, view.basis.up));
        let v = cross(u, dir);
        normal = in.uv.x * u + in.uv.y * v - sqrt(1.0 - rr) * dir;
        hit = center + radius * normal;
        t = distance(hit, r.origin);
    }
    if dot(normal, r.dir) > 0.0 {
        normal = -normal;
    }
    let packed = colors[index];
    let base = vec3<f32>(f32(packed & 0xffu), f32((packed >> 8u) & 0xffu), f32((packed >> 16u) & 0xffu));
    let l0 = Light(params.light0.xyz, params.light0.w);
    let l1 = Light(params.light1.xyz, params.light1.w);
    let c = shade(params.modes2.y, base, normal, hit, r.origin, l0, l1);
    let near = params.image.z;
    let far = params.image.w;
    let depth = clamp(log(t / near) / log(far / near), 0.0, 1.0);
    return FragmentOut(vec4<f32>(c / 255.0, 1.0), t, depth);
}
