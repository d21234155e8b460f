//! The comparison report: per eye, whole-eye, per-latitude-band and seam statistics.

use std::fmt;

use serde::Serialize;

use super::stats::RegionStats;

/// Statistics of one eye.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EyeReport {
    /// `mono`, `left` or `right`.
    pub eye: String,
    /// Eye width in pixels.
    pub width: u32,
    /// Eye height in pixels.
    pub height: u32,
    /// The whole eye.
    pub all: RegionStats,
    /// 18 bands of 10° latitude, top (+90..+80) first; none unless the eye is a full
    /// equirect panorama.
    pub latitude_bands: Vec<RegionStats>,
    /// Columns on each side of the seam (longitude ±180°) in `seam`; 0 without a seam.
    pub seam_columns_each_side: u32,
    /// The seam columns (both edges together); only in a full equirect panorama.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seam: Option<RegionStats>,
}

/// Result of comparing a test image against a reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareReport {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `mono` or `top-bottom` (left eye on top).
    pub layout: String,
    /// The projection, as `--projection` writes it, when the files say it; `None` when the
    /// layout was guessed from the image's shape (a square image a top-bottom pair, every
    /// image a full equirect).
    pub projection: Option<String>,
    /// One report per eye, left first.
    pub eyes: Vec<EyeReport>,
}

impl CompareReport {
    /// True when coverage, depth and colour agree exactly in every eye.
    pub fn is_identical(&self) -> bool {
        self.eyes.iter().all(|e| {
            e.all.mismatch == 0
                && e.all.depth_relative.as_ref().is_none_or(|d| d.max == 0.0)
                && e.all.color_rmse.is_none_or(|c| c == 0.0)
        })
    }
}

/// Formats an optional PSNR: identical colours show as `inf`.
fn psnr(s: &RegionStats) -> String {
    match (s.color_psnr_db, s.color_rmse) {
        (Some(p), _) => format!("{p:.1} dB"),
        (None, Some(_)) => "inf dB".to_owned(),
        (None, None) => "n/a".to_owned(),
    }
}

impl fmt::Display for RegionStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "coverage mismatch {} px ({:.4}%: {} ref-only, {} test-only), IoU {:.6}",
            self.mismatch, self.mismatch_percent, self.only_ref, self.only_test, self.iou
        )?;
        if self.mismatch > 0 {
            write!(
                f,
                "; silhouette error mean {:.2} px, max {:.2} px",
                self.silhouette_mean_px, self.silhouette_max_px
            )?;
        }
        match &self.depth_relative {
            Some(d) => write!(
                f,
                "; depth rel. error p50 {:.2e} p99 {:.2e} max {:.2e} ({} px)",
                d.p50, d.p99, d.max, d.pixels
            )?,
            None => write!(f, "; no depth to compare")?,
        }
        write!(f, "; colour PSNR {}", psnr(self))
    }
}

impl fmt::Display for CompareReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.projection {
            Some(p) => writeln!(
                f,
                "{}x{} {p} {} image",
                self.width, self.height, self.layout
            )?,
            None => writeln!(
                f,
                "{}x{} {} image (no description in the files: layout guessed from the shape)",
                self.width, self.height, self.layout
            )?,
        }
        for e in &self.eyes {
            writeln!(f, "{:>5}: {}", e.eye, e.all)?;
            let worst = e
                .latitude_bands
                .iter()
                .rev() // max_by keeps the last of equals: report the topmost band
                .max_by(|a, b| a.mismatch_percent.total_cmp(&b.mismatch_percent));
            if let Some(w) = worst.filter(|w| w.mismatch > 0) {
                writeln!(
                    f,
                    "       worst latitude band {}: {} px mismatch ({:.4}%)",
                    w.region, w.mismatch, w.mismatch_percent
                )?;
            }
            let Some(seam) = &e.seam else { continue };
            let depth = seam
                .depth_relative
                .as_ref()
                .map(|d| format!(", depth rel. error max {:.2e}", d.max))
                .unwrap_or_default();
            writeln!(
                f,
                "       seam ({} columns each side): {} px mismatch ({:.4}%){depth}",
                e.seam_columns_each_side, seam.mismatch, seam.mismatch_percent
            )?;
        }
        Ok(())
    }
}
