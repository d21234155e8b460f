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
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::CompareError;
use super::measure::check_sizes;
use super::stats::depth_relative_error;
use crate::font::{FONT, register_font};
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
    /// Spacing unit in pixels (grows with the image width).
    pub scale: u32,
    /// Text size in pixels.
    pub text_size: u32,
    /// Top-left corners of the ref-only, test-only and no-depth swatches.
    pub swatches: [(u32, u32); 3],
    /// Side of a swatch in pixels.
    pub swatch_size: u32,
    /// First and last column of the ramp bar.
    pub ramp_x: (u32, u32),
    /// First row of the ramp bar; the bar is `swatch_size` rows tall.
    pub ramp_y: u32,
}

const SWATCH_LABELS: [&str; 3] = ["ref only", "test only", "no depth"];
const RAMP_LABEL: &str = "depth error";

/// The label of the tick at relative depth error 10^`exponent`.
fn decade_label(exponent: i32) -> String {
    format!("1e{exponent}")
}

/// Width of `text` at `size` pixels in the legend font.
fn text_width(text: &str, size: u32) -> u32 {
    register_font();
    (FONT, f64::from(size))
        .into_font()
        .box_size(text)
        // Without the font nothing is drawn; an average glyph width keeps the layout sane.
        .map_or(size * 3 / 5 * text.chars().count() as u32, |(w, _)| w)
}

impl LegendLayout {
    /// The legend layout for an image `width x height`.
    pub fn new(width: u32, height: u32) -> LegendLayout {
        let u = (width / 512).max(1);
        let text_size = 12 * u;
        let swatch_size = 10 * u;
        let y = height + 3 * u;
        let mut x = 3 * u;
        let swatches = SWATCH_LABELS.map(|label| {
            let at = (x, y);
            x += swatch_size + 3 * u + text_width(label, text_size) + 8 * u;
            at
        });
        x += text_width(RAMP_LABEL, text_size) + 4 * u;
        // The ramp takes the rest of the width, keeping room for half of its last label.
        let last_label = text_width(&decade_label(RAMP_MAX_LOG10), text_size);
        let end = width.saturating_sub(last_label / 2 + 2 * u).max(x + 10 * u);
        LegendLayout {
            top: height,
            // Margin, swatch row, tick, gap, tick labels, margin.
            height: 3 * u + swatch_size + 4 * u + text_size + 3 * u,
            scale: u,
            text_size,
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
    let strip = legend_strip(w, &legend);
    for (px, rgb) in img
        .pixels_mut()
        .skip(reference.len())
        .zip(strip.chunks_exact(3))
    {
        *px = Rgba([rgb[0], rgb[1], rgb[2], 255]);
    }
    Ok(img)
}

/// The legend strip, `width x l.height` RGB bytes, drawn with plotters.
fn legend_strip(width: u32, l: &LegendLayout) -> Vec<u8> {
    let mut buf = vec![0u8; width as usize * l.height as usize * 3];
    {
        let area = BitMapBackend::with_buffer(&mut buf, (width, l.height)).into_drawing_area();
        // Drawing into memory fails only without the embedded font; the legend then lacks its
        // text, which is no reason to lose the heatmap.
        let _ = draw_legend(&area, l);
    }
    buf
}

type Strip<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// Drawing errors as text (they cannot be matched on, only shown).
type DrawResult = Result<(), String>;

/// Fills columns `x..x + w` of rows `y..y + h` (strip coordinates) with `color`.
fn fill(area: &Strip, x: u32, y: u32, w: u32, h: u32, color: Rgba<u8>) -> DrawResult {
    let [r, g, b, _] = color.0;
    let (x, y, w, h) = (x as i32, y as i32, w as i32, h as i32);
    // The bitmap backend fills a rectangle up to, not including, its second corner.
    area.draw(&Rectangle::new(
        [(x, y), (x + w, y + h)],
        RGBColor(r, g, b).filled(),
    ))
    .map_err(|e| e.to_string())
}

fn draw_legend(area: &Strip, l: &LegendLayout) -> DrawResult {
    register_font();
    let u = l.scale;
    let s = l.swatch_size;
    let ink = RGBColor(INK.0[0], INK.0[1], INK.0[2]);
    let font = (FONT, f64::from(l.text_size)).into_font();
    let beside = font.color(&ink).pos(Pos::new(HPos::Left, VPos::Center));
    let below = font.color(&ink).pos(Pos::new(HPos::Center, VPos::Top));
    let local = |y: u32| y - l.top;
    for ((x, y), (label, color)) in l
        .swatches
        .iter()
        .zip(SWATCH_LABELS.iter().zip([REF_ONLY, TEST_ONLY, NO_DEPTH]))
    {
        fill(area, *x, local(*y), s, s, color)?;
        let at = ((x + s + 3 * u) as i32, (local(*y) + s / 2) as i32);
        area.draw(&Text::new(*label, at, &beside))
            .map_err(|e| e.to_string())?;
    }
    let (x0, x1) = l.ramp_x;
    let ramp_y = local(l.ramp_y);
    let label_x = x0 - 4 * u - text_width(RAMP_LABEL, l.text_size);
    let at = (label_x as i32, (ramp_y + s / 2) as i32);
    area.draw(&Text::new(RAMP_LABEL, at, &beside))
        .map_err(|e| e.to_string())?;
    let span = (x1 - x0).max(1) as f64;
    for x in x0..=x1 {
        fill(area, x, ramp_y, 1, s, ramp((x - x0) as f64 / span))?;
    }
    let decades = RAMP_MAX_LOG10 - RAMP_MIN_LOG10;
    for d in 0..=decades {
        let x = x0 + ((x1 - x0) as f64 * d as f64 / decades as f64).round() as u32;
        fill(area, x, ramp_y + s, u, 3 * u, INK)?;
        let at = ((x + u / 2) as i32, (ramp_y + s + 4 * u) as i32);
        let label = decade_label(RAMP_MIN_LOG10 + d);
        area.draw(&Text::new(label, at, &below))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}
