//! Keeping the rate while moving: the JPEG quality, and with `--live-scale auto` the width,
//! of moving frames follow how long the last frames took to render and to encode.

use std::str::FromStr;

/// Whether moving frames may render narrower than the served width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LiveScale {
    /// The width halves (down to a quarter) while rendering takes longer than the frame
    /// budget, and rises again when it is quick.
    #[default]
    Auto,
    /// Every frame at the served width.
    Full,
}

impl FromStr for LiveScale {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(LiveScale::Auto),
            "1" => Ok(LiveScale::Full),
            _ => Err(format!("expected `auto` or `1`, got `{s}`")),
        }
    }
}

/// Lowest quality of a moving frame.
const MIN_QUALITY: u8 = 50;
/// Highest (and first) quality of a moving frame.
const MAX_QUALITY: u8 = 80;
/// Smallest share of the served width a moving frame renders at (auto scale).
const MIN_SHARE: u32 = 4;
/// Narrowest moving frame, pixels per eye.
const MIN_WIDTH: u32 = 128;

/// The settings of the next moving frame, adjusted after each one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pace {
    scale: LiveScale,
    /// Milliseconds a frame may take: one over the target rate.
    budget_ms: f64,
    quality: u8,
    /// The width is the served width divided by this (1, 2 or 4).
    divisor: u32,
}

impl Pace {
    /// Starts at full width and the highest moving quality, aiming at `fps` frames a second.
    pub fn new(scale: LiveScale, fps: f64) -> Self {
        Pace {
            scale,
            budget_ms: 1000.0 / fps,
            quality: MAX_QUALITY,
            divisor: 1,
        }
    }

    /// The JPEG quality of the next moving frame.
    pub fn quality(&self) -> u8 {
        self.quality
    }

    /// The width of the next moving frame for a served width `full` (a multiple of 16 when
    /// narrower, so both eyes keep even sides).
    pub fn width(&self, full: u32) -> u32 {
        if self.divisor == 1 {
            return full;
        }
        (full / self.divisor / 16 * 16).max(MIN_WIDTH.min(full))
    }

    /// Takes in how long the last moving frame rendered and encoded: rendering over the
    /// budget narrows the frames (auto scale), encoding over half of it lowers the quality;
    /// both well within it raise them back, width first.
    pub fn after(&mut self, render_ms: f64, encode_ms: f64) {
        let auto = self.scale == LiveScale::Auto;
        let slow_render = render_ms > self.budget_ms;
        let slow_encode = encode_ms > 0.5 * self.budget_ms;
        if slow_render && auto && self.divisor < MIN_SHARE {
            self.divisor *= 2;
        }
        if slow_encode {
            self.quality = self.quality.saturating_sub(10).max(MIN_QUALITY);
        }
        // A quarter of the budget: doubling the width (four times the pixels) stays within it.
        let quick = render_ms + encode_ms < 0.25 * self.budget_ms;
        if quick && self.divisor > 1 {
            self.divisor /= 2;
        } else if !slow_encode && encode_ms < 0.25 * self.budget_ms {
            self.quality = (self.quality + 5).min(MAX_QUALITY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_renders_narrow_auto_frames_and_quick_ones_widen_them_again() {
        let mut p = Pace::new(LiveScale::Auto, 10.0);
        assert_eq!((p.width(1440), p.quality()), (1440, 80));
        p.after(150.0, 20.0);
        assert_eq!(p.width(1440), 720);
        p.after(120.0, 20.0);
        assert_eq!(p.width(1440), 352, "a quarter, to a multiple of 16");
        p.after(120.0, 20.0);
        assert_eq!(p.width(1440), 352, "no narrower than a quarter");
        p.after(15.0, 5.0);
        assert_eq!(p.width(1440), 720);
        assert_eq!(Pace { divisor: 4, ..p }.width(256), 128, "never under 128");
        let mut full = Pace::new(LiveScale::Full, 10.0);
        full.after(500.0, 20.0);
        assert_eq!(full.width(1440), 1440, "--live-scale 1 keeps the width");
    }

    #[test]
    fn slow_encodes_lower_the_quality_within_its_range() {
        let mut p = Pace::new(LiveScale::Full, 10.0);
        for expected in [70, 60, 50, 50] {
            p.after(40.0, 60.0);
            assert_eq!(p.quality(), expected);
        }
        p.after(40.0, 10.0);
        assert_eq!(p.quality(), 55);
        p.after(40.0, 30.0);
        assert_eq!(
            p.quality(),
            55,
            "between a quarter and half the budget: kept"
        );
        assert_eq!("auto".parse(), Ok(LiveScale::Auto));
        assert_eq!("1".parse(), Ok(LiveScale::Full));
        assert!(
            "0.5"
                .parse::<LiveScale>()
                .unwrap_err()
                .contains("`auto` or `1`")
        );
    }
}
