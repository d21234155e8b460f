//! The one error type of point-cloud loading: every variant names the file and says, in one
//! line, what is wrong with it.

use std::path::PathBuf;

/// Why a point-cloud file could not be opened or read.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The path does not exist.
    #[error("{}: file not found", path.display())]
    NotFound {
        /// The file asked for.
        path: PathBuf,
    },
    /// The file exists but reading it failed (permissions, a directory, an I/O error).
    #[error("{}: cannot read the file: {source}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The file holds no byte at all.
    #[error("{}: the file is empty", path.display())]
    EmptyFile {
        /// The file.
        path: PathBuf,
    },
    /// Neither the first bytes nor the extension name a format we read.
    #[error(
        "{}: unsupported format (neither LAS/LAZ, PLY nor E57 magic bytes; extension '{extension}'); expected .las, .laz, .ply or .e57",
        path.display()
    )]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
        /// Its extension (empty when it has none).
        extension: String,
    },
    /// The header is truncated or does not parse.
    #[error("{}: corrupt or truncated {format} header: {detail}", path.display())]
    CorruptHeader {
        /// The file.
        path: PathBuf,
        /// "LAS", "PLY" or "E57".
        format: &'static str,
        /// What failed.
        detail: String,
    },
    /// The header declares more points than the file's bytes can hold.
    #[error(
        "{}: the header declares {declared} points but the file holds only {available}",
        path.display()
    )]
    PointCountExceedsFile {
        /// The file.
        path: PathBuf,
        /// Point count from the header.
        declared: u64,
        /// Whole point records present in the file.
        available: u64,
    },
    /// A COPC read was asked of a file without the COPC info VLR.
    #[error("{}: not a COPC file (no COPC info VLR); it reads as a plain LAS/LAZ file", path.display())]
    NotCopc {
        /// The file.
        path: PathBuf,
    },
    /// A COPC file's octree hierarchy is missing or corrupt.
    #[error("{}: corrupt COPC hierarchy: {detail}", path.display())]
    CorruptCopc {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        detail: String,
    },
    /// The point data ends or breaks before the declared count (found while reading).
    #[error(
        "{}: truncated or corrupt point data: failed after {read} of {declared} points: {detail}",
        path.display()
    )]
    CorruptPoints {
        /// The file.
        path: PathBuf,
        /// Points read successfully before the failure.
        read: u64,
        /// Point count from the header.
        declared: u64,
        /// What failed.
        detail: String,
    },
    /// The header declares zero points.
    #[error("{}: the file holds zero points", path.display())]
    NoPoints {
        /// The file.
        path: PathBuf,
    },
    /// Every point had a NaN or infinite coordinate.
    #[error("{}: all {dropped} points have NaN or infinite coordinates", path.display())]
    NoFinitePoints {
        /// The file.
        path: PathBuf,
        /// Points dropped.
        dropped: u64,
    },
    /// A LAS version other than 1.0–1.4.
    #[error("{}: unsupported LAS version {major}.{minor} (1.0 to 1.4 are supported)", path.display())]
    UnsupportedLasVersion {
        /// The file.
        path: PathBuf,
        /// Major version from the header.
        major: u8,
        /// Minor version from the header.
        minor: u8,
    },
    /// A LAS point data record format other than 0–10, or one the version does not allow.
    #[error("{}: unsupported LAS point format: {detail}", path.display())]
    UnsupportedLasPointFormat {
        /// The file.
        path: PathBuf,
        /// What the header said.
        detail: String,
    },
    /// The file made a third-party decoder panic (corrupt data the decoder does not check).
    #[error("{}: corrupt data: the decoder failed while {what}: {detail}", path.display())]
    DecoderPanic {
        /// The file.
        path: PathBuf,
        /// The step that failed, e.g. "decoding points".
        what: &'static str,
        /// The decoder's panic message.
        detail: String,
    },
    /// A seek asked for a point index beyond the declared count.
    #[error("{}: cannot seek to point {point}: the file declares {declared} points", path.display())]
    SeekPastEnd {
        /// The file.
        path: PathBuf,
        /// Point index asked for.
        point: u64,
        /// Point count from the header.
        declared: u64,
    },
    /// The reader cannot position itself at a point (a LAZ file without a chunk table, a
    /// failed file seek, data ending before the point).
    #[error("{}: cannot seek to point {point}: {detail}", path.display())]
    SeekFailed {
        /// The file.
        path: PathBuf,
        /// Point index asked for.
        point: u64,
        /// What failed.
        detail: String,
    },
    /// A scan picked by index or name (`--scan`, `#scan:`) is not in the E57 file.
    #[error("{}: {detail}", path.display())]
    NoSuchScan {
        /// The file.
        path: PathBuf,
        /// Which pick failed and why.
        detail: String,
    },
    /// The PLY file has no `vertex` element with scalar `x`, `y` and `z` properties.
    #[error("{}: PLY has no 'vertex' element with scalar x, y and z properties ({detail})", path.display())]
    PlyMissingXyz {
        /// The file.
        path: PathBuf,
        /// What is missing.
        detail: String,
    },
}

impl LoadError {
    /// The file the error is about.
    pub fn path(&self) -> &std::path::Path {
        match self {
            LoadError::NotFound { path }
            | LoadError::Unreadable { path, .. }
            | LoadError::EmptyFile { path }
            | LoadError::UnsupportedFormat { path, .. }
            | LoadError::CorruptHeader { path, .. }
            | LoadError::CorruptCopc { path, .. }
            | LoadError::NotCopc { path }
            | LoadError::PointCountExceedsFile { path, .. }
            | LoadError::CorruptPoints { path, .. }
            | LoadError::NoPoints { path }
            | LoadError::NoFinitePoints { path, .. }
            | LoadError::UnsupportedLasVersion { path, .. }
            | LoadError::UnsupportedLasPointFormat { path, .. }
            | LoadError::PlyMissingXyz { path, .. }
            | LoadError::NoSuchScan { path, .. }
            | LoadError::SeekPastEnd { path, .. }
            | LoadError::SeekFailed { path, .. }
            | LoadError::DecoderPanic { path, .. } => path,
        }
    }

    /// Maps an error from opening or reading the file, telling "missing" from "unreadable".
    pub(crate) fn from_io(path: &std::path::Path, source: std::io::Error) -> Self {
        if source.kind() == std::io::ErrorKind::NotFound {
            LoadError::NotFound {
                path: path.to_path_buf(),
            }
        } else {
            LoadError::Unreadable {
                path: path.to_path_buf(),
                source,
            }
        }
    }
}
