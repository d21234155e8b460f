//! `omnicloud compare`: read two files, compare, write the JSON report and heatmap.

use std::io::Write;
use std::path::Path;

use super::CompareError;
use super::eyes::ImageLayout;
use super::measure::compare_named;
use super::report::CompareReport;
use crate::output::{
    ImageDescription, ImageFormat, OutputError, read_description, read_image, write_atomically,
};

/// Compares `test_path` against `ref_path` (EXR, or PNG without depth), writing the JSON
/// report to `report` and the heatmap PNG to `heatmap_path` when given (both atomically).
/// The images are laid out as their descriptions say (which must agree on the projection
/// and the number of eyes), else as their shape suggests.
pub fn compare_files(
    ref_path: &Path,
    test_path: &Path,
    report: Option<&Path>,
    heatmap_path: Option<&Path>,
) -> Result<CompareReport, CompareError> {
    if let Some(p) = heatmap_path {
        // Fail before the (possibly long) comparison, not after.
        if cfg!(not(feature = "charts")) {
            return Err(CompareError::NoCharts {
                path: p.to_path_buf(),
            });
        }
        ImageFormat::require(p, ImageFormat::Png)?;
    }
    let what = format!("{} vs {}", ref_path.display(), test_path.display());
    let described = agreed_description(
        read_description(ref_path)?,
        read_description(test_path)?,
        &what,
    )?;
    let reference = read_image(ref_path)?;
    let test = read_image(test_path)?;
    let layout = match &described {
        Some(d) => {
            ImageLayout::described(d, reference.height).ok_or_else(|| CompareError::Layout {
                what: what.clone(),
                reason: format!(
                    "{} rows do not split into the {} eyes its description names",
                    reference.height,
                    d.eyes.count()
                ),
            })?
        }
        None => ImageLayout::from_shape(reference.width, reference.height),
    };
    let result = compare_named(&reference, &test, &layout, &what)?;
    if let Some(path) = report {
        let json = serde_json::to_vec_pretty(&result).map_err(|source| CompareError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        write_atomically(path, |w| {
            w.write_all(&json).map_err(|source| OutputError::Io {
                path: path.to_path_buf(),
                action: "writing",
                source,
            })
        })?;
    }
    #[cfg(feature = "charts")]
    if let Some(path) = heatmap_path {
        crate::output::write_png_buffer(path, &super::heatmap::heatmap(&reference, &test)?)?;
    }
    Ok(result)
}

/// The description the comparison goes by: the reference's, else the test's. Both, when
/// given, must name the same projection and the same number of eyes (a left eye may be
/// compared with a right one).
fn agreed_description(
    reference: Option<ImageDescription>,
    test: Option<ImageDescription>,
    what: &str,
) -> Result<Option<ImageDescription>, CompareError> {
    match (reference, test) {
        (Some(r), Some(t)) if r.projection != t.projection || r.eyes.count() != t.eyes.count() => {
            Err(CompareError::Layout {
                what: what.to_owned(),
                reason: format!(
                    "reference is {} {} but test is {} {}; compare renders of the same \
                     projection and stereo mode",
                    r.projection,
                    r.eyes.name(),
                    t.projection,
                    t.eyes.name()
                ),
            })
        }
        (r, t) => Ok(r.or(t)),
    }
}
