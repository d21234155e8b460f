//! Per-pixel errors and their summary over a region of pixels.

use serde::Serialize;

use crate::stats::percentile;

/// Relative depth error `|z_t - z_r| / z_r`, where both depths are finite and `z_r > 0`.
pub fn depth_relative_error(z_ref: f32, z_test: f32) -> Option<f64> {
    let (r, t) = (z_ref as f64, z_test as f64);
    (r.is_finite() && t.is_finite() && r > 0.0).then(|| (t - r).abs() / r)
}

/// Sum over R, G, B of the squared difference of two sRGB-encoded colours (channels in
/// [0, 1], as [`super::Samples::srgb`] gives them).
pub fn color_squared_error(reference: [f64; 3], test: [f64; 3]) -> f64 {
    (0..3).map(|k| (reference[k] - test[k]).powi(2)).sum()
}

/// What one pixel contributes to the statistics.
#[derive(Debug, Clone, Copy)]
pub struct PixelErrors {
    /// The reference hit this pixel.
    pub ref_hit: bool,
    /// The test hit this pixel.
    pub test_hit: bool,
    /// Silhouette error in pixels (coverage mismatches only, see `silhouette`).
    pub silhouette: Option<f64>,
    /// Relative depth error (pixels both hit, with valid depths).
    pub depth_relative: Option<f64>,
    /// Squared sRGB colour error summed over channels (pixels both hit).
    pub color_squared: Option<f64>,
}

/// Relative depth error percentiles over the pixels both images hit with valid depth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DepthErrorStats {
    /// Pixels measured.
    pub pixels: u64,
    /// Median (nearest rank).
    pub p50: f64,
    /// 99th percentile (nearest rank).
    pub p99: f64,
    /// Largest.
    pub max: f64,
}

/// Error statistics over one region (a whole eye, a latitude band, the seam columns).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionStats {
    /// Region name: `all`, a band like `+90..+80`, or `seam`.
    pub region: String,
    /// Pixels in the region.
    pub pixels: u64,
    /// Pixels the reference hits.
    pub ref_hits: u64,
    /// Pixels the test hits.
    pub test_hits: u64,
    /// Pixels only the reference hits.
    pub only_ref: u64,
    /// Pixels only the test hits.
    pub only_test: u64,
    /// Pixels both hit whose colours differ.
    pub color_differs: u64,
    /// Coverage mismatches: `only_ref + only_test`.
    pub mismatch: u64,
    /// `mismatch` as a percentage of the region's pixels.
    pub mismatch_percent: f64,
    /// Coverage intersection over union; 1 when neither image hits anything here.
    pub iou: f64,
    /// Mean silhouette error of the measured mismatches, pixels (0 when there are none).
    pub silhouette_mean_px: f64,
    /// Largest silhouette error, pixels (0 when there are none).
    pub silhouette_max_px: f64,
    /// Relative depth error; `None` when no pixel here has valid depth in both.
    pub depth_relative: Option<DepthErrorStats>,
    /// Root-mean-square sRGB colour error (0..1 scale) where both hit; `None` when none do.
    pub color_rmse: Option<f64>,
    /// Colour PSNR in dB (peak 1, sRGB-encoded) where both hit; `None` when none do or the
    /// colours are identical (infinite PSNR; then `color_rmse` is 0).
    pub color_psnr_db: Option<f64>,
}

impl RegionStats {
    /// Pixels both images hit.
    pub fn both_hits(&self) -> u64 {
        self.ref_hits - self.only_ref
    }
}

/// Running sums for one region.
#[derive(Debug, Default)]
pub struct RegionAccumulator {
    pixels: u64,
    ref_hits: u64,
    test_hits: u64,
    only_ref: u64,
    only_test: u64,
    color_differs: u64,
    silhouette_count: u64,
    silhouette_sum: f64,
    silhouette_max: f64,
    depth: Vec<f64>,
    color_sum: f64,
    color_pixels: u64,
}

impl RegionAccumulator {
    /// Adds one pixel.
    pub fn add(&mut self, e: &PixelErrors) {
        self.pixels += 1;
        self.ref_hits += e.ref_hit as u64;
        self.test_hits += e.test_hit as u64;
        self.only_ref += (e.ref_hit && !e.test_hit) as u64;
        self.only_test += (!e.ref_hit && e.test_hit) as u64;
        if let Some(s) = e.silhouette {
            self.silhouette_count += 1;
            self.silhouette_sum += s;
            self.silhouette_max = self.silhouette_max.max(s);
        }
        if let Some(d) = e.depth_relative {
            self.depth.push(d);
        }
        if let Some(c) = e.color_squared {
            self.color_sum += c;
            self.color_pixels += 1;
            self.color_differs += (c > 0.0) as u64;
        }
    }

    /// The statistics, under `region`'s name.
    pub fn finish(mut self, region: String) -> RegionStats {
        let mismatch = self.only_ref + self.only_test;
        let both = self.ref_hits - self.only_ref;
        let union = both + mismatch;
        self.depth.sort_unstable_by(f64::total_cmp);
        let depth_relative = self.depth.last().map(|&max| DepthErrorStats {
            pixels: self.depth.len() as u64,
            p50: percentile(&self.depth, 0.5).unwrap_or(max),
            p99: percentile(&self.depth, 0.99).unwrap_or(max),
            max,
        });
        let mse = (self.color_pixels > 0).then(|| self.color_sum / (3 * self.color_pixels) as f64);
        RegionStats {
            region,
            pixels: self.pixels,
            ref_hits: self.ref_hits,
            test_hits: self.test_hits,
            only_ref: self.only_ref,
            only_test: self.only_test,
            color_differs: self.color_differs,
            mismatch,
            mismatch_percent: if self.pixels > 0 {
                100.0 * mismatch as f64 / self.pixels as f64
            } else {
                0.0
            },
            iou: if union > 0 {
                both as f64 / union as f64
            } else {
                1.0
            },
            silhouette_mean_px: if self.silhouette_count > 0 {
                self.silhouette_sum / self.silhouette_count as f64
            } else {
                0.0
            },
            silhouette_max_px: self.silhouette_max,
            depth_relative,
            color_rmse: mse.map(f64::sqrt),
            color_psnr_db: mse.filter(|&m| m > 0.0).map(|m| -10.0 * m.log10()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psnr_of_known_error() {
        let mut acc = RegionAccumulator::default();
        // One pixel, every channel off by 0.1 in sRGB: MSE 0.01, PSNR 20 dB.
        acc.add(&PixelErrors {
            ref_hit: true,
            test_hit: true,
            silhouette: None,
            depth_relative: Some(0.0),
            color_squared: Some(3.0 * 0.01),
        });
        let s = acc.finish("all".into());
        assert!((s.color_psnr_db.unwrap() - 20.0).abs() < 1e-9);
        assert_eq!(s.iou, 1.0);
        assert_eq!(s.color_differs, 1);
    }
}
