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

// One fragment's shading; `hit` false where the fragment shows no sphere.
struct Shaded {
    hit: bool,
    color: vec4<f32>,
    distance: f32,
    depth: f32,
}

// Shades pixel `pos` (centre, pixels) as point `point` (bit 31: force ray casting); `uv` is
// the billboard coordinate for sprites.
fn shade_pixel(pos: vec2<f32>, point: u32, uv: vec2<f32>) -> Shaded {
    let miss = Shaded(false, vec4<f32>(0.0), 0.0, 1.0);
    let index = point & ~FORCE_RAYCAST_BIT;
    let pt = points[index];
    let center = pt.xyz;
    let radius = pt.w;
    let view = view_of(params);
    let a = angles_of_position(image_size(params), pos);
    let r = ray(view, a.x, a.y);
    var t: f32;
    var normal: vec3<f32>;
    var hit: vec3<f32>;
    if params.modes2.x == 0u || (point & FORCE_RAYCAST_BIT) != 0u {
        t = intersect_sphere(r, center, radius);
        if t <= 0.0 {
            return miss;
        }
        hit = r.origin + t * r.dir;
        normal = (hit - center) / radius;
    } else {
        let rr = dot(uv, uv);
        if rr > 1.0 {
            return miss;
        }
        let dir = normalize(center);
        let u = normalize(cross(dir, view.basis.up));
        let v = cross(u, dir);
        normal = uv.x * u + uv.y * v - sqrt(1.0 - rr) * dir;
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
    return Shaded(true, vec4<f32>(c / 255.0, 1.0), t, depth);
}

@fragment
fn fs(in: VertexOut) -> FragmentOut {
    let s = shade_pixel(in.position.xy, in.point, in.uv);
    if !s.hit {
        discard;
    }
    return FragmentOut(s.color, s.distance, s.depth);
}

// Splat keys per pixel, as written by the compute splat (see splat.wgsl): x = !point index,
// y = !distance bits; (0, 0) = nothing splatted. Read as u32 pairs so this stage needs no
// 64-bit support.
@group(0) @binding(3) var<storage, read> splat_keys: array<vec2<u32>>;

// A triangle covering the whole image.
@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.5, 1.0);
}

// Resolves the nearest splatted sphere of each pixel into the targets; the depth test keeps
// whichever of it and the rasterized proxies is nearer.
@fragment
fn fs_resolve(@builtin(position) position: vec4<f32>) -> FragmentOut {
    let width = u32(image_size(params).x);
    let key = splat_keys[u32(position.y) * width + u32(position.x)];
    if key.x == 0u && key.y == 0u {
        discard;
    }
    let s = shade_pixel(position.xy, ~key.x | FORCE_RAYCAST_BIT, vec2<f32>(0.0));
    if !s.hit {
        discard;
    }
    return FragmentOut(s.color, s.distance, s.depth);
}
