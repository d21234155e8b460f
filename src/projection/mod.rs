//! Camera model, equirectangular mapping, pole merging and the ODS ray (DESIGN §1–4).
//!
//! Everything here is f64 and exact: the reference that the WGSL in `shaders/` mirrors
//! file for file (`camera.wgsl`, `equirect.wgsl`, `pole_merge.wgsl`, `ods.wgsl`).

pub mod camera;
pub mod equirect;
pub mod ods;
pub mod pole_merge;

pub use camera::Camera;
pub use equirect::Equirect;
pub use ods::{Eye, OdsOffset, Stereo, StereoKind, View};
pub use pole_merge::{PoleMerge, PoleMerging};
