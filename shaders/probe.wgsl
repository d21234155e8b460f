// Test kernel: evaluates the shared math (ods.wgsl, pole_merge.wgsl) on given inputs so the
// Rust tests can compare it with the f64 reference. Prepended: camera, equirect, pole_merge,
// ods, params.

@group(0) @binding(0) var<uniform> params: Params;
// xyz: a point relative to C; w unused.
@group(0) @binding(1) var<storage, read> probe_points: array<vec4<f32>>;
// xy: (lam, phi) of a ray.
@group(0) @binding(2) var<storage, read> probe_angles: array<vec2<f32>>;
// Per item, 3 slots: (lam, phi, ok, merge(phi_in)), (ray origin, 0), (ray dir, 0).
@group(0) @binding(3) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    let view = view_of(params);
    let q = project(view, probe_points[i].xyz);
    let a = probe_angles[i];
    let m = pole_merging_factor(view.north, view.south, a.y);
    probe_out[3u * i] = vec4<f32>(q.angles, select(0.0, 1.0, q.ok), m);
    let r = ray(view, a.x, a.y);
    probe_out[3u * i + 1u] = vec4<f32>(r.origin, 0.0);
    probe_out[3u * i + 2u] = vec4<f32>(r.dir, 0.0);
}
