//! Accuracy of a render against the ray-traced reference, in the terms the benchmark tables
//! use: coverage mismatch (overall, and in full equirect panoramas per 10° latitude band and
//! at the seam), IoU, relative
//! depth error percentiles where both hit, unlit colour mismatch where both hit, and PSNR.
//!
//! Every figure is [`crate::compare`]'s, over all eyes together ([`compare_eyes`]): hit =
//! covered pixel, nearest-rank percentiles, 10° bands by pixel-centre latitude (north first),
//! the seam columns, and the colour PSNR (peak 1, sRGB) over pixels both hit.

use crate::compare::{RegionStats, Regions, compare_eyes};
use crate::frame::Rendered;

use super::report::{Accuracy, BandAccuracy, RegionCount};

/// The reference and test renders have different shapes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot compare renders: reference is {reference}, test is {test}")]
pub struct ShapeMismatch {
    /// Reference shape, e.g. `2 frames of 512x256`.
    pub reference: String,
    /// Test shape.
    pub test: String,
}

fn shape(r: &Rendered) -> String {
    let f = r.frames();
    format!("{} frame(s) of {}x{}", f.len(), f[0].width, f[0].height)
}

/// Compares `test` against `reference` over all eyes; latitude bands and the seam only when
/// the renders are full equirect `panorama`s (in other projections rows are not latitudes).
pub fn measure(
    reference: &Rendered,
    test: &Rendered,
    panorama: bool,
) -> Result<Accuracy, ShapeMismatch> {
    let (rf, tf) = (reference.frames(), test.frames());
    let mismatch = || ShapeMismatch {
        reference: shape(reference),
        test: shape(test),
    };
    if rf.len() != tf.len() {
        return Err(mismatch());
    }
    let pairs: Vec<_> = rf.into_iter().zip(tf).collect();
    let regions = compare_eyes(&pairs, panorama).map_err(|_| mismatch())?;
    Ok(accuracy(&regions))
}

fn count(r: &RegionStats) -> RegionCount {
    RegionCount {
        pixels: r.pixels,
        mismatched: r.mismatch,
    }
}

fn fraction(n: u64, d: u64) -> f64 {
    if d == 0 { 0.0 } else { n as f64 / d as f64 }
}

/// The benchmark's figures from compare's statistics.
fn accuracy(r: &Regions) -> Accuracy {
    let all = &r.all;
    let depth =
        |f: fn(&crate::compare::DepthErrorStats) -> f64| all.depth_relative.as_ref().map_or(0.0, f);
    Accuracy {
        coverage_mismatch: fraction(all.mismatch, all.pixels),
        iou: all.iou,
        depth_rel_p50: depth(|d| d.p50),
        depth_rel_p99: depth(|d| d.p99),
        depth_rel_max: depth(|d| d.max),
        color_mismatch: fraction(all.color_differs, all.both_hits()),
        psnr_db: all.color_psnr_db,
        bands: r
            .latitude_bands
            .iter()
            .enumerate()
            .map(|(b, s)| {
                let top = 90.0 - 10.0 * b as f64;
                BandAccuracy {
                    lat_lo_deg: top - 10.0,
                    lat_hi_deg: top,
                    pixels: s.pixels,
                    mismatched: s.mismatch,
                }
            })
            .collect(),
        seam: r.seam.as_ref().map(count),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Frame;

    fn frame_with(hits: &[(u32, u32, f32, [u8; 3])]) -> Frame {
        let mut f = Frame::new(8, 4);
        for &(i, j, d, c) in hits {
            let k = f.index(i, j);
            f.color[k] = [c[0], c[1], c[2], 255];
            f.depth[k] = d;
        }
        f
    }

    #[test]
    fn counts_mismatch_iou_depth_colour_and_bands() {
        let r = frame_with(&[(0, 0, 2.0, [10, 10, 10]), (1, 1, 4.0, [20, 20, 20])]);
        let t = frame_with(&[(1, 1, 4.4, [20, 20, 21]), (2, 3, 1.0, [1, 1, 1])]);
        let a = measure(&Rendered::Mono(r.clone()), &Rendered::Mono(t.clone()), true).unwrap();
        assert_eq!(a.coverage_mismatch, 2.0 / 32.0);
        assert!((a.iou - 1.0 / 3.0).abs() < 1e-12);
        assert!((a.depth_rel_max - 0.1).abs() < 1e-6);
        assert_eq!(a.color_mismatch, 1.0);
        // Colour PSNR over the one pixel both hit: one channel off by 1/255.
        let psnr = -10.0 * ((1.0f64 / 255.0).powi(2) / 3.0).log10();
        assert!((a.psnr_db.unwrap() - psnr).abs() < 1e-9, "{:?}", a.psnr_db);
        // North first: row 0 is the band 67.5° → [60, 70); row 3 is −67.5° → [−70, −60).
        assert_eq!(a.bands[2].mismatched, 1);
        assert_eq!((a.bands[2].lat_lo_deg, a.bands[2].lat_hi_deg), (60.0, 70.0));
        assert_eq!(a.bands[15].mismatched, 1);
        assert_eq!(
            (a.bands[15].lat_lo_deg, a.bands[15].lat_hi_deg),
            (-70.0, -60.0)
        );
        assert_eq!(a.bands.iter().map(|b| b.pixels).sum::<u64>(), 32);
        // Width 8: one seam column each side, 8 pixels; (0, 0) is in it.
        assert_eq!(
            a.seam,
            Some(RegionCount {
                pixels: 8,
                mismatched: 1
            })
        );
        // Another projection's rows are not latitudes: the same figures, no bands or seam.
        let b = measure(&Rendered::Mono(r), &Rendered::Mono(t), false).unwrap();
        assert!(b.bands.is_empty() && b.seam.is_none());
        assert_eq!((b.coverage_mismatch, b.iou), (a.coverage_mismatch, a.iou));
    }

    #[test]
    fn identical_renders_are_exact() {
        let r = Rendered::Mono(frame_with(&[(3, 2, 7.0, [5, 6, 7])]));
        let a = measure(&r, &r.clone(), true).unwrap();
        assert_eq!(a.coverage_mismatch, 0.0);
        assert_eq!(a.iou, 1.0);
        assert_eq!(a.depth_rel_p99, 0.0);
        assert_eq!(a.psnr_db, None);
    }

    #[test]
    fn different_shapes_are_an_error() {
        let a = Rendered::Mono(Frame::new(8, 4));
        let b = Rendered::Mono(Frame::new(16, 8));
        assert!(measure(&a, &b, true).is_err());
    }
}
