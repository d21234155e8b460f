//! Camera model and orientation, the projections, pole merging, the ODS ray and the other
//! stereo models, disparity and the depth budget (DESIGN §1–4, §8–9), the bounding box of a
//! sphere's image (`docs/SPHERE_BOUNDS.md`), its pixel rectangles in every projection
//! (`image_bounds`) and the ray–sphere intersection (`sphere`).
//!
//! Everything here is f64 and exact: the reference that the WGSL in `shaders/` mirrors
//! file for file (`camera.wgsl`, `equirect.wgsl`, `pole_merge.wgsl`, `ods.wgsl`,
//! `sphere_bounds.wgsl`, `projection.wgsl`, `image_bounds.wgsl`, `sphere.wgsl`).

pub mod camera;
pub mod cubemap;
pub mod cylindrical;
pub mod depth_map;
pub mod disparity;
pub mod disparity_image;
pub mod equirect;
pub mod fisheye;
pub mod hammer;
pub mod image;
pub mod image_bounds;
pub mod map;
pub mod ods;
pub mod pole_merge;
pub mod sphere;
pub mod sphere_bounds;

pub use camera::Camera;
pub use equirect::Equirect;
pub use image::{Image, Projection};
pub use image_bounds::{Margins, PixelRect, image_bounds};
pub use map::MapFrame;
pub use ods::{Eye, EyeModel, OdsOffset, Stereo, StereoKind, View};
pub use pole_merge::{PoleMerge, PoleMerging};
pub use sphere_bounds::{Bounds, Rect, cap_rect, sphere_bounds};
