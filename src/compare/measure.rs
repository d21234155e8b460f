//! Computing the report from two images.

use super::CompareError;
use super::eyes::{EyeRows, LATITUDE_BANDS, band_name, latitude_band, seam_columns, split_eyes};
use super::report::{CompareReport, EyeReport};
use super::silhouette::silhouette_errors;
use super::stats::{PixelErrors, RegionAccumulator, color_squared_error, depth_relative_error};
use crate::output::LinearImage;

/// Fails unless the two images have the same, non-zero size; `what` names them in errors.
pub(crate) fn check_sizes(
    reference: &LinearImage,
    test: &LinearImage,
    what: &str,
) -> Result<(), CompareError> {
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(CompareError::SizeMismatch {
            what: what.to_owned(),
            reference: (reference.width, reference.height),
            test: (test.width, test.height),
        });
    }
    if reference.is_empty() {
        return Err(CompareError::Empty {
            what: what.to_owned(),
        });
    }
    Ok(())
}

/// Compares a test image against a reference of the same size (see the module docs for each
/// metric). A square image is compared per eye as a top-bottom ODS pair.
pub fn compare(reference: &LinearImage, test: &LinearImage) -> Result<CompareReport, CompareError> {
    compare_named(reference, test, "images")
}

/// [`compare`], naming the inputs `what` in errors.
pub(crate) fn compare_named(
    reference: &LinearImage,
    test: &LinearImage,
    what: &str,
) -> Result<CompareReport, CompareError> {
    check_sizes(reference, test, what)?;
    let eyes = split_eyes(reference.width, reference.height);
    let layout = if eyes.len() == 2 {
        "top-bottom"
    } else {
        "mono"
    };
    Ok(CompareReport {
        width: reference.width,
        height: reference.height,
        layout: layout.to_owned(),
        eyes: eyes
            .iter()
            .map(|e| compare_eye(reference, test, e))
            .collect(),
    })
}

fn compare_eye(reference: &LinearImage, test: &LinearImage, eye: &EyeRows) -> EyeReport {
    let w = reference.width as usize;
    let h = eye.height as usize;
    let base = eye.first_row as usize * w;
    let ref_hit: Vec<bool> = (base..base + w * h).map(|k| reference.hit(k)).collect();
    let test_hit: Vec<bool> = (base..base + w * h).map(|k| test.hit(k)).collect();
    let silhouette = silhouette_errors(&ref_hit, &test_hit, w, h);
    let seam = seam_columns(reference.width) as usize;

    let mut all = RegionAccumulator::default();
    let mut bands: Vec<RegionAccumulator> = (0..LATITUDE_BANDS)
        .map(|_| RegionAccumulator::default())
        .collect();
    let mut seam_acc = RegionAccumulator::default();
    for j in 0..h {
        let band = &mut bands[latitude_band(j as u32, eye.height)];
        for i in 0..w {
            let local = j * w + i;
            let k = base + local;
            let both = ref_hit[local] && test_hit[local];
            let e = PixelErrors {
                ref_hit: ref_hit[local],
                test_hit: test_hit[local],
                silhouette: silhouette[local],
                depth_relative: both
                    .then(|| depth_relative_error(reference.depth[k], test.depth[k]))
                    .flatten(),
                color_squared: both.then(|| color_squared_error(reference.color[k], test.color[k])),
            };
            all.add(&e);
            band.add(&e);
            if i < seam || i >= w - seam {
                seam_acc.add(&e);
            }
        }
    }
    EyeReport {
        eye: eye.name.to_owned(),
        width: reference.width,
        height: eye.height,
        all: all.finish("all".to_owned()),
        latitude_bands: bands
            .into_iter()
            .enumerate()
            .map(|(b, acc)| acc.finish(band_name(b)))
            .collect(),
        seam_columns_each_side: seam as u32,
        seam: seam_acc.finish("seam".to_owned()),
    }
}
