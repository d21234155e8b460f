//! Writing renders to files: stereo layout, format by extension, metadata, depth-only EXR.

use std::path::{Path, PathBuf};

use super::OutputError;
use super::atomic::{StagedFile, commit_all};
use super::description::{ImageDescription, StoredEyes};
use super::exr::{ExrContent, ExrViews, encode_exr_with};
use super::format::ImageFormat;
use super::jpeg::{encode_jpeg, encode_vr_jpeg};
use super::png::encode_png;
use super::xmp::{PhotoSphere, heading_from_yaw};
use crate::frame::{Frame, Rendered};
use crate::projection::Projection;

/// How a stereo render is laid out in files. Mono renders always give one file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// One `W x 2H` file, left eye on top (DESIGN §6), what 360° players expect.
    #[default]
    TopBottom,
    /// Two files: `NAME.ext` becomes `NAME_left.ext` and `NAME_right.ext`.
    SeparateEyes,
}

/// The file name of one eye in [`Layout::SeparateEyes`]: `pano.png` -> `pano_left.png`.
pub fn eye_path(path: &Path, eye: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match path.extension() {
        Some(ext) => format!("{stem}_{eye}.{}", ext.to_string_lossy()),
        None => format!("{stem}_{eye}"),
    };
    path.with_file_name(name)
}

/// How files are written besides their format: stereo layout, JPEG quality, camera heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputOptions {
    /// Stereo layout (ignored for mono renders and `.vr.jpg`, which holds both eyes).
    pub layout: Layout,
    /// JPEG quality, 1..=100.
    pub jpeg_quality: u8,
    /// The camera's `yaw` in degrees (DESIGN §1), written as the panorama's heading.
    pub yaw_degrees: f64,
    /// The projection of each eye, written into every file's [`ImageDescription`]. Only the
    /// full 360° x 180° equirect carries the metadata that tells players the image is a
    /// panorama (GPano, VR Photo, EXR `envmap`).
    pub projection: Projection,
    /// Metres per unit of the scan's coordinates, written into every file's description;
    /// `None` when the scan declares no unit of length.
    pub metres_per_unit: Option<f64>,
}

impl OutputOptions {
    /// True when the image is the full 360° x 180° equirect.
    pub fn panorama(&self) -> bool {
        self.projection.is_full_equirect()
    }

    /// The description of a file holding `eyes` of the image.
    fn description(&self, eyes: StoredEyes) -> ImageDescription {
        ImageDescription {
            projection: self.projection,
            eyes,
            metres_per_unit: self.metres_per_unit,
        }
    }
}

impl Default for OutputOptions {
    fn default() -> Self {
        OutputOptions {
            layout: Layout::TopBottom,
            jpeg_quality: super::jpeg::DEFAULT_QUALITY,
            yaw_degrees: 0.0,
            projection: Projection::EQUIRECT,
            metres_per_unit: None,
        }
    }
}

/// What one file holds.
#[derive(Debug, Clone, Copy)]
enum Content<'r> {
    /// One image: mono, or one eye of separate files.
    One(&'r Frame, StoredEyes),
    /// Both eyes of an ODS render in one file.
    Pair { left: &'r Frame, right: &'r Frame },
}

/// The files a render gives under `layout` and what each holds.
fn files_for<'r>(
    path: &Path,
    rendered: &'r Rendered,
    layout: Layout,
    format: ImageFormat,
) -> Result<Vec<(PathBuf, Content<'r>)>, OutputError> {
    let not_stereo = || OutputError::NotStereo {
        path: path.to_path_buf(),
        what: "a VR photo (.vr.jpg)",
    };
    Ok(match rendered {
        Rendered::Mono(_) if format == ImageFormat::VrJpeg => return Err(not_stereo()),
        Rendered::Mono(f) => vec![(path.to_path_buf(), Content::One(f, StoredEyes::Mono))],
        // A VR photo holds both eyes whatever the layout.
        Rendered::Stereo { left, right }
            if layout == Layout::SeparateEyes && format != ImageFormat::VrJpeg =>
        {
            vec![
                (eye_path(path, "left"), Content::One(left, StoredEyes::Left)),
                (
                    eye_path(path, "right"),
                    Content::One(right, StoredEyes::Right),
                ),
            ]
        }
        Rendered::Stereo { left, right } => {
            vec![(path.to_path_buf(), Content::Pair { left, right })]
        }
    })
}

/// Stages every file first and renames them only when all were written, so a failure leaves
/// none of them.
fn write_files(
    files: Vec<(PathBuf, Content<'_>)>,
    write: impl Fn(
        Content<'_>,
        &mut std::io::BufWriter<std::fs::File>,
        &Path,
    ) -> Result<(), OutputError>,
) -> Result<Vec<PathBuf>, OutputError> {
    let staged = files
        .iter()
        .map(|(p, c)| StagedFile::create(p, |w| write(*c, w, p)))
        .collect::<Result<Vec<_>, _>>()?;
    commit_all(staged)
}

/// Both eyes stacked top-bottom (left on top, DESIGN §6).
fn stack(left: &Frame, right: &Frame, path: &Path) -> Result<Frame, OutputError> {
    if left.width != right.width {
        return Err(OutputError::EyeSizeMismatch {
            path: path.to_path_buf(),
            left: (left.width, left.height),
            right: (right.width, right.height),
        });
    }
    let mut out = left.clone();
    out.height += right.height;
    out.color.extend_from_slice(&right.color);
    out.depth.extend_from_slice(&right.depth);
    Ok(out)
}

/// Writes the colour image(s) of `rendered` with default [`OutputOptions`] but `layout`
/// (heading 0, JPEG quality 90); see [`write_image_with`].
pub fn write_image(
    path: &Path,
    rendered: &Rendered,
    layout: Layout,
) -> Result<Vec<PathBuf>, OutputError> {
    let options = OutputOptions {
        layout,
        ..OutputOptions::default()
    };
    write_image_with(path, rendered, &options)
}

/// Writes the colour image(s) of `rendered`, the format by `path`'s extension, each file
/// atomically. Returns the files written (two for [`Layout::SeparateEyes`] in stereo).
///
/// Metadata that 360° players read:
/// - a full panorama (mono, or one eye of separate files) in PNG or JPEG carries Photo
///   Sphere XMP (GPano) with the heading from `yaw_degrees`;
/// - a top-bottom ODS PNG or JPEG carries none: GPano describes one sphere, and a viewer
///   that trusted it would stretch both eyes over one sphere. Players recognise top-bottom
///   stereo from the file name (`_360_TB`) instead;
/// - `.vr.jpg` is Google's VR Photo (left eye with GPano, right eye in extended XMP);
/// - EXR files are marked `envmap = latlong`; an ODS pair is a multi-view file.
///
/// JPEG files also carry a small EXIF block (make and model `omnicloud`). Every PNG, JPEG and
/// EXR names its projection and eyes ([`ImageDescription`]), so that `compare` and `view` need
/// not guess them from the image's shape.
pub fn write_image_with(
    path: &Path,
    rendered: &Rendered,
    options: &OutputOptions,
) -> Result<Vec<PathBuf>, OutputError> {
    let format = ImageFormat::from_path(path)?;
    let quality = options.jpeg_quality;
    let heading_degrees = heading_from_yaw(options.yaw_degrees);
    let panorama = options.panorama();
    let sphere = |f: &Frame| PhotoSphere {
        width: f.width,
        height: f.height,
        heading_degrees,
    };
    let sphere = |f: &Frame| panorama.then(|| sphere(f));
    if format == ImageFormat::VrJpeg && !panorama {
        return Err(OutputError::NotPanorama {
            path: path.to_path_buf(),
            what: "a VR photo (.vr.jpg)",
        });
    }
    let files = files_for(path, rendered, options.layout, format)?;
    write_files(files, |content, w, p| {
        let description = options.description(content.eyes());
        let d = Some(&description);
        match (format, content) {
            (ImageFormat::Png, Content::One(f, _)) => encode_png(f, sphere(f).as_ref(), d, w, p),
            (ImageFormat::Png, Content::Pair { left, right }) => {
                encode_png(&stack(left, right, p)?, None, d, w, p)
            }
            (ImageFormat::Jpeg, Content::One(f, _)) => {
                encode_jpeg(f, quality, sphere(f).as_ref(), d, w, p)
            }
            (ImageFormat::Jpeg, Content::Pair { left, right }) => {
                encode_jpeg(&stack(left, right, p)?, quality, None, d, w, p)
            }
            // Its own XMP says what a VR photo holds (and its main image is one eye).
            (ImageFormat::VrJpeg, Content::Pair { left, right }) => {
                encode_vr_jpeg(left, right, quality, heading_degrees, w, p)
            }
            (ImageFormat::VrJpeg, Content::One(..)) => Err(OutputError::NotStereo {
                path: p.to_path_buf(),
                what: "a VR photo (.vr.jpg)",
            }),
            (ImageFormat::Exr, c) => {
                encode_exr_with(exr_views(c), ExrContent::ColorAndDepth, &description, w, p)
            }
        }
    })
}

impl Content<'_> {
    /// The eyes the file stores.
    fn eyes(self) -> StoredEyes {
        match self {
            Content::One(_, eyes) => eyes,
            Content::Pair { .. } => StoredEyes::TopBottom,
        }
    }
}

fn exr_views(content: Content<'_>) -> ExrViews<'_> {
    match content {
        Content::One(f, _) => ExrViews::Mono(f),
        Content::Pair { left, right } => ExrViews::Stereo { left, right },
    }
}

/// Writes depth only (a single `Z` channel, metres along the ray, `+inf` background) to an
/// `.exr` file, with the same stereo layout rules as [`write_image`] (an ODS pair is one
/// multi-view file with `Z` and `right.Z`).
pub fn write_depth(
    path: &Path,
    rendered: &Rendered,
    layout: Layout,
) -> Result<Vec<PathBuf>, OutputError> {
    write_depth_with(
        path,
        rendered,
        &OutputOptions {
            layout,
            ..OutputOptions::default()
        },
    )
}

/// [`write_depth`] with `options`' layout, described with `options`' projection (marked a
/// panorama only when it is the full equirect).
pub fn write_depth_with(
    path: &Path,
    rendered: &Rendered,
    options: &OutputOptions,
) -> Result<Vec<PathBuf>, OutputError> {
    ImageFormat::require(path, ImageFormat::Exr)?;
    let files = files_for(path, rendered, options.layout, ImageFormat::Exr)?;
    write_files(files, |c, w, p| {
        let description = options.description(c.eyes());
        encode_exr_with(exr_views(c), ExrContent::DepthOnly, &description, w, p)
    })
}
