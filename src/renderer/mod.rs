//! The renderer chosen at run time (rasterizer or ray tracer) with its scene kept resident
//! between frames: the points on the GPU (or streamed through it), or the ray tracer's BVH.
//! `render --origin`, `render --projection map`, `tour` and `serve` all draw through
//! [`Resident`], so a tour's frame, a served frame and the single render of their camera are
//! the same computation.
//!
//! [`anchor`] says where the rasterizer's f32 positions are measured from, [`resident`] holds
//! the scene for either renderer, `node_stream` draws a COPC scan through its level of detail
//! with the nodes cached on the GPU, [`frames`] is what both offer a tour, and [`error`] says
//! why they could not.

pub mod anchor;
pub mod error;
pub mod frames;
#[cfg(feature = "gpu")]
pub mod node_stream;
#[cfg(feature = "gpu")]
mod on_gpu;
pub mod resident;

pub use anchor::Anchor;
pub use error::ResidentError;
pub use frames::DrawsFrames;
#[cfg(feature = "gpu")]
pub use node_stream::{FrameNodes, NodeRules, NodeStream};
pub use resident::Resident;
