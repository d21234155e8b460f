//! CPU ray tracer: the exact accuracy reference (obvhs BVH over spheres).
//!
//! One ray per pixel centre (DESIGN §2, §3), computed in f64 by [`View::pixel_ray`]; the
//! BVH is traversed in f32 but each candidate sphere is intersected in f64
//! ([`crate::projection::sphere::intersect`]), so depths carry f64 precision from the f32 sphere centres.
//!
//! [`View::pixel_ray`]: crate::projection::View::pixel_ray

pub mod bvh;
pub mod render;

pub use bvh::{BvhBuildParams, Hit, Tracer, TracerMemory, trace_brute_force};
pub use render::{padding_for, render, render_with_tracer};

use crate::render::color::MissingAttribute;

/// Why the ray tracer could not render a scene.
#[derive(Debug, thiserror::Error)]
pub enum RaytraceError {
    /// The requested colour mode needs an attribute the scene lacks.
    #[error("ray tracer: {0}")]
    Color(#[from] MissingAttribute),
    /// The BVH indexes points with u32.
    #[error("ray tracer: the scene has {0} points; at most 4,294,967,295 are supported")]
    TooManyPoints(usize),
    /// A point centre is NaN or infinite.
    #[error("ray tracer: point {0} has a non-finite position")]
    NonFinitePosition(usize),
    /// A sphere radius is negative, NaN or infinite.
    #[error("ray tracer: point {index} has an invalid radius {radius}")]
    InvalidRadius {
        /// Point index.
        index: usize,
        /// The offending radius.
        radius: f32,
    },
    /// The image has no pixels.
    #[error("ray tracer: image {width}x{height} has no pixels")]
    EmptyImage {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
    /// A prebuilt tracer was given a scene with a different number of points.
    #[error("ray tracer: the tracer was built for {tracer} points but the scene has {scene}")]
    SceneMismatch {
        /// Points in the tracer.
        tracer: usize,
        /// Points in the scene.
        scene: usize,
    },
}
