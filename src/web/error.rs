//! What can go wrong while opening panoramas or starting the viewer's server.

use std::path::PathBuf;

/// An error of the viewer: the message names the file or address at fault.
#[derive(Debug, thiserror::Error)]
pub enum WebError {
    /// A file or folder could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file is not a PNG or JPEG image the viewer can decode.
    #[error("{path} is not a PNG or JPEG image: {reason}")]
    NotAnImage {
        /// The file.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// An MP4 file the viewer cannot play as a panorama.
    #[error("cannot show {path} as a 360 video: {reason}")]
    NotAVideo {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The image's shape is neither 2:1 (mono) nor 1:1 (ODS top-bottom).
    #[error(
        "{path} is {width}x{height}: expected a 2:1 mono panorama or a 1:1 top-bottom ODS pair"
    )]
    Shape {
        /// The file.
        path: PathBuf,
        /// Its width in pixels.
        width: u32,
        /// Its height in pixels.
        height: u32,
    },
    /// A file's metadata could not be read or does not parse (the error names the file).
    #[error(transparent)]
    Metadata(#[from] crate::output::OutputError),
    /// The file says it is not a full equirect panorama.
    #[error(
        "{path} is a {projection} image, not a 360° panorama: the viewer shows full equirect \
         renders (--projection equirect)"
    )]
    NotPanorama {
        /// The file.
        path: PathBuf,
        /// Its projection, as its description names it.
        projection: String,
    },
    /// A folder's frames cannot be shown together (none, or of different sizes).
    #[error(transparent)]
    Frames(#[from] crate::frames::FramesError),
    /// The server could not listen on the address.
    #[error("cannot listen on {addr}: {reason}")]
    Bind {
        /// The host and port asked for.
        addr: String,
        /// Why.
        reason: String,
    },
}
