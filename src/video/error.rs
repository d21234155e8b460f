//! What can go wrong while reading frames, encoding or muxing a video.

use std::path::PathBuf;

/// An error of the video encoder: the message names the file, frame or setting at fault.
#[derive(Debug, thiserror::Error)]
pub enum VideoError {
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
    #[error("{path} holds no frames (frame_000000.png, frame_000001.png, ... or .jpg)")]
    NoFrames {
        /// The folder.
        path: PathBuf,
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
    /// `tour.json` is not what a tour writes.
    #[error("{path}: {reason}")]
    BadTour {
        /// The `tour.json`.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The frame size cannot be encoded or would not play on common players.
    #[error("{width}x{height} frames cannot be encoded: {reason}")]
    FrameTooLarge {
        /// Frame width.
        width: u32,
        /// Frame height.
        height: u32,
        /// Why, with the largest sizes allowed.
        reason: String,
    },
    /// The frame rate and size together exceed what the accepted H.264 level allows.
    #[error(
        "{width}x{height} at {fps} fps needs {needed} macroblocks per second, more than H.264 level {level} allows ({allowed}): lower --fps (at most {max_fps:.0} at this size) or the width"
    )]
    RateTooHigh {
        /// Frame width.
        width: u32,
        /// Frame height.
        height: u32,
        /// Frames per second.
        fps: f64,
        /// Macroblocks per second needed.
        needed: u64,
        /// The highest level accepted.
        level: &'static str,
        /// Its macroblock rate.
        allowed: u64,
        /// The highest frame rate at this size.
        max_fps: f64,
    },
    /// A bad option value.
    #[error("{0}")]
    Option(String),
    /// The stereo layout asked for does not fit the frame shape.
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
    /// The H.264 encoder or decoder failed.
    #[error("H.264 {action} failed at frame {frame}: {reason}")]
    Codec {
        /// "encoding" or "decoding".
        action: &'static str,
        /// The frame number.
        frame: usize,
        /// What OpenH264 said.
        reason: String,
    },
    /// An MP4 file could not be written or read as the video this module writes.
    #[error("{path}: {reason}")]
    Mp4 {
        /// The MP4 file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Writing the output file failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}
