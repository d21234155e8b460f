//! omnicloud: LiDAR point clouds to 360° equirectangular panoramas and omnidirectional-stereo
//! (ODS) pairs, by a GPU imposter-sphere rasterizer and an exact CPU ray tracer.
//!
//! The conventions every renderer shares (camera, ODS ray, pole merging, outputs) are in
//! `DESIGN.md`; [`projection`] implements them.
//!
//! Features: `gpu` (the wgpu rasterizer, [`raster`]), `charts` (benchmark charts and the
//! comparison heatmap), `bench` (both, plus timing runs), `web` (the panorama viewer's
//! server; with `gpu` also the live scan server), `video` (360 videos: H.264 MP4 with
//! Spherical Video V2 metadata), `cli` (all of them and the `omnicloud` binary; the default).
//! Without them the library reads, prepares, ray-traces, streams, writes and compares scans.

#[cfg(feature = "bench")]
pub mod bench;
#[cfg(feature = "cli")]
pub mod cli;
pub mod compare;
#[cfg(feature = "charts")]
pub mod font;
pub mod frame;
pub mod frames;
pub mod index;
pub mod io;
pub mod memory;
pub mod output;
pub mod prepare;
pub mod projection;
#[cfg(feature = "gpu")]
pub mod raster;
pub mod raytrace;
pub mod render;
pub mod renderer;
pub mod rng;
pub mod scene;
pub mod stats;
pub mod stream;
pub mod suite;
pub mod synthetic;
pub mod tour;
pub mod value;
#[cfg(feature = "video")]
pub mod video;
#[cfg(feature = "web")]
pub mod web;

pub use frame::{Frame, Rendered};
pub use scene::{Attributes, Radii, Scene};
