//! omnicloud: LiDAR point clouds to 360° equirectangular panoramas and omnidirectional-stereo
//! (ODS) pairs, by a GPU imposter-sphere rasterizer and an exact CPU ray tracer.
//!
//! The conventions every renderer shares (camera, ODS ray, pole merging, outputs) are in
//! `DESIGN.md`; [`projection`] implements them.

pub mod bench;
pub mod cli;
pub mod compare;
pub mod frame;
pub mod io;
pub mod memory;
pub mod output;
pub mod placement;
pub mod projection;
pub mod radius;
pub mod raster;
pub mod raytrace;
pub mod render;
pub mod rng;
pub mod scene;
pub mod stream;
pub mod subsample;
pub mod suite;
pub mod synthetic;

pub use frame::{Frame, Rendered};
pub use scene::{Attributes, Radii, Scene};
