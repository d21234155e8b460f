//! Errors of the comparison.

use std::path::PathBuf;

use crate::output::OutputError;

/// Why two images could not be compared or the results not written.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// Reading an input or writing the heatmap failed (the error names the file).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A scan file (an E57 image as the reference) could not be read.
    #[error(transparent)]
    Load(#[from] crate::io::LoadError),
    /// Reference and test differ in size.
    #[error(
        "{what}: reference is {}x{} pixels but test is {}x{}; compare renders of the same size",
        reference.0, reference.1, test.0, test.1
    )]
    SizeMismatch {
        /// What was compared (the two file names, or `images`).
        what: String,
        /// Reference (width, height).
        reference: (u32, u32),
        /// Test (width, height).
        test: (u32, u32),
    },
    /// The images' descriptions disagree, or do not fit the image.
    #[error("{what}: {reason}")]
    Layout {
        /// What was compared (the two file names).
        what: String,
        /// What does not fit.
        reason: String,
    },
    /// The images have no pixels.
    #[error("{what}: images have no pixels")]
    Empty {
        /// What was compared.
        what: String,
    },
    /// The JSON report could not be serialised.
    #[error("{path}: writing JSON report failed: {source}")]
    Json {
        /// The report file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: serde_json::Error,
    },
    /// A heatmap was asked of a library built without the `charts` feature.
    #[error("{path}: drawing a heatmap needs omnicloud's `charts` feature")]
    NoCharts {
        /// The heatmap file asked for.
        path: PathBuf,
    },
}
