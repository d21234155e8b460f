//! Why a scene could not be kept resident or rendered from there.

use crate::raytrace::RaytraceError;

/// Why a resident scene could not be built or rendered.
#[derive(Debug, thiserror::Error)]
pub enum ResidentError {
    /// The ray tracer failed.
    #[error(transparent)]
    Raytrace(#[from] RaytraceError),
    /// The rasterizer failed (no adapter, or the scan does not fit the GPU).
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Raster(#[from] crate::raster::RasterError),
    /// The colour mode needs an attribute the scene lacks.
    #[error(transparent)]
    Color(#[from] crate::render::color::MissingAttribute),
    /// The points were released from the GPU and not placed again.
    #[cfg(feature = "gpu")]
    #[error("the scene's points are not on the GPU: place them before rendering")]
    NotPlaced,
    /// A level-of-detail node could not be read.
    #[error(transparent)]
    Read(#[from] crate::prepare::PrepareError),
    /// The scan file read node by node changed on disk after it was opened.
    #[error(
        "{}: the file changed while it was being read ({what}): no frame is drawn from a \
         changed scan; rerun to start from the file as it is now",
        path.display()
    )]
    ScanChanged {
        /// The file.
        path: std::path::PathBuf,
        /// What differs from when it was opened.
        what: String,
    },
    /// This build has no rasterizer.
    #[error("this build has no GPU rasterizer (feature `gpu`); use --renderer raytrace")]
    NoRasterizer,
}
