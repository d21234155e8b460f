//! GPU imposter-sphere rasterizer (wgpu), DESIGN §3, §5, §7.
//!
//! A compute pass (`expand.rs`, `shaders/expand.wgsl`) turns each point into per-eye proxy
//! triangles in equirect pixel space (in the other projections of DESIGN §8: the pixel
//! rectangles of `shaders/image_bounds.wgsl`, each pixel ray cast with its projection's ray,
//! `shaders/projection.wgsl`); a render pass (`imposter.rs`, `shaders/imposter.wgsl`)
//! shades each fragment as the sphere (exact ODS ray cast, or the paper's sprite). Where the
//! device has 64-bit atomics and the imposters are ray cast (the keyed path, `splat.rs`), small
//! spheres are ray cast by the compute pass instead, and every hit, splatted or drawn, keeps
//! its pixel's nearest distance and colour in a 64-bit key that is the image
//! (`key_targets.rs`); elsewhere fragments shade into render targets with a logarithmic depth
//! test (`targets.rs`). Points live on the GPU relative to the camera centre, in chunks that
//! fit one storage binding. Rays of the equirect and cylindrical projections come from
//! per-column and per-row tables (`pixel_trig.rs`). [`Rasterizer`] holds the device, the pipelines compiled
//! per mode (`specialisation.rs`) and the last frame's buffers (`frame_buffers.rs`); frames
//! borrow it.

mod chunk;
mod chunked_frame;
mod constants;
mod context;
mod error;
mod expand;
mod formats;
mod frame_buffers;
mod imposter;
mod key_targets;
mod lock;
mod params;
mod piece_occlusion;
pub mod pipeline_cache;
mod pixel_trig;
pub mod probe;
mod raster_frame;
mod rasterizer;
mod read_back;
#[cfg(test)]
mod shader_validation;
mod shaders;
mod sizing;
mod specialisation;
mod splat;
mod splat_shade;
mod stats;
mod targets;
mod tile_resolve;
mod timing;
mod upload;

pub use chunked_frame::ChunkedFrame;
pub use error::RasterError;
pub use pipeline_cache::CacheStatus;
pub use raster_frame::RasterFrame;
pub use rasterizer::Rasterizer;
pub use sizing::draws;
pub use stats::RasterStats;
pub use timing::{FrameTiming, TimingSource};
pub use upload::UploadedScene;
