//! `omnicloud view`: a local web server that shows a panorama (mono or ODS top-bottom) or a
//! tour folder of frames in the browser, and in a headset through WebXR; with the `gpu`
//! feature, `omnicloud serve` ([`serve`]): a scan rendered live for the same page code.
//!
//! The page samples the equirect image per pixel along each view ray (DESIGN.md section 2:
//! longitude 0 at the image centre, +90° to the right, latitude +90° on the top row), so a
//! direction in the page is the direction the renderer gave that pixel.

mod assets;
pub mod door;
mod error;
mod host;
pub mod panorama;
pub mod query;
mod respond;
pub mod routes;
#[cfg(feature = "gpu")]
pub mod serve;
mod server;

pub use error::WebError;
pub use panorama::{Panorama, PanoramaInfo, PanoramaKind};
/// The `Range` header as the servers read it, public for the fuzz targets.
#[doc(hidden)]
pub use respond::{FileRange, byte_range};
pub use server::{Running, Stopper, ViewServer};
