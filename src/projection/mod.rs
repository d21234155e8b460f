//! Camera model, equirectangular mapping, pole merging, the ODS ray (DESIGN §1–4) and the
//! bounding box of a sphere's image (`docs/SPHERE_BOUNDS.md`).
//!
//! Everything here is f64 and exact: the reference that the WGSL in `shaders/` mirrors
//! file for file (`camera.wgsl`, `equirect.wgsl`, `pole_merge.wgsl`, `ods.wgsl`,
//! `sphere_bounds.wgsl`).

pub mod camera;
pub mod cubemap;
pub mod cylindrical;
pub mod depth_map;
pub mod equirect;
pub mod fisheye;
pub mod hammer;
pub mod image;
pub mod map;
pub mod ods;
pub mod pole_merge;
pub mod sphere_bounds;

pub use camera::Camera;
pub use equirect::Equirect;
pub use image::{Image, Projection};
pub use map::MapFrame;
pub use ods::{Eye, EyeModel, OdsOffset, Stereo, StereoKind, View};
pub use pole_merge::{PoleMerge, PoleMerging};
pub use sphere_bounds::{Bounds, Rect, cap_rect, sphere_bounds};
