//! Choosing the file format from a file name's extension.

use std::path::Path;

use super::OutputError;

/// A file format this crate writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit sRGB RGBA PNG.
    Png,
    /// 8-bit sRGB JPEG (`.jpg`, `.jpeg`), no coverage.
    Jpeg,
    /// Google's VR Photo (`.vr.jpg`): the left eye as a JPEG, the right eye inside its XMP.
    VrJpeg,
    /// 32-bit float OpenEXR.
    Exr,
}

const EXPECTED: &str = ".png, .jpg, .vr.jpg or .exr";

impl ImageFormat {
    /// The format named by `path`'s extension (`.png`, `.jpg`/`.jpeg`, `.vr.jpg`, `.exr`,
    /// any case).
    pub fn from_path(path: &Path) -> Result<ImageFormat, OutputError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let vr = path
            .file_stem()
            .and_then(|s| s.to_str())
            .is_some_and(|s| s.to_ascii_lowercase().ends_with(".vr"));
        match ext.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("jpg") if vr => Ok(ImageFormat::VrJpeg),
            Some("jpg" | "jpeg") => Ok(ImageFormat::Jpeg),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(OutputError::UnsupportedExtension {
                path: path.to_path_buf(),
                expected: EXPECTED,
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
                    ImageFormat::Jpeg => ".jpg",
                    ImageFormat::VrJpeg => ".vr.jpg",
                    ImageFormat::Exr => ".exr",
                },
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_name() {
        let f = |name: &str| ImageFormat::from_path(Path::new(name)).ok();
        assert_eq!(f("a.PNG"), Some(ImageFormat::Png));
        assert_eq!(f("a.jpg"), Some(ImageFormat::Jpeg));
        assert_eq!(f("a.JPEG"), Some(ImageFormat::Jpeg));
        assert_eq!(f("dir.vr/a.jpg"), Some(ImageFormat::Jpeg));
        assert_eq!(f("a.vr.jpg"), Some(ImageFormat::VrJpeg));
        assert_eq!(f("a.VR.JPG"), Some(ImageFormat::VrJpeg));
        assert_eq!(f("a.vr.jpeg"), Some(ImageFormat::Jpeg));
        assert_eq!(f("a.exr"), Some(ImageFormat::Exr));
        assert_eq!(f("a.tif"), None);
    }
}
