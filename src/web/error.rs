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
    /// A folder holds no PNG or JPEG frames.
    #[error("{path} holds no PNG or JPEG frames (frame_000000.png, ...)")]
    NoFrames {
        /// The folder.
        path: PathBuf,
    },
    /// A frame of a folder differs in size from the first.
    #[error(
        "{path} is {width}x{height}, but the first frame {first} is {first_width}x{first_height}"
    )]
    FrameSize {
        /// The odd frame.
        path: PathBuf,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// The first frame.
        first: PathBuf,
        /// The first frame's width.
        first_width: u32,
        /// The first frame's height.
        first_height: u32,
    },
    /// The server could not listen on the address.
    #[error("cannot listen on {addr}: {reason}")]
    Bind {
        /// The host and port asked for.
        addr: String,
        /// Why.
        reason: String,
    },
}
