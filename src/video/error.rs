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
    /// The frame folder or its `tour.json` is not what a video is made of.
    #[error(transparent)]
    Frames(#[from] crate::frames::FramesError),
    /// Writing the output file failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}
