//! Why an index could not be written.

use std::path::PathBuf;

use crate::io::LoadError;
use crate::output::OutputError;

/// Why [`super::index`] failed. Nothing is left at the output path, and no temporary file.
#[derive(Debug, thiserror::Error)]
pub enum IndexError {
    /// An input could not be read (the error names the file).
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The output could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A temporary bucket file failed (a full disk, mostly).
    #[error("{path}: {action} a temporary file failed: {source}")]
    Scratch {
        /// The temporary file.
        path: PathBuf,
        /// What was being done.
        action: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Writing the output file failed.
    #[error("{path}: writing the index failed: {detail}")]
    Write {
        /// The output file.
        path: PathBuf,
        /// What went wrong.
        detail: String,
    },
    /// No input point has usable coordinates.
    #[error("{path}: no point with usable coordinates to index")]
    NoPoints {
        /// The first input.
        path: PathBuf,
    },
    /// The inputs' coordinates cannot share one LAS integer grid.
    #[error(
        "{path}: the points span {extent:.0} units, too wide for 32-bit LAS coordinates at scale {scale}"
    )]
    TooWide {
        /// The first input.
        path: PathBuf,
        /// Largest extent.
        extent: f64,
        /// The scale tried.
        scale: f64,
    },
}
