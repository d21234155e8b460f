// Render pass: rasterizes the expanded proxies of one eye and shades each fragment as the
// sphere it stands for. Driven by src/raster/imposter.rs. Prepended: the constants prelude,
// camera, equirect, pole_merge, ods, depth_map, projection, params, chunk, shading, sphere,
// shade_hit.

@group(0) @binding(0) var<storage, read> params: Params;
@group(0) @binding(1) var<storage, read> points: array<GpuPoint>;
@group(0) @binding(2) var<storage, read> colors: array<u32>;

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

// Clip-space position of image position `xy` (pixels).
fn clip_position(xy: vec2<f32>) -> vec4<f32> {
    let size = params.image_size;
    return vec4<f32>(xy.x / size.x * 2.0 - 1.0, 1.0 - xy.y / size.y * 2.0, 0.5, 1.0);
}

@vertex
fn vs(@location(0) xy: vec2<f32>, @location(1) uv: u32, @location(2) point: u32) -> VertexOut {
    return VertexOut(clip_position(xy), unpack2x16snorm(uv), point);
}

// Pixel `pos` (centre, pixels) seen for point `index`: the point's view, the pixel's ray in
// it and the sphere (centre relative to C); `ok` false where the pixel has no ray.
struct PixelCast {
    ok: bool,
    view: View,
    ray: Ray,
    center: vec3<f32>,
    radius: f32,
}

fn pixel_cast(pos: vec2<f32>, index: u32) -> PixelCast {
    let pt = points[index];
    let center = pt.position - params.camera_offset;
    let view = sphere_view(params, center);
    let pixel = pixel_ray(view, vec2<u32>(pos));
    return PixelCast(pixel.ok, view, pixel.ray, center, pt.radius);
}

// Shades pixel `pos` (centre, pixels) as point `point` (| FORCE_RAYCAST: ray cast it); `uv` is
// the billboard coordinate for sprites.
fn shade_pixel(pos: vec2<f32>, point: u32, uv: vec2<f32>) -> Shaded {
    let miss = Shaded(false, vec4<f32>(0.0), 0.0, 1.0);
    let index = point & ~FORCE_RAYCAST;
    let seen = pixel_cast(pos, index);
    if !seen.ok {
        return miss;
    }
    let r = seen.ray;
    let center = seen.center;
    let radius = seen.radius;
    var t: f32;
    var normal: vec3<f32>;
    var hit: vec3<f32>;
    if imposter_of(params) == IMPOSTER_RAYCAST || (point & FORCE_RAYCAST) != 0u {
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
        let u = normalize(cross(dir, seen.view.basis.up));
        let v = cross(u, dir);
        normal = uv.x * u + uv.y * v - sqrt(1.0 - rr) * dir;
        hit = center + radius * normal;
        t = distance(hit, r.origin);
    }
    return shade_hit(index, r, t, hit, normal);
}

@fragment
fn fs(in: VertexOut) -> FragmentOut {
    let s = shade_pixel(in.position.xy, in.point, in.uv);
    if !s.hit {
        discard;
    }
    return FragmentOut(s.color, s.distance, s.depth);
}
