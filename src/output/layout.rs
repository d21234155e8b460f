//! Writing renders to files: stereo layout, format by extension, depth-only EXR.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use super::OutputError;
use super::atomic::{StagedFile, commit_all};
use super::exr::{ExrContent, encode_exr};
use super::format::ImageFormat;
use super::png::encode_png;
use crate::frame::{Frame, Rendered};

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

/// The (file, frame) pairs a render gives under `layout`; only a top-bottom pair is a new
/// image, the others borrow the rendered frames (no copy of a large panorama).
fn frames_for<'r>(
    path: &Path,
    rendered: &'r Rendered,
    layout: Layout,
) -> Vec<(PathBuf, Cow<'r, Frame>)> {
    match (rendered, layout) {
        (Rendered::Mono(f), _) => vec![(path.to_path_buf(), Cow::Borrowed(f))],
        (Rendered::Stereo { .. }, Layout::TopBottom) => {
            vec![(path.to_path_buf(), Cow::Owned(rendered.top_bottom()))]
        }
        (Rendered::Stereo { left, right }, Layout::SeparateEyes) => vec![
            (eye_path(path, "left"), Cow::Borrowed(left)),
            (eye_path(path, "right"), Cow::Borrowed(right)),
        ],
    }
}

/// Stages every file first and renames them only when all were written, so a failure leaves
/// none of them.
fn write_frames(
    files: Vec<(PathBuf, Cow<'_, Frame>)>,
    write: impl Fn(&Frame, &mut std::io::BufWriter<std::fs::File>, &Path) -> Result<(), OutputError>,
) -> Result<Vec<PathBuf>, OutputError> {
    let staged = files
        .iter()
        .map(|(p, f)| StagedFile::create(p, |w| write(f, w, p)))
        .collect::<Result<Vec<_>, _>>()?;
    commit_all(staged)
}

/// Writes the colour image(s) of `rendered`, PNG or EXR by `path`'s extension, each file
/// atomically. Returns the files written (two for [`Layout::SeparateEyes`] in stereo).
pub fn write_image(
    path: &Path,
    rendered: &Rendered,
    layout: Layout,
) -> Result<Vec<PathBuf>, OutputError> {
    let format = ImageFormat::from_path(path)?;
    write_frames(frames_for(path, rendered, layout), |f, w, p| match format {
        ImageFormat::Png => encode_png(f, w, p),
        ImageFormat::Exr => encode_exr(f, ExrContent::ColorAndDepth, w, p),
    })
}

/// Writes depth only (a single `Z` channel, metres along the ray, `+inf` background) to an
/// `.exr` file, with the same stereo layout rules as [`write_image`].
pub fn write_depth(
    path: &Path,
    rendered: &Rendered,
    layout: Layout,
) -> Result<Vec<PathBuf>, OutputError> {
    ImageFormat::require(path, ImageFormat::Exr)?;
    write_frames(frames_for(path, rendered, layout), |f, w, p| {
        encode_exr(f, ExrContent::DepthOnly, w, p)
    })
}
