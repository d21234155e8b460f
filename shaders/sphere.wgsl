// Ray-sphere intersection shared by the imposter fragment stage and the compute splat.

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
