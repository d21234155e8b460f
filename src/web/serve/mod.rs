//! `omnicloud serve`: a scan kept in memory and on the GPU, a top-down map to pick camera
//! positions on, and ODS pairs rendered live as the page asks (camera, IPD, pole merging),
//! shown by the viewer's page code, in VR too; and a live stream ([`live`]) of pairs for a
//! client walking through the scan.

pub mod live;
pub mod map;
pub mod queue;
pub mod render_thread;
pub mod request;
pub mod routes;
pub mod scan;
mod server;

use std::path::PathBuf;

pub use live::StreamOptions;
pub use map::{MapGrid, render_map};
pub use render_thread::{
    LiveFrame, RawFrame, RenderFailure, RenderQueue, RenderThread, live_settings,
};
pub use request::{CameraLimits, RenderRequest};
pub use scan::{LiveOptions, LiveScan, ScanInfo, ServedLod};
pub use server::LiveServer;

/// Why a scan cannot be served.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The scan holds no point.
    #[error("{}: no points to serve", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The colour mode needs an attribute the scan lacks.
    #[error(transparent)]
    Color(#[from] crate::render::color::MissingAttribute),
    /// An image could not be encoded.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// The renderer could not start or could not hold the scan.
    #[error(transparent)]
    Resident(#[from] crate::renderer::ResidentError),
    /// The render thread could not be started.
    #[error("cannot start the render thread: {0}")]
    Thread(std::io::Error),
    /// The server could not listen.
    #[error(transparent)]
    Web(#[from] super::WebError),
}
