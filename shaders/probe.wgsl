// Test kernel: evaluates the shared math (ods.wgsl, pole_merge.wgsl, sphere_bounds.wgsl,
// projection.wgsl, image_bounds.wgsl, sphere.wgsl, shading.wgsl) on given inputs so the Rust
// tests can compare it with the f64 reference. Prepended: camera, equirect, pole_merge, ods,
// depth_map, projection, params, sphere_bounds, image_bounds, sphere, shading.

// One item's inputs; laid out as `ProbeItem` in src/raster/probe.rs. Positions are relative
// to C.
struct ProbeItem {
    // xyz: a point to project.
    point: vec4<f32>,
    // xy: (lam, phi) of a ray and of a merge factor.
    angles: vec4<f32>,
    // A ray to intersect with `sphere`: xyz origin, then xyz unit direction.
    ray_origin: vec4<f32>,
    ray_dir: vec4<f32>,
    // xyz centre, w radius: intersected with the ray and bounded by sphere_bounds.
    sphere: vec4<f32>,
    // Shading inputs: xyz base colour (sRGB bytes), w mode (0 unlit, 1 phong, 2 normal);
    // unit normal, hit point and eye.
    base: vec4<f32>,
    normal: vec4<f32>,
    hit: vec4<f32>,
    eye: vec4<f32>,
    // xy: an image position (pixels) for image_ray.
    pixel: vec4<f32>,
}

const PROBE_SLOTS: u32 = 15u;

@group(0) @binding(0) var<storage, read> params: Params;
@group(0) @binding(1) var<storage, read> probe_items: array<ProbeItem>;
// Per item, PROBE_SLOTS slots: (lam, phi, ok, merge(phi_in)), (ray origin, 0), (ray dir, 0),
// (shaded colour, intersection t), (bounds lo, bounds hi), (bounds special, rect count, image
// ray ok, 0), (image ray origin, 0), (image ray dir, 0), then MAX_RECTS (rect lo, rect hi).
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&probe_items) {
        return;
    }
    let it = probe_items[i];
    let view = view_of(params);
    let o = PROBE_SLOTS * i;
    let q = project(view, it.point.xyz);
    let a = it.angles.xy;
    let m = pole_merging_factor(view.north, view.south, a.y);
    probe_out[o] = vec4<f32>(q.angles, select(0.0, 1.0, q.ok), m);
    let r = ray(view, a.x, a.y);
    probe_out[o + 1u] = vec4<f32>(r.origin, 0.0);
    probe_out[o + 2u] = vec4<f32>(r.dir, 0.0);
    let t = intersect_sphere(Ray(it.ray_origin.xyz, it.ray_dir.xyz), it.sphere.xyz, it.sphere.w);
    let l0 = Light(params.light0_position, params.light0_intensity);
    let l1 = Light(params.light1_position, params.light1_intensity);
    let c = shade(u32(it.base.w), it.base.xyz, it.normal.xyz, it.hit.xyz, it.eye.xyz, l0, l1);
    probe_out[o + 3u] = vec4<f32>(c, t);
    let b = sphere_bounds(view, it.sphere.xyz, it.sphere.w);
    probe_out[o + 4u] = vec4<f32>(b.rect.lo, b.rect.hi);
    let size = params.image_size;
    let proj = projection_of(params);
    var rects = image_bounds(view, proj, size, it.sphere.xyz, it.sphere.w);
    let pixel = image_ray(view, proj, size, it.pixel.xy);
    probe_out[o + 5u] = vec4<f32>(select(0.0, 1.0, b.special), f32(rects.n),
                                  select(0.0, 1.0, pixel.ok), 0.0);
    probe_out[o + 6u] = vec4<f32>(pixel.ray.origin, 0.0);
    probe_out[o + 7u] = vec4<f32>(pixel.ray.dir, 0.0);
    for (var k = 0u; k < MAX_RECTS; k++) {
        probe_out[o + 8u + k] = vec4<f32>(0.0);
        if k < rects.n {
            probe_out[o + 8u + k] = vec4<f32>(rects.lo[k], rects.hi[k]);
        }
    }
}
