//! Comparing a test render against a reference: coverage, silhouette, depth and colour
//! errors, per eye, per 10° latitude band and at the seam; a JSON report and a heatmap.
//!
//! Definitions (a pixel is *hit* when its coverage is at least 0.5):
//! - coverage mismatch: pixels hit in exactly one image (count, % of pixels);
//!   IoU = |ref ∩ test| / |ref ∪ test| (1 when both are empty);
//! - silhouette error: per mismatched pixel, the distance in pixels to the nearest pixel of
//!   opposite *reference* coverage (see [`silhouette`]), mean and max;
//! - depth relative error `|z_t - z_r| / z_r` over pixels both hit with finite depths
//!   (nearest-rank p50, p99, max);
//! - colour: pixels both hit whose colour differs, and the PSNR (peak 1) of sRGB-encoded
//!   colour over pixels both hit.
//!
//! Files are laid out as their descriptions say ([`crate::output::description`]: projection
//! and eyes); without one, a square image is taken for a top-bottom ODS pair and any image for
//! full equirect panoramas. A pair is reported per eye (left = top half). In full equirect
//! panoramas, latitude bands are 10° by pixel-centre latitude, top first, and the seam is the
//! 1% of columns nearest each edge (at least one column each side); other projections get
//! neither.
//!
//! Images are read through [`Samples`]: EXR and PNG files as [`crate::output::LinearImage`],
//! renders as [`crate::Frame`]s; [`compare_eyes`] sums the eyes of a render into one set of
//! statistics (what `bench` reports).

mod error;
pub mod eyes;
mod files;
#[cfg(feature = "charts")]
pub mod heatmap;
pub mod holes;
mod measure;
pub mod photo;
pub mod rendered_disparity;
mod report;
mod samples;
pub mod silhouette;
pub mod stats;

pub use error::CompareError;
pub use files::compare_files;
#[cfg(feature = "charts")]
pub use heatmap::{LegendLayout, heatmap};
pub use holes::{HoleStats, holes};
pub use measure::{Regions, compare, compare_eyes, compare_named};
pub use report::{CompareReport, EyeReport};
pub use samples::Samples;
pub use stats::{DepthErrorStats, RegionStats};
