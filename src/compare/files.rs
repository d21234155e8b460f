//! `omnicloud compare`: read two files, compare, write the JSON report and heatmap.

use std::io::Write;
use std::path::Path;

use super::CompareError;
use super::measure::compare_named;
use super::report::CompareReport;
use crate::output::{ImageFormat, OutputError, read_image, write_atomically};

/// Compares `test_path` against `ref_path` (EXR, or PNG without depth), writing the JSON
/// report to `report` and the heatmap PNG to `heatmap_path` when given (both atomically).
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
    let reference = read_image(ref_path)?;
    let test = read_image(test_path)?;
    let what = format!("{} vs {}", ref_path.display(), test_path.display());
    let result = compare_named(&reference, &test, &what)?;
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
