//! GPU imposter-sphere rasterizer (wgpu), DESIGN §3, §5, §7.
//!
//! A compute pass (`shaders/expand.wgsl`) turns each point into per-eye proxy triangles in
//! equirect pixel space; a render pass (`shaders/imposter.wgsl`) shades each fragment as the
//! sphere (exact ODS ray cast, or the paper's sprite) with a logarithmic depth test. Points
//! live on the GPU relative to the camera centre, in chunks that fit one storage binding.

pub mod chunked_frame;
pub mod context;
pub mod error;
pub mod params;
pub mod pipelines;
pub mod probe;
pub mod raster_frame;
pub mod rasterizer;
pub mod shaders;
pub mod targets;

pub use chunked_frame::ChunkedFrame;
pub use error::RasterError;
pub use raster_frame::RasterFrame;
pub use rasterizer::{FrameTiming, RasterStats, Rasterizer, TimingSource, UploadedScene};
