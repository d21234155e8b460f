//! The error heatmap: one picture of where and how much the test differs.
//!
//! Above the legend strip, each pixel of the image (both eyes of a top-bottom pair) is:
//! black where neither image hits, [`REF_ONLY`] red where only the reference hits,
//! [`TEST_ONLY`] blue where only the test hits, and, where both hit, the relative depth error
//! on a log ramp from 1e-6 (dark green) through green and yellow to 1e-1 and above (white);
//! [`NO_DEPTH`] grey where both hit but depth cannot be compared (a PNG input). Below the
//! image a legend strip shows the three swatches and the ramp with a tick and label per
//! decade.

use image::{Rgba, RgbaImage};

use super::CompareError;
use super::font::{draw_text, fill_rect, text_width};
use super::measure::check_sizes;
use super::stats::depth_relative_error;
use crate::output::LinearImage;

/// Pixels only the reference hits.
pub const REF_ONLY: Rgba<u8> = Rgba([255, 40, 40, 255]);
/// Pixels only the test hits.
pub const TEST_ONLY: Rgba<u8> = Rgba([40, 120, 255, 255]);
/// Pixels both hit without comparable depth.
pub const NO_DEPTH: Rgba<u8> = Rgba([128, 128, 128, 255]);
/// Pixels neither hits, and the legend background.
pub const BACKGROUND: Rgba<u8> = Rgba([0, 0, 0, 255]);
/// Legend text and ticks.
const INK: Rgba<u8> = Rgba([255, 255, 255, 255]);

/// The ramp spans relative depth errors 10^RAMP_MIN ..= 10^RAMP_MAX.
pub const RAMP_MIN_LOG10: i32 = -6;
/// Upper end of the ramp (log10 of the relative depth error).
pub const RAMP_MAX_LOG10: i32 = -1;

/// Ramp stops: dark green, green, yellow, white.
const STOPS: [[f64; 3]; 4] = [
    [0.0, 60.0, 0.0],
    [0.0, 200.0, 0.0],
    [255.0, 230.0, 0.0],
    [255.0, 255.0, 255.0],
];

/// Ramp colour at `t` in [0, 1] (clamped).
pub fn ramp(t: f64) -> Rgba<u8> {
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (t as usize).min(STOPS.len() - 2);
    let f = t - k as f64;
    let c: [u8; 3] =
        std::array::from_fn(|i| (STOPS[k][i] + f * (STOPS[k + 1][i] - STOPS[k][i])).round() as u8);
    Rgba([c[0], c[1], c[2], 255])
}

/// Ramp colour of a relative depth error (log scale; 0 maps to the bottom).
pub fn depth_error_color(relative: f64) -> Rgba<u8> {
    let lo = RAMP_MIN_LOG10 as f64;
    let hi = RAMP_MAX_LOG10 as f64;
    let t = if relative > 0.0 {
        (relative.log10() - lo) / (hi - lo)
    } else {
        0.0
    };
    ramp(t)
}

/// Where the legend's parts lie in a heatmap of an image `width x height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LegendLayout {
    /// First row of the legend strip (= the image height).
    pub top: u32,
    /// Legend strip height in pixels.
    pub height: u32,
    /// Font and spacing unit in pixels (grows with the image width).
    pub scale: u32,
    /// Top-left corners of the ref-only, test-only and no-depth swatches.
    pub swatches: [(u32, u32); 3],
    /// Side of a swatch in pixels.
    pub swatch_size: u32,
    /// First and last column of the ramp bar.
    pub ramp_x: (u32, u32),
    /// First row of the ramp bar; the bar is `swatch_size` rows tall.
    pub ramp_y: u32,
}

const SWATCH_LABELS: [&str; 3] = ["REF ONLY", "TEST ONLY", "NO DEPTH"];
const RAMP_LABEL: &str = "DEPTH ERR";

impl LegendLayout {
    /// The legend layout for an image `width x height`.
    pub fn new(width: u32, height: u32) -> LegendLayout {
        let u = (width / 512).max(1);
        let swatch_size = 6 * u;
        let y = height + 2 * u;
        let mut x = 2 * u;
        let swatches = SWATCH_LABELS.map(|label| {
            let at = (x, y);
            x += swatch_size + 2 * u + text_width(label, u) + 3 * u;
            at
        });
        x += 3 * u + text_width(RAMP_LABEL, u) + u;
        // The ramp takes the rest of the width, keeping room for half of its last label.
        let end = width.saturating_sub(10 * u).max(x + 10 * u);
        LegendLayout {
            top: height,
            height: 18 * u,
            scale: u,
            swatches,
            swatch_size,
            ramp_x: (x, end),
            ramp_y: y,
        }
    }
}

/// The heatmap of `test` against `reference` (module docs), `W x (H + legend height)`.
pub fn heatmap(reference: &LinearImage, test: &LinearImage) -> Result<RgbaImage, CompareError> {
    check_sizes(reference, test, "images")?;
    let (w, h) = (reference.width, reference.height);
    let legend = LegendLayout::new(w, h);
    let mut img = RgbaImage::from_pixel(w, h + legend.height, BACKGROUND);
    for (k, px) in img.pixels_mut().take(reference.len()).enumerate() {
        *px = match (reference.hit(k), test.hit(k)) {
            (false, false) => BACKGROUND,
            (true, false) => REF_ONLY,
            (false, true) => TEST_ONLY,
            (true, true) => match depth_relative_error(reference.depth[k], test.depth[k]) {
                Some(e) => depth_error_color(e),
                None => NO_DEPTH,
            },
        };
    }
    draw_legend(&mut img, &legend);
    Ok(img)
}

fn draw_legend(img: &mut RgbaImage, l: &LegendLayout) {
    let u = l.scale;
    let s = l.swatch_size;
    for ((x, y), (label, color)) in l
        .swatches
        .iter()
        .zip(SWATCH_LABELS.iter().zip([REF_ONLY, TEST_ONLY, NO_DEPTH]))
    {
        fill_rect(img, *x, *y, s, s, color);
        draw_text(img, x + s + 2 * u, y + u / 2, u, label, INK);
    }
    let (x0, x1) = l.ramp_x;
    draw_text(
        img,
        x0 - text_width(RAMP_LABEL, u) - u,
        l.ramp_y + u / 2,
        u,
        RAMP_LABEL,
        INK,
    );
    let span = (x1 - x0).max(1) as f64;
    for x in x0..=x1 {
        fill_rect(img, x, l.ramp_y, 1, s, ramp((x - x0) as f64 / span));
    }
    let decades = RAMP_MAX_LOG10 - RAMP_MIN_LOG10;
    for d in 0..=decades {
        let x = x0 + ((x1 - x0) as f64 * d as f64 / decades as f64).round() as u32;
        fill_rect(img, x, l.ramp_y + s, u, 2 * u, INK);
        let label = format!("1E{}", RAMP_MIN_LOG10 + d);
        let half = text_width(&label, u) / 2;
        draw_text(
            img,
            x.saturating_sub(half),
            l.ramp_y + s + 3 * u,
            u,
            &label,
            INK,
        );
    }
}
