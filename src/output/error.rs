//! Errors of the output writers and the EXR reader; every variant names the file.

use std::path::PathBuf;

/// Why an image could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file name's extension names no format this writer produces.
    #[error("{path}: unsupported extension (expected {expected})")]
    UnsupportedExtension {
        /// The requested output file.
        path: PathBuf,
        /// The extensions that would be accepted, e.g. `.png or .exr`.
        expected: &'static str,
    },
    /// A file-system operation (create, write, rename, read) failed.
    #[error("{path}: {action} failed: {source}")]
    Io {
        /// The file concerned (the final name, not the temporary one).
        path: PathBuf,
        /// What was being done, e.g. `creating temporary file`.
        action: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// PNG encoding or decoding failed.
    #[error("{path}: PNG error: {source}")]
    Png {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: image::ImageError,
    },
    /// PNG encoding (with metadata chunks) failed.
    #[error("{path}: PNG error: {source}")]
    PngEncode {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: png::EncodingError,
    },
    /// OpenEXR encoding or decoding failed.
    #[error("{path}: OpenEXR error: {source}")]
    Exr {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: exr::error::Error,
    },
    /// An EXR file lacks the channels needed to recover coverage.
    #[error("{path}: EXR has neither an `A` (coverage) nor a `Z` (depth) channel")]
    NoCoverage {
        /// The file concerned.
        path: PathBuf,
    },
    /// An EXR file is not a disparity image (a channel missing, another unit).
    #[error("{path}: not a disparity EXR: {what}")]
    NotDisparity {
        /// The file concerned.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// A stereo-only output (anaglyph, VR photo) was asked for a mono render.
    #[error("{path}: {what} needs a stereo (ODS) render, got a mono one")]
    NotStereo {
        /// The requested output file.
        path: PathBuf,
        /// What was asked for, e.g. `an anaglyph`.
        what: &'static str,
    },
    /// A 360°-only output (VR photo) was asked for another projection.
    #[error(
        "{path}: {what} holds 360° x 180° equirectangular eyes: render it with --projection equirect"
    )]
    NotPanorama {
        /// The requested output file.
        path: PathBuf,
        /// What was asked for.
        what: &'static str,
    },
    /// JPEG encoding failed.
    #[error("{path}: JPEG encoding failed: {source}")]
    JpegEncode {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: jpeg_encoder::EncodingError,
    },
    /// JPEG decoding failed.
    #[error("{path}: JPEG error: {source}")]
    Jpeg {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: image::ImageError,
    },
    /// Metadata too large for one JPEG segment (64 KiB) or for extended XMP (4 GiB).
    #[error("{path}: {bytes} bytes of metadata exceed what a JPEG segment can hold")]
    SegmentTooLarge {
        /// The file concerned.
        path: PathBuf,
        /// Size of the segment or packet.
        bytes: usize,
    },
    /// A `.vr.jpg` file holds no readable right eye.
    #[error("{path}: not a VR photo: {what}")]
    NoRightEye {
        /// The file concerned.
        path: PathBuf,
        /// What is missing.
        what: &'static str,
    },
    /// The two eyes of a stereo render differ in size.
    #[error("{path}: left eye is {left:?} pixels but right eye is {right:?}")]
    EyeSizeMismatch {
        /// The requested output file.
        path: PathBuf,
        /// Left eye (width, height).
        left: (u32, u32),
        /// Right eye (width, height).
        right: (u32, u32),
    },
    /// The image has no pixels or more than the format can hold.
    #[error("{path}: cannot write a {width}x{height} image")]
    BadSize {
        /// The requested output file.
        path: PathBuf,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// A file's omnicloud description (see [`super::description`]) does not parse.
    #[error("{path}: bad `omnicloud` description `{text}`: {reason}")]
    BadDescription {
        /// The file concerned.
        path: PathBuf,
        /// The description's text.
        text: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A file could not be read for its description.
    #[error("{path}: cannot read its metadata: {reason}")]
    Metadata {
        /// The file concerned.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}
