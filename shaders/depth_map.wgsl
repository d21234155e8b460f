// Mirrors src/projection/depth_map.rs: the depth budget `--depth-map B0=D0,...` (DESIGN §9).
// Breakpoints B and distances D (metres, both increasing) are packed four to a vec4: pair k
// is component k % 4 of element k / 4; `count` pairs (1..=8) are used.

const DEPTH_MAP_MAX_PAIRS: u32 = 8u;

// Pair k's value in a packed array.
fn depth_map_at(values: array<vec4<f32>, 2>, k: u32) -> f32 {
    // A function-local copy: a reference may be indexed dynamically on every backend.
    var v = values;
    return v[k / 4u][k % 4u];
}

// The scale s of a sphere whose centre lies at horizontal distance rho_c from the camera,
// with s(D) = half_ipd / D: s(D0) up to B0, affine in 1/rho_c between breakpoints,
// s(Dn) * Bn / rho_c beyond Bn.
fn depth_map_scale(
    b: array<vec4<f32>, 2>,
    d: array<vec4<f32>, 2>,
    count: u32,
    half_ipd: f32,
    rho_c: f32,
) -> f32 {
    let n = clamp(count, 1u, DEPTH_MAP_MAX_PAIRS);
    if rho_c <= depth_map_at(b, 0u) {
        return half_ipd / depth_map_at(d, 0u);
    }
    for (var i = 0u; i + 1u < n; i++) {
        let b0 = depth_map_at(b, i);
        let b1 = depth_map_at(b, i + 1u);
        if rho_c <= b1 {
            let t = (1.0 / b0 - 1.0 / rho_c) / (1.0 / b0 - 1.0 / b1);
            let s0 = half_ipd / depth_map_at(d, i);
            let s1 = half_ipd / depth_map_at(d, i + 1u);
            return s0 + t * (s1 - s0);
        }
    }
    // `Bn / rho_c` is exactly 1 at `rho_c = Bn`, so the last piece starts at s(Dn).
    return half_ipd / depth_map_at(d, n - 1u) * (depth_map_at(b, n - 1u) / rho_c);
}

// The sphere's own ODS radius r_s = rho_c * s.
fn depth_map_ods_radius(
    b: array<vec4<f32>, 2>,
    d: array<vec4<f32>, 2>,
    count: u32,
    half_ipd: f32,
    rho_c: f32,
) -> f32 {
    return rho_c * depth_map_scale(b, d, count, half_ipd, rho_c);
}
