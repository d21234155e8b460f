//! Why the rasterizer could not render.

/// A rasterizer failure; every variant says what failed and, where useful, what to do.
#[derive(Debug, thiserror::Error)]
pub enum RasterError {
    /// No wgpu adapter exists on this machine.
    #[error(
        "no GPU adapter found (install mesa-vulkan-drivers for the software adapter, or use --renderer raytrace)"
    )]
    NoAdapter,
    /// The adapter refused the device (features or limits).
    #[error("the GPU adapter {adapter} refused to create a device: {reason}")]
    DeviceRequest {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        reason: String,
    },
    /// A request does not fit the adapter's limits.
    #[error("{what} needs {needed} but the GPU adapter allows at most {limit}")]
    Limit {
        /// What was being sized.
        what: String,
        /// What it needs.
        needed: u64,
        /// The adapter's limit.
        limit: u64,
    },
    /// The device ran out of memory.
    #[error("the GPU ran out of memory while {while_doing} ({message}); try a smaller --width")]
    OutOfMemory {
        /// The step that failed.
        while_doing: String,
        /// wgpu's message.
        message: String,
    },
    /// The device was lost (driver reset, crash).
    #[error("the GPU device was lost: {0}")]
    DeviceLost(String),
    /// wgpu reported a validation or internal error: a bug in this crate.
    #[error("GPU error while {while_doing}: {message}")]
    Gpu {
        /// The step that failed.
        while_doing: String,
        /// wgpu's message.
        message: String,
    },
    /// The colour mode needs an attribute the scene lacks.
    #[error(transparent)]
    Color(#[from] crate::render::color::MissingAttribute),
    /// The settings ask for something the rasterizer cannot draw.
    #[error("invalid rasterizer settings: {0}")]
    Settings(String),
}
