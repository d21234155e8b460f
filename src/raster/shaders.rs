//! WGSL sources, composed by concatenation: the math files mirror `src/projection` and
//! `src/render/shading.rs` file for file; the pipeline files use them.

/// `shaders/camera.wgsl`.
pub const CAMERA: &str = include_str!("../../shaders/camera.wgsl");
/// `shaders/equirect.wgsl`.
pub const EQUIRECT: &str = include_str!("../../shaders/equirect.wgsl");
/// `shaders/pole_merge.wgsl`.
pub const POLE_MERGE: &str = include_str!("../../shaders/pole_merge.wgsl");
/// `shaders/ods.wgsl`.
pub const ODS: &str = include_str!("../../shaders/ods.wgsl");
/// `shaders/sphere_bounds.wgsl`: the box of a sphere's image.
pub const SPHERE_BOUNDS: &str = include_str!("../../shaders/sphere_bounds.wgsl");
/// `shaders/shading.wgsl`.
pub const SHADING: &str = include_str!("../../shaders/shading.wgsl");
/// `shaders/params.wgsl`: the per-(chunk, eye) uniform.
pub const PARAMS: &str = include_str!("../../shaders/params.wgsl");
/// `shaders/expand.wgsl`: the proxy-expansion compute pass.
pub const EXPAND: &str = include_str!("../../shaders/expand.wgsl");
/// `shaders/sphere.wgsl`: the ray-sphere intersection.
pub const SPHERE: &str = include_str!("../../shaders/sphere.wgsl");
/// `shaders/splat.wgsl`: the compute splat of small spheres (64-bit atomics).
pub const SPLAT: &str = include_str!("../../shaders/splat.wgsl");
/// `shaders/splat_off.wgsl`: the splat's stand-in without 64-bit atomics.
pub const SPLAT_OFF: &str = include_str!("../../shaders/splat_off.wgsl");
/// `shaders/imposter.wgsl`: the imposter vertex and fragment stages.
pub const IMPOSTER: &str = include_str!("../../shaders/imposter.wgsl");

/// The projection math every pipeline needs, followed by `parts`.
pub fn compose(parts: &[&str]) -> String {
    let mut s = [CAMERA, EQUIRECT, POLE_MERGE, ODS].join("\n");
    for p in parts {
        s.push('\n');
        s.push_str(p);
    }
    s
}

/// Source of the expand compute pipeline; `splat` includes the compute splat (the device
/// must have 64-bit atomics).
pub fn expand_source(splat: bool) -> String {
    compose(&[
        PARAMS,
        SPHERE_BOUNDS,
        EXPAND,
        SPHERE,
        if splat { SPLAT } else { SPLAT_OFF },
    ])
}

/// Source of the imposter render pipeline.
pub fn imposter_source() -> String {
    compose(&[PARAMS, SHADING, SPHERE, IMPOSTER])
}
