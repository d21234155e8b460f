//! What can go wrong while reading a folder of frames or its `tour.json`.

use std::path::PathBuf;

/// An error of a frame folder: the message names the file or frame at fault.
#[derive(Debug, thiserror::Error)]
pub enum FramesError {
    /// A file or folder could not be read or written.
    #[error("cannot {action} {path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What was being done ("read", "write", ...).
        action: &'static str,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A folder holds no frames.
    #[error("{path} holds no {kinds} frames (frame_000000.png, frame_000001.png, ...)")]
    NoFrames {
        /// The folder.
        path: PathBuf,
        /// The image kinds looked for ("PNG or JPEG", ...).
        kinds: &'static str,
    },
    /// The numbered frames have a gap.
    #[error("{dir}: frame {missing} is missing ({expected} not found); frames run 0 to {last}")]
    MissingFrame {
        /// The folder.
        dir: PathBuf,
        /// The missing frame's number.
        missing: usize,
        /// The file name that was expected.
        expected: String,
        /// The highest frame number present.
        last: usize,
    },
    /// `tour.json` lists more frames than the folder holds.
    #[error(
        "{path} lists {listed} frames but the folder holds {found}: the tour is not fully rendered yet"
    )]
    IncompleteTour {
        /// The `tour.json`.
        path: PathBuf,
        /// Frames it lists.
        listed: usize,
        /// Frames found.
        found: usize,
    },
    /// A frame differs in size from the first.
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
    /// A frame could not be decoded.
    #[error("{path} is not a readable PNG or JPEG image: {reason}")]
    BadImage {
        /// The file.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// `tour.json`, or the folder it describes, is not what a tour writes.
    #[error("{path}: {reason}")]
    BadTour {
        /// The `tour.json` or the frame at fault.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The frames' shape does not fit the stereo layout asked for, or any.
    #[error("{path} is {width}x{height}: {reason}")]
    Shape {
        /// The first frame.
        path: PathBuf,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// Why the layout does not fit.
        reason: String,
    },
    /// A frame's description could not be read, or the manifest not written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}
