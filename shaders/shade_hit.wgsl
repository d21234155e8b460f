// The shading of a ray's hit on a sphere, shared by the imposter fragment stage and the
// deferred shading of the keyed path (splat_shade.wgsl). Each module that includes it declares
// `params` and `colors`.

// A shaded pixel; `hit` false where it shows no sphere.
struct Shaded {
    hit: bool,
    color: vec4<f32>,
    distance: f32,
    depth: f32,
}

// Shades point `index` hit at distance `t` along ray `r`, at `hit` with outward `normal`.
fn shade_hit(index: u32, r: Ray, t: f32, hit: vec3<f32>, outward: vec3<f32>) -> Shaded {
    var normal = outward;
    if dot(normal, r.dir) > 0.0 {
        normal = -normal;
    }
    let base = unpack_color(colors[index]);
    let l0 = Light(params.light0_position, params.light0_intensity);
    let l1 = Light(params.light1_position, params.light1_intensity);
    let c = shade(shading_of(params), base, normal, hit, r.origin, l0, l1);
    let near = params.depth_near;
    let far = params.depth_far;
    let depth = clamp(log(t / near) / log(far / near), 0.0, 1.0);
    return Shaded(true, vec4<f32>(c / 255.0, 1.0), t, depth);
}
