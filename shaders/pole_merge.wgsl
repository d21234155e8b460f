// Mirrors src/projection/pole_merge.rs (DESIGN §4).
// kind MERGE_OFF; MERGE_MARRINAN (a = start_deg, b = end_deg, c = exponent);
// MERGE_CYCLES (a = from_deg, b = to_deg).

struct PoleMerge {
    kind: u32,
    a: f32,
    b: f32,
    c: f32,
}

// One pole's merge factor in [0, 1] at absolute latitude `abs_phi` (radians).
fn pole_merge_factor(p: PoleMerge, abs_phi: f32) -> f32 {
    let deg = degrees(min(abs(abs_phi), FRAC_PI_2));
    if p.kind == MERGE_MARRINAN {
        if p.a <= 0.0 {
            return 1.0;
        }
        let lo = 90.0 - p.a;
        let hi = 90.0 - p.b;
        var f: f32;
        if hi > lo {
            f = clamp((deg - lo) / (hi - lo), 0.0, 1.0);
        } else if deg >= lo {
            f = 1.0;
        } else {
            f = 0.0;
        }
        // Outside the merge band the power is skipped: llvmpipe pays for it even at base 1
        // unless every lane of its SIMD row skips it.
        if f <= 0.0 {
            return 1.0;
        }
        let base = 1.0 - f;
        if base <= 0.0 {
            return 0.0;
        }
        return pow(base, p.c);
    }
    if p.kind == MERGE_CYCLES {
        if deg <= p.a {
            return 1.0;
        }
        if deg >= p.b {
            return 0.0;
        }
        let fac = (deg - p.a) / (p.b - p.a);
        return cos(fac * FRAC_PI_2);
    }
    return 1.0;
}

// Mirrors PoleMerging::factor: the profile of latitude `phi`'s hemisphere. The profile is
// chosen before the one evaluation: a branch per hemisphere would evaluate both on llvmpipe,
// which runs every branch a lane of its SIMD row takes.
fn pole_merging_factor(north: PoleMerge, south: PoleMerge, phi: f32) -> f32 {
    let n = phi >= 0.0;
    let p = PoleMerge(select(south.kind, north.kind, n), select(south.a, north.a, n),
                      select(south.b, north.b, n), select(south.c, north.c, n));
    return pole_merge_factor(p, abs(phi));
}
