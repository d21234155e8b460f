//! Why planning or streaming a render failed.

use crate::io::LoadError;
use crate::prepare::PrepareError;
use crate::render::color::MissingAttribute;
use std::path::PathBuf;

/// An error boxed by a [`super::ChunkSink`] (the renderer's own error type).
pub type SinkError = Box<dyn std::error::Error + Send + Sync>;

/// Why a streamed render could not be planned or completed.
#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    /// Opening, seeking or reading the file failed (the error names the file).
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The colour mode needs an attribute the file lacks.
    #[error(transparent)]
    Color(#[from] MissingAttribute),
    /// Preparing the surveyed points failed (no camera position could be found on them).
    #[error(transparent)]
    Prepare(#[from] PrepareError),
    /// The renderer failed on a chunk; streaming stopped.
    #[error("rendering failed: {0}")]
    Sink(SinkError),
    /// The decoding thread could not start or died.
    #[error("{}: the decoding thread failed: {detail}", path.display())]
    Worker {
        /// The file being decoded.
        path: PathBuf,
        /// What happened.
        detail: String,
    },
}

impl StreamError {
    /// Wraps a renderer's error as [`StreamError::Sink`].
    pub fn sink(error: impl Into<SinkError>) -> Self {
        StreamError::Sink(error.into())
    }
}
