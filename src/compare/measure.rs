//! Computing the report from two images.

use super::CompareError;
use super::eyes::{EyeRows, ImageLayout, LATITUDE_BANDS, band_name, latitude_band, seam_columns};
use super::report::{CompareReport, EyeReport};
use super::samples::Samples;
use super::silhouette::silhouette_errors;
use super::stats::{
    PixelErrors, RegionAccumulator, RegionStats, color_squared_error, depth_relative_error,
};

/// Fails unless the two images have the same, non-zero size; `what` names them in errors.
pub(crate) fn check_sizes<S: Samples>(
    reference: &S,
    test: &S,
    what: &str,
) -> Result<(), CompareError> {
    let (r, t) = (reference.size(), test.size());
    if r != t {
        return Err(CompareError::SizeMismatch {
            what: what.to_owned(),
            reference: r,
            test: t,
        });
    }
    if r.0 == 0 || r.1 == 0 {
        return Err(CompareError::Empty {
            what: what.to_owned(),
        });
    }
    Ok(())
}

/// Compares a test image against a reference of the same size (see the module docs for each
/// metric), laid out as its shape suggests: a square image is compared per eye as a
/// top-bottom ODS pair, any image as full equirect panoramas.
pub fn compare<S: Samples>(reference: &S, test: &S) -> Result<CompareReport, CompareError> {
    let (width, height) = reference.size();
    compare_named(
        reference,
        test,
        &ImageLayout::from_shape(width, height),
        "images",
    )
}

/// [`compare`] of images laid out as `layout` says (its eyes' rows must lie in the images),
/// naming the inputs `what` in errors. Latitude bands and the seam are measured only in
/// panoramas.
pub fn compare_named<S: Samples>(
    reference: &S,
    test: &S,
    layout: &ImageLayout,
    what: &str,
) -> Result<CompareReport, CompareError> {
    check_sizes(reference, test, what)?;
    let (width, height) = reference.size();
    let panorama = layout.is_panorama();
    Ok(CompareReport {
        width,
        height,
        layout: layout.name().to_owned(),
        projection: layout.projection.map(|p| p.to_string()),
        eyes: layout
            .eyes
            .iter()
            .map(|eye| {
                let mut regions = RegionsAccumulator::new(panorama);
                regions.add_eye(reference, test, eye);
                let r = regions.finish();
                EyeReport {
                    eye: eye.name.to_owned(),
                    width,
                    height: eye.height,
                    all: r.all,
                    latitude_bands: r.latitude_bands,
                    seam_columns_each_side: r.seam_columns_each_side,
                    seam: r.seam,
                }
            })
            .collect(),
    })
}

/// Statistics over a set of eyes: all their pixels and, in full equirect panoramas, each 10°
/// latitude band and the seam.
#[derive(Debug, Clone, PartialEq)]
pub struct Regions {
    /// Every pixel.
    pub all: RegionStats,
    /// 18 bands of 10° latitude, top (+90..+80) first; none outside panoramas.
    pub latitude_bands: Vec<RegionStats>,
    /// Columns on each side of the seam (longitude ±180°) in `seam`; 0 without a seam.
    pub seam_columns_each_side: u32,
    /// The seam columns (both edges together); only in panoramas.
    pub seam: Option<RegionStats>,
}

/// Compares pairs of (reference, test) eye images, each a whole image, and sums their
/// statistics: the measure of a mono render or of both eyes of a stereo pair together.
/// Latitude bands and the seam are measured when the eyes are full equirect `panorama`s (in
/// other projections rows are not latitudes).
pub fn compare_eyes<S: Samples>(
    pairs: &[(&S, &S)],
    panorama: bool,
) -> Result<Regions, CompareError> {
    let mut regions = RegionsAccumulator::new(panorama);
    for &(reference, test) in pairs {
        check_sizes(reference, test, "eyes")?;
        let (_, height) = reference.size();
        let eye = EyeRows {
            name: "mono",
            first_row: 0,
            height,
        };
        regions.add_eye(reference, test, &eye);
    }
    Ok(regions.finish())
}

/// Running sums of [`Regions`], fed one eye at a time.
struct RegionsAccumulator {
    all: RegionAccumulator,
    /// Empty outside panoramas.
    bands: Vec<RegionAccumulator>,
    /// `None` outside panoramas.
    seam: Option<RegionAccumulator>,
    seam_columns: u32,
}

impl RegionsAccumulator {
    /// Sums over whole eyes, and over bands and seam when the eyes are `panorama`s.
    fn new(panorama: bool) -> Self {
        let bands = if panorama { LATITUDE_BANDS } else { 0 };
        RegionsAccumulator {
            all: RegionAccumulator::default(),
            bands: (0..bands).map(|_| RegionAccumulator::default()).collect(),
            seam: panorama.then(RegionAccumulator::default),
            seam_columns: 0,
        }
    }

    /// Adds rows `eye` of `reference` and `test` (same size, checked by the caller).
    fn add_eye<S: Samples>(&mut self, reference: &S, test: &S, eye: &EyeRows) {
        let (width, _) = reference.size();
        let w = width as usize;
        let h = eye.height as usize;
        let base = eye.first_row as usize * w;
        let ref_hit: Vec<bool> = (base..base + w * h).map(|k| reference.hit(k)).collect();
        let test_hit: Vec<bool> = (base..base + w * h).map(|k| test.hit(k)).collect();
        let silhouette = silhouette_errors(&ref_hit, &test_hit, w, h);
        if self.seam.is_some() {
            self.seam_columns = seam_columns(width);
        }
        let seam = self.seam_columns as usize;
        for j in 0..h {
            let mut band = self.bands.get_mut(latitude_band(j as u32, eye.height));
            for i in 0..w {
                let local = j * w + i;
                let k = base + local;
                let both = ref_hit[local] && test_hit[local];
                let e = PixelErrors {
                    ref_hit: ref_hit[local],
                    test_hit: test_hit[local],
                    silhouette: silhouette[local],
                    depth_relative: both
                        .then(|| depth_relative_error(reference.depth(k), test.depth(k)))
                        .flatten(),
                    color_squared: both
                        .then(|| color_squared_error(reference.srgb(k), test.srgb(k))),
                };
                self.all.add(&e);
                if let Some(band) = band.as_deref_mut() {
                    band.add(&e);
                }
                if let Some(s) = self.seam.as_mut()
                    && (i < seam || i >= w - seam)
                {
                    s.add(&e);
                }
            }
        }
    }

    fn finish(self) -> Regions {
        Regions {
            all: self.all.finish("all".to_owned()),
            latitude_bands: self
                .bands
                .into_iter()
                .enumerate()
                .map(|(b, acc)| acc.finish(band_name(b)))
                .collect(),
            seam_columns_each_side: self.seam_columns,
            seam: self.seam.map(|s| s.finish("seam".to_owned())),
        }
    }
}
