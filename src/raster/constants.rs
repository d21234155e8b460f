//! Constants shared by the Rust side and the WGSL, defined once here. [`wgsl_prelude`]
//! declares each of them for the shaders; `shaders::compose` prepends it to every module.

use std::mem::{offset_of, size_of};

use super::stats::EyeStats;

/// A value a WGSL `const` declaration can hold.
trait WgslLiteral {
    /// The declaration `const NAME: TYPE = VALUE;`.
    fn declare(&self, name: &str) -> String;
}

impl WgslLiteral for u32 {
    fn declare(&self, name: &str) -> String {
        format!("const {name}: u32 = {self}u;\n")
    }
}

impl WgslLiteral for i32 {
    fn declare(&self, name: &str) -> String {
        format!("const {name}: i32 = {self}i;\n")
    }
}

impl WgslLiteral for f32 {
    fn declare(&self, name: &str) -> String {
        // `{:?}` is the shortest decimal that reads back as this f32, with a `.` or exponent.
        format!("const {name}: f32 = {self:?};\n")
    }
}

/// Defines each constant in Rust and lists it in [`wgsl_prelude`].
macro_rules! shared_constants {
    ($($(#[doc = $doc:literal])* $name:ident: $ty:ty = $value:expr;)*) => {
        $($(#[doc = $doc])* pub const $name: $ty = $value;)*

        /// WGSL declarations of every constant of this module.
        pub fn wgsl_prelude() -> String {
            let mut s = String::from("// Generated from src/raster/constants.rs.\n");
            $(s.push_str(&WgslLiteral::declare(&$name, stringify!($name)));)*
            s
        }
    };
}

/// Index of a `u32` counter of [`EyeStats`] from its byte offset.
const fn stat(offset: usize) -> u32 {
    (offset / size_of::<u32>()) as u32
}

shared_constants! {
    /// Invocations per expand workgroup (`@workgroup_size` of `expand`).
    EXPAND_WORKGROUP: u32 = 256;
    /// Side of a deferred-shading workgroup, pixels (`@workgroup_size` of `shade_keys`).
    SHADE_WORKGROUP_SIDE: u32 = 8;
    /// Side of an occlusion tile, pixels (`shaders/occlusion.wgsl`).
    TILE_SIDE: u32 = 8;
    /// Side of a tile-resolve workgroup, in tiles (`@workgroup_size` of `resolve_tiles`).
    RESOLVE_WORKGROUP_SIDE: u32 = 8;
    /// Largest tessellation level the dynamic proxy may choose.
    MAX_DYNAMIC_LEVEL: u32 = 16;
    /// Bit 31 of a vertex's point index: shade this proxy by ray casting whatever the imposter
    /// mode (eye-enclosing, near-eye and pole-band proxies have no meaningful billboard).
    FORCE_RAYCAST: u32 = 1 << 31;
    /// Angular slack added around analytic bounds, radians: covers f32 rounding of the bounds
    /// and of the fragment's ray (about 0.06 px at 3840 wide).
    ANGLE_MARGIN: f32 = 2e-4;
    /// Largest point index within a chunk that a key can hold (see `shaders/splat_key.wgsl`):
    /// the low 24 bits of its payload.
    MAX_KEY_INDEX: u32 = (1 << 24) - 1;
    /// Slack added around the pixel rectangles of `shaders/image_bounds.wgsl`, pixels: covers
    /// the f32 rounding of their corners (the projections other than the full equirect).
    PIXEL_MARGIN: f32 = 0.01;
    /// Fixed-point steps of the ODS inverse before it falls back to bisection (as the f64
    /// solver in `src/projection/ods.rs`).
    FIXED_POINT_ITERATIONS: i32 = crate::projection::ods::FIXED_POINT_ITERATIONS as i32;

    /// `Params::proxy`: the analytic bounding rectangle.
    PROXY_BOUNDS: u32 = 0;
    /// `Params::proxy`: projected billboard corners.
    PROXY_QUAD: u32 = 1;
    /// `Params::proxy`: an N x N billboard (`Params::static_level`).
    PROXY_STATIC: u32 = 2;
    /// `Params::proxy`: a billboard tessellated per point.
    PROXY_DYNAMIC: u32 = 3;

    /// `Params::projection`: the full 360 x 180 equirect (`equirect.wgsl`'s own arithmetic).
    PROJ_EQUIRECT_FULL: u32 = 0;
    /// `Params::projection`: equirect over `a = (hfov, vfov)` radians.
    PROJ_EQUIRECT: u32 = 1;
    /// `Params::projection`: Hammer–Aitoff.
    PROJ_HAMMER: u32 = 2;
    /// `Params::projection`: cylindrical, `a = (tan(vfov/2), vfov)`.
    PROJ_CYLINDRICAL: u32 = 3;
    /// `Params::projection`: equidistant fisheye, `a.x = fov` radians.
    PROJ_FISHEYE: u32 = 4;
    /// `Params::projection`: the six-face strip.
    PROJ_CUBEMAP: u32 = 5;
    /// `Params::projection`: the map, `a = (x0, y1, x1 - x0, y1 - y0)`, `b.x = z_top`,
    /// relative to the camera centre.
    PROJ_MAP: u32 = 6;

    /// `Params::imposter`: exact per-pixel ray casting.
    IMPOSTER_RAYCAST: u32 = 0;
    /// `Params::imposter`: billboard (sprite) shading.
    IMPOSTER_SPRITE: u32 = 1;

    /// `Params::shading`: the base colour only.
    SHADING_UNLIT: u32 = 0;
    /// `Params::shading`: ambient, diffuse and specular from two lights.
    SHADING_PHONG: u32 = 1;
    /// `Params::shading`: the normal as colour.
    SHADING_NORMAL: u32 = 2;

    /// `PoleMerge::kind`: no merging.
    MERGE_OFF: u32 = 0;
    /// `PoleMerge::kind`: Marrinan (a = start_deg, b = end_deg, c = exponent).
    MERGE_MARRINAN: u32 = 1;
    /// `PoleMerge::kind`: Cycles (a = from_deg, b = to_deg).
    MERGE_CYCLES: u32 = 2;

    /// `Params::ods_offset`: the exact inverse.
    OFFSET_EXACT: u32 = 0;
    /// `Params::ods_offset`: the paper's per-vertex offset.
    OFFSET_PAPER: u32 = 1;

    /// `Params::eye_model`: rays on the viewing circle (ODS; mono when the eye sign is 0).
    MODEL_ODS: u32 = 0;
    /// `Params::eye_model`: every ray of an eye starts at its parallel camera.
    MODEL_PARALLEL: u32 = 1;

    /// A pipeline constant of `params.wgsl` left open: the shader reads `Params` instead.
    SPEC_ANY: u32 = u32::MAX;
    /// `SPEC_EYES`: every view of the pipeline is mono (eye sign 0).
    SPEC_MONO: u32 = 0;
    /// `SPEC_EYES`: every view of the pipeline is a stereo eye.
    SPEC_STEREO: u32 = 1;

    /// Counters per eye in the statistics buffer (one [`EyeStats`]).
    STATS_PER_EYE: u32 = stat(size_of::<EyeStats>());
    /// Counter index of [`EyeStats::culled`].
    STAT_CULLED: u32 = stat(offset_of!(EyeStats, culled));
    /// Counter index of [`EyeStats::drawn`].
    STAT_DRAWN: u32 = stat(offset_of!(EyeStats, drawn));
    /// Counter index of [`EyeStats::special`].
    STAT_SPECIAL: u32 = stat(offset_of!(EyeStats, special));
    /// Counter index of [`EyeStats::seam`].
    STAT_SEAM: u32 = stat(offset_of!(EyeStats, seam));
    /// Counter index of [`EyeStats::overflow`].
    STAT_OVERFLOW: u32 = stat(offset_of!(EyeStats, overflow));
    /// Counter index of [`EyeStats::vertices`].
    STAT_VERTICES: u32 = stat(offset_of!(EyeStats, vertices));
    /// Counter index of [`EyeStats::splatted`].
    STAT_SPLATTED: u32 = stat(offset_of!(EyeStats, splatted));
    /// Counter index of [`EyeStats::occluded`].
    STAT_OCCLUDED: u32 = stat(offset_of!(EyeStats, occluded));
    /// Counter index of [`EyeStats::wide`].
    STAT_WIDE: u32 = stat(offset_of!(EyeStats, wide));
}

/// Near and far distances (metres) of the logarithmic depth `log(t/near)/log(far/near)`:
/// a Depth32Float then orders hits to about 2e-6 relative distance over 13 decades. They
/// reach the shaders through `Params` (as run-time values the division and logarithm stay run-time
/// operations, exactly as the fragment stage has always evaluated them).
pub const DEPTH_NEAR: f32 = 1e-6;
/// See [`DEPTH_NEAR`].
pub const DEPTH_FAR: f32 = 1e7;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_prelude_declares_each_constant_with_its_value() {
        let p = wgsl_prelude();
        assert!(p.contains("const EXPAND_WORKGROUP: u32 = 256u;\n"), "{p}");
        assert!(
            p.contains("const FORCE_RAYCAST: u32 = 2147483648u;\n"),
            "{p}"
        );
        assert!(
            p.contains("const FIXED_POINT_ITERATIONS: i32 = 8i;\n"),
            "{p}"
        );
        assert!(p.contains("const STAT_SPLATTED: u32 = 6u;\n"), "{p}");
        assert!(p.contains("const STAT_OCCLUDED: u32 = 7u;\n"), "{p}");
        assert!(p.contains("const STAT_WIDE: u32 = 8u;\n"), "{p}");
        assert!(p.contains("const STATS_PER_EYE: u32 = 9u;\n"), "{p}");
        // The f32 literal reads back (through f64, as WGSL's abstract float) as the same f32.
        let text = p
            .lines()
            .find_map(|l| l.strip_prefix("const ANGLE_MARGIN: f32 = "))
            .and_then(|v| v.strip_suffix(';'))
            .expect("ANGLE_MARGIN declared");
        assert_eq!(text.parse::<f64>().unwrap() as f32, ANGLE_MARGIN);
    }
}
