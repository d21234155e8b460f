//! Choosing the file format from a file name's extension.

use std::path::Path;

use super::OutputError;

/// A file format this crate writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit sRGB RGBA PNG.
    Png,
    /// 32-bit float OpenEXR.
    Exr,
}

impl ImageFormat {
    /// The format named by `path`'s extension (`.png` or `.exr`, any case).
    pub fn from_path(path: &Path) -> Result<ImageFormat, OutputError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(OutputError::UnsupportedExtension {
                path: path.to_path_buf(),
                expected: ".png or .exr",
            }),
        }
    }

    /// Like [`ImageFormat::from_path`] but accepts only `wanted`.
    pub fn require(path: &Path, wanted: ImageFormat) -> Result<(), OutputError> {
        match ImageFormat::from_path(path) {
            Ok(f) if f == wanted => Ok(()),
            _ => Err(OutputError::UnsupportedExtension {
                path: path.to_path_buf(),
                expected: match wanted {
                    ImageFormat::Png => ".png",
                    ImageFormat::Exr => ".exr",
                },
            }),
        }
    }
}
