//! Accuracy of a render against the ray-traced reference, in the terms the benchmark tables
//! use: coverage mismatch (overall and per 10° latitude band), IoU, relative depth error
//! percentiles where both hit, unlit colour mismatch where both hit, and PSNR.
//!
//! The definitions are those of [`crate::compare`] (hit = covered pixel, nearest-rank
//! percentiles, 10° bands by pixel-centre latitude); this works on the in-memory 8-bit frames
//! so it can also tell whether the unlit colour is bit-identical where both hit.

use crate::frame::{Frame, Rendered};
use crate::projection::Equirect;

use super::report::{Accuracy, BandAccuracy, RegionCount};

/// Latitude bands of [`Accuracy::bands`]: 18 bands of 10°.
pub const BAND_COUNT: usize = 18;

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

/// Band of the latitude of row `j` in an image `height` rows high.
fn band_of_row(height: u32, j: u32) -> usize {
    let (_, phi) = Equirect {
        width: 2 * height,
        height,
    }
    .pixel_angles(0, j);
    (((phi.to_degrees() + 90.0) / 10.0).floor() as usize).min(BAND_COUNT - 1)
}

/// Compares `test` against `reference` over all eyes.
pub fn measure(reference: &Rendered, test: &Rendered) -> Result<Accuracy, ShapeMismatch> {
    let (rf, tf) = (reference.frames(), test.frames());
    let same = rf.len() == tf.len()
        && rf
            .iter()
            .zip(&tf)
            .all(|(a, b)| a.width == b.width && a.height == b.height);
    if !same {
        return Err(ShapeMismatch {
            reference: shape(reference),
            test: shape(test),
        });
    }
    let mut acc = Tally::default();
    for (r, t) in rf.iter().zip(&tf) {
        acc.add(r, t);
    }
    Ok(acc.finish())
}

#[derive(Default)]
struct Tally {
    pixels: u64,
    either: u64,
    both: u64,
    mismatched: u64,
    color_differs: u64,
    squared_error: f64,
    depth_rel: Vec<f32>,
    band_pixels: [u64; BAND_COUNT],
    band_mismatched: [u64; BAND_COUNT],
    seam: RegionCount,
}

impl Tally {
    fn add(&mut self, r: &Frame, t: &Frame) {
        let seam_cols = crate::compare::eyes::seam_columns(r.width);
        for j in 0..r.height {
            let band = band_of_row(r.height, j);
            for i in 0..r.width {
                let k = r.index(i, j);
                let (rc, tc) = (r.color[k], t.color[k]);
                let (rh, th) = (rc[3] != 0, tc[3] != 0);
                if i < seam_cols || i >= r.width - seam_cols {
                    self.seam.pixels += 1;
                    self.seam.mismatched += u64::from(rh != th);
                }
                self.pixels += 1;
                self.band_pixels[band] += 1;
                self.squared_error += (0..3)
                    .map(|c| (rc[c] as f64 - tc[c] as f64).powi(2))
                    .sum::<f64>();
                if rh || th {
                    self.either += 1;
                }
                if rh != th {
                    self.mismatched += 1;
                    self.band_mismatched[band] += 1;
                } else if rh {
                    self.both += 1;
                    if rc[..3] != tc[..3] {
                        self.color_differs += 1;
                    }
                    let (dr, dt) = (r.depth[k], t.depth[k]);
                    self.depth_rel.push(((dt - dr).abs() / dr).max(0.0));
                }
            }
        }
    }

    fn finish(mut self) -> Accuracy {
        let frac = |n: u64, d: u64| if d == 0 { 0.0 } else { n as f64 / d as f64 };
        let n = self.depth_rel.len();
        self.depth_rel.sort_by(f32::total_cmp);
        let quantile = |q: f64| -> f64 {
            if n == 0 {
                0.0
            } else {
                // Nearest rank, as `compare` defines its percentiles.
                let rank = (q * n as f64).ceil() as usize;
                self.depth_rel[rank.clamp(1, n) - 1] as f64
            }
        };
        let mse = self.squared_error / (3.0 * self.pixels.max(1) as f64);
        Accuracy {
            coverage_mismatch: frac(self.mismatched, self.pixels),
            iou: if self.either == 0 {
                1.0
            } else {
                self.both as f64 / self.either as f64
            },
            depth_rel_p50: quantile(0.5),
            depth_rel_p99: quantile(0.99),
            depth_rel_max: quantile(1.0),
            color_mismatch: frac(self.color_differs, self.both),
            psnr_db: (mse > 0.0).then(|| 10.0 * (255.0f64 * 255.0 / mse).log10()),
            bands: (0..BAND_COUNT)
                .map(|b| BandAccuracy {
                    lat_lo_deg: -90.0 + 10.0 * b as f64,
                    lat_hi_deg: -80.0 + 10.0 * b as f64,
                    pixels: self.band_pixels[b],
                    mismatched: self.band_mismatched[b],
                })
                .collect(),
            seam: self.seam,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let a = measure(&Rendered::Mono(r), &Rendered::Mono(t)).unwrap();
        assert_eq!(a.coverage_mismatch, 2.0 / 32.0);
        assert!((a.iou - 1.0 / 3.0).abs() < 1e-12);
        assert!((a.depth_rel_max - 0.1).abs() < 1e-6);
        assert_eq!(a.color_mismatch, 1.0);
        // Row 0 is the band 67.5° → [60, 70); row 3 is −67.5° → [−70, −60).
        assert_eq!(a.bands[15].mismatched, 1);
        assert_eq!(a.bands[2].mismatched, 1);
        assert_eq!(a.bands.iter().map(|b| b.pixels).sum::<u64>(), 32);
        // Width 8: one seam column each side, 8 pixels; (0, 0) is in it.
        assert_eq!(
            a.seam,
            RegionCount {
                pixels: 8,
                mismatched: 1
            }
        );
    }

    #[test]
    fn identical_renders_are_exact() {
        let r = Rendered::Mono(frame_with(&[(3, 2, 7.0, [5, 6, 7])]));
        let a = measure(&r, &r.clone()).unwrap();
        assert_eq!(a.coverage_mismatch, 0.0);
        assert_eq!(a.iou, 1.0);
        assert_eq!(a.depth_rel_p99, 0.0);
        assert_eq!(a.psnr_db, None);
    }

    #[test]
    fn different_shapes_are_an_error() {
        let a = Rendered::Mono(Frame::new(8, 4));
        let b = Rendered::Mono(Frame::new(16, 8));
        assert!(measure(&a, &b).is_err());
    }
}
