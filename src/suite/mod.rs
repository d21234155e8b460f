//! The stability suite: small generated scenes with known geometry where projection-based
//! renderers fail (poles, seam, near and enclosing spheres, the ODS viewing circle, UTM
//! coordinates, dense clusters, huge spheres, high latitudes), written to `data/scenes/` with
//! a manifest `suite.json` that says how to view each.

pub mod manifest;
pub mod ply;
pub mod scenes;

use std::path::PathBuf;

pub use manifest::{
    MANIFEST_FILE, Manifest, ManifestEntry, load_manifest, manifest_of, suite_files, write_suite,
};
pub use scenes::{SuitePoint, SuiteScene, SuiteStereo, SuiteView, all_scenes};

/// What can go wrong writing or reading the suite.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    /// A suite file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A suite file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The manifest is not valid JSON of the expected shape.
    #[error("bad manifest {path}: {source}")]
    Json {
        /// The manifest file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
    /// A manifest entry holds a value the CLI would reject.
    #[error("suite entry '{name}': {reason}")]
    BadEntry {
        /// The entry's name.
        name: String,
        /// What is wrong.
        reason: String,
    },
}
