//! One streamed pass over a file's points for `omnicloud info --stats`: histograms, ranges and
//! the actual bounds, in memory that does not grow with the point count.

use super::chunk::{ColorScale, RawRgb};
use super::error::LoadError;
use super::info::asprs_class_name;
use super::{open, usable};
use glam::DVec3;
use indicatif::ProgressBar;
use serde_json::{Value, json};
use std::fmt;
use std::path::Path;

/// Points decoded per read.
const READ_POINTS: usize = 1 << 16;

/// What a full pass over the points found.
#[derive(Debug, Clone, PartialEq)]
pub struct PointStats {
    /// Point records read.
    pub points_read: u64,
    /// Records with a NaN/inf (or absurd) coordinate; left out of the bounds.
    pub nonfinite: u64,
    /// `(min, max)` of the usable points, file coordinates.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Points per classification code (256 entries); `None` without classification.
    pub classes: Option<Vec<u64>>,
    /// Points per return number 0–15; `None` without returns.
    pub return_numbers: Option<[u64; 16]>,
    /// Points per number of returns of their pulse, 0–15; `None` without returns.
    pub numbers_of_returns: Option<[u64; 16]>,
    /// `(min, max)` intensity.
    pub intensity: Option<(u16, u16)>,
    /// `(min, max)` stored colour per channel (8- or 16-bit values as the file holds them).
    pub rgb: Option<([u16; 3], [u16; 3])>,
    /// How colour becomes 8-bit, decided from every point (as loading decides it).
    pub color_scale: Option<ColorScale>,
}

/// Reads every point of `path` once and gathers [`PointStats`]; also returns the usable
/// points whose indices fall in `sample` (`(first, count)` blocks, ascending), for measures
/// that need positions (the point spacing). `progress` counts points read of the declared
/// total.
///
/// # Errors
/// Any [`LoadError`] from opening or reading, e.g. [`LoadError::PointCountExceedsFile`] or
/// [`LoadError::CorruptPoints`] for a truncated file.
pub fn point_stats(
    path: &Path,
    sample: &[(u64, u64)],
    progress: &ProgressBar,
) -> Result<(PointStats, Vec<DVec3>), LoadError> {
    let mut reader = open(path)?;
    let info = reader.info().clone();
    progress.set_length(info.point_count);
    let mut stats = PointStats {
        points_read: 0,
        nonfinite: 0,
        bounds: None,
        classes: None,
        return_numbers: None,
        numbers_of_returns: None,
        intensity: None,
        rgb: None,
        color_scale: None,
    };
    let mut picked = Vec::new();
    let mut color_max = 0u16;
    let mut eight_bit = false;
    while let Some(raw) = reader.next_raw(READ_POINTS)? {
        let first = stats.points_read;
        let n = raw.positions.len() as u64;
        stats.points_read += n;
        progress.inc(n);
        for (i, p) in raw.positions.iter().enumerate() {
            if !usable(*p) {
                stats.nonfinite += 1;
                continue;
            }
            let (lo, hi) = stats.bounds.get_or_insert((*p, *p));
            *lo = lo.min(*p);
            *hi = hi.max(*p);
            let index = first + i as u64;
            if sample.iter().any(|&(s, len)| index >= s && index < s + len) {
                picked.push(*p);
            }
        }
        if let Some(c) = &raw.classification {
            let h = stats.classes.get_or_insert_with(|| vec![0; 256]);
            for &code in c {
                h[usize::from(code)] += 1;
            }
        }
        if let Some(r) = &raw.returns {
            let numbers = stats.return_numbers.get_or_insert([0; 16]);
            for x in r {
                numbers[usize::from(x.number.min(15))] += 1;
            }
            let of = stats.numbers_of_returns.get_or_insert([0; 16]);
            for x in r {
                of[usize::from(x.of.min(15))] += 1;
            }
        }
        if let Some(v) = &raw.intensity {
            for &x in v {
                let (lo, hi) = stats.intensity.get_or_insert((x, x));
                *lo = (*lo).min(x);
                *hi = (*hi).max(x);
            }
        }
        let widen = |range: &mut Option<([u16; 3], [u16; 3])>, c: [u16; 3]| {
            let (lo, hi) = range.get_or_insert((c, c));
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        };
        match &raw.rgb {
            Some(RawRgb::Bits8(v)) => {
                eight_bit = true;
                for c in v {
                    widen(&mut stats.rgb, c.map(u16::from));
                }
            }
            Some(RawRgb::Bits16(v)) => {
                for c in v {
                    color_max = color_max.max(c[0]).max(c[1]).max(c[2]);
                    widen(&mut stats.rgb, *c);
                }
            }
            None => {}
        }
    }
    if stats.rgb.is_some() {
        stats.color_scale = Some(if eight_bit {
            ColorScale::Direct8
        } else {
            ColorScale::detect_16(color_max)
        });
    }
    Ok((stats, picked))
}

/// `1234567` as `1,234,567`.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

impl PointStats {
    /// `(code, count)` of the classes present, ascending.
    pub fn class_counts(&self) -> Vec<(u8, u64)> {
        self.classes.as_ref().map_or_else(Vec::new, |h| {
            (0..=255u8)
                .zip(h.iter().copied())
                .filter(|(_, n)| *n > 0)
                .collect()
        })
    }

    /// The statistics as JSON (the `stats` object of `omnicloud info --json --stats`).
    pub fn to_json(&self) -> Value {
        let xyz = |v: DVec3| json!([v.x, v.y, v.z]);
        let histogram = |h: &Option<[u64; 16]>, key: &str| {
            h.map(|h| {
                (0..16)
                    .filter(|&i| h[i] > 0)
                    .map(|i| json!({ key: i, "count": h[i] }))
                    .collect::<Vec<_>>()
            })
        };
        json!({
            "points_read": self.points_read,
            "nonfinite": self.nonfinite,
            "bounds": self.bounds.map(|(lo, hi)| json!({"min": xyz(lo), "max": xyz(hi)})),
            "classes": self.classes.as_ref().map(|_| self.class_counts().iter().map(|(c, n)| json!({
                "code": c, "name": asprs_class_name(*c), "count": n
            })).collect::<Vec<_>>()),
            "return_numbers": histogram(&self.return_numbers, "number"),
            "numbers_of_returns": histogram(&self.numbers_of_returns, "returns"),
            "intensity": self.intensity.map(|(lo, hi)| json!({"min": lo, "max": hi})),
            "rgb": self.rgb.map(|(lo, hi)| json!({"min": lo, "max": hi})),
            "color_scale": self.color_scale.map(|s| match s {
                ColorScale::Direct8 => "8-bit",
                ColorScale::Low8In16 => "8-bit values in 16-bit fields",
                ColorScale::Full16 => "16-bit",
            }),
        })
    }
}

impl fmt::Display for PointStats {
    /// What `omnicloud info --stats` adds: one item per line, a class per line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "read:          {} points", thousands(self.points_read))?;
        if self.nonfinite > 0 {
            write!(
                f,
                " ({} with NaN/inf coordinates, left out)",
                thousands(self.nonfinite)
            )?;
        }
        if let Some((lo, hi)) = self.bounds {
            write!(
                f,
                "\nactual bounds: x {:.3} .. {:.3}, y {:.3} .. {:.3}, z {:.3} .. {:.3}",
                lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
            )?;
        }
        let total = self.points_read.max(1) as f64;
        for (i, (code, n)) in self.class_counts().into_iter().enumerate() {
            write!(
                f,
                "\n{}{code:>3} {:<28}{:>12} ({:.1}%)",
                if i == 0 {
                    "classes:       "
                } else {
                    "               "
                },
                asprs_class_name(code),
                thousands(n),
                100.0 * n as f64 / total
            )?;
        }
        let line = |h: &[u64; 16], what: &str| {
            (0..16)
                .filter(|&i| h[i] > 0)
                .map(|i| format!("{what}{i}: {}", thousands(h[i])))
                .collect::<Vec<_>>()
                .join(", ")
        };
        if let Some(h) = &self.return_numbers {
            write!(f, "\nreturn number: {}", line(h, ""))?;
        }
        if let Some(h) = &self.numbers_of_returns {
            write!(f, "\nreturns/pulse: {}", line(h, ""))?;
        }
        if let Some((lo, hi)) = self.intensity {
            write!(f, "\nintensity:     {lo} .. {hi}")?;
        }
        if let Some((lo, hi)) = self.rgb {
            write!(
                f,
                "\nrgb:           r {} .. {}, g {} .. {}, b {} .. {}",
                lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
            )?;
        }
        if let Some(scale) = self.color_scale {
            write!(
                f,
                "\ncolour scale:  {}",
                match scale {
                    ColorScale::Direct8 => "8-bit values",
                    ColorScale::Low8In16 =>
                        "0-255 values stored in 16-bit fields (used as they are)",
                    ColorScale::Full16 => "full 0-65535 range (scaled by 1/256)",
                }
            )?;
        }
        Ok(())
    }
}
