//! Eye-dome lighting (EDL): shading from the depth image alone, which makes the shape of
//! unlit, uncoloured scans readable. A pass on a frame's depth and colour, so it gives the same
//! result whichever renderer drew the frame.
//!
//! The formula is Potree's (after Boucheny's thesis and CloudCompare's shader), with the
//! neighbours taken in angle on the sphere instead of in screen pixels. For a covered pixel
//! `p` at distance `d(p)` along its ray and its eight neighbours `q_k`:
//!
//! ```text
//! response(p) = (1/8) · Σ_k max(0, log2 d(p) − log2 d(q_k))     (background q_k skipped)
//! shade(p)    = exp(−300 · strength · response(p))
//! colour(p)   = colour(p) · shade(p)                              (in linear light)
//! ```
//!
//! so a pixel farther than its neighbours, the far side of a depth edge, darkens; a flat
//! depth leaves the colour as it is. Neighbour `q_k` lies at the great-circle angle `ρ` from
//! the pixel's centre direction, toward bearing `2πk/8` (east, north-east, …), where `ρ` is
//! the radius in pixels of the output image times its latitude step `π / height`. Near the
//! poles the east-west neighbours are thus many columns away (a pixel there spans little
//! angle); a neighbour across the seam wraps to the other edge, and one past a pole lands on
//! the opposite meridian. A neighbour's `log2 d` is interpolated bilinearly between the four
//! pixel centres around its direction when all four are covered (so that the varying column
//! offsets of the rows make no bands on smooth surfaces), else the value of the pixel containing
//! that direction. Background pixels, coverage and depth are left as they are.

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use super::shading::{linear_to_srgb, srgb_to_linear};
use crate::frame::Frame;

/// Number of neighbours of each pixel (Potree's).
pub const NEIGHBOURS: usize = 8;
/// Scale of the response in the exponent (Potree's).
pub const RESPONSE_SCALE: f32 = 300.0;

/// EDL's two parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edl {
    /// Darkening strength; 0 leaves the image unchanged.
    pub strength: f32,
    /// Neighbour distance in pixels of the output image, measured along a meridian.
    pub radius: f32,
}

impl Default for Edl {
    /// Potree's defaults: strength 1, radius 1.4 pixels.
    fn default() -> Self {
        Edl {
            strength: Self::DEFAULT_STRENGTH,
            radius: Self::DEFAULT_RADIUS,
        }
    }
}

impl Edl {
    /// Strength when none is given.
    pub const DEFAULT_STRENGTH: f32 = 1.0;
    /// Radius in output pixels when none is given.
    pub const DEFAULT_RADIUS: f32 = 1.4;

    /// The neighbours' angular distance, radians, for an output image `height` pixels tall.
    pub fn angle(&self, height: u32) -> f64 {
        self.radius as f64 * PI / height.max(1) as f64
    }

    /// Shades `frame` (one equirectangular eye) with neighbours `angle` radians away (see
    /// [`Edl::angle`]; a supersampled frame takes its output image's angle).
    pub fn apply(&self, frame: &mut Frame, angle: f64) {
        if self.strength == 0.0 || frame.width == 0 || frame.height == 0 {
            return;
        }
        let (w, h) = (frame.width as usize, frame.height as usize);
        let offsets = neighbour_offsets(frame.width, frame.height, angle);
        let log_depth: Vec<f32> = frame
            .depth
            .iter()
            .zip(&frame.color)
            .map(|(&d, c)| {
                if c[3] != 0 && d.is_finite() && d > 0.0 {
                    d.log2()
                } else {
                    f32::NAN
                }
            })
            .collect();
        let scale = RESPONSE_SCALE * self.strength;
        frame
            .color
            .par_chunks_mut(w)
            .enumerate()
            .for_each(|(j, row)| {
                let here = &log_depth[j * w..(j + 1) * w];
                for (i, c) in row.iter_mut().enumerate() {
                    let l = here[i];
                    if l.is_nan() {
                        continue;
                    }
                    let mut sum = 0.0f32;
                    for n in &offsets[j] {
                        let n = n.log_depth(&log_depth, w, i);
                        // NaN (background) compares false: skipped.
                        if n < l {
                            sum += l - n;
                        }
                    }
                    if sum > 0.0 {
                        let shade = (-scale * sum / NEIGHBOURS as f32).exp();
                        for ch in &mut c[..3] {
                            *ch = linear_to_srgb(srgb_to_linear(*ch) * shade);
                        }
                    }
                }
            });
        debug_assert_eq!(log_depth.len(), w * h);
    }
}

/// A strength as the command line gives it: a finite number >= 0.
///
/// # Errors
/// A message quoting `s` (which says where to put the option when `s` looks like a file).
pub fn parse_strength(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        Ok(_) => Err(format!(
            "the EDL strength must be a finite number >= 0, got `{s}`"
        )),
        Err(_) => Err(format!(
            "`{s}` is not an EDL strength (a number >= 0); to use the default, put --edl \
             after the input file or write --edl=1"
        )),
    }
}

/// A radius in pixels as the command line gives it: above 0 and at most 32.
///
/// # Errors
/// A message quoting `s`.
pub fn parse_radius(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v > 0.0 && v <= 32.0 => Ok(v),
        _ => Err(format!(
            "the EDL radius must be a number of pixels above 0 and at most 32, got `{s}`"
        )),
    }
}

/// Where one neighbour of the pixels of a row lies, relative to the pixel's column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Neighbour {
    /// Row of the pixel containing the neighbour's direction.
    pub row: u32,
    /// Column offset of that pixel.
    pub col: i64,
    /// Rows above and below the direction, between pixel centres (equal at the edges).
    rows: [u32; 2],
    /// Column offset of the pixel centre west of the direction.
    col_west: i64,
    /// Fractions east of `col_west` and below `rows[0]`.
    frac: [f32; 2],
}

impl Neighbour {
    /// The neighbour's log-depth for the pixel in column `i`: bilinear between the four
    /// pixel centres around its direction when all four are covered, else the value of the
    /// pixel containing it (NaN for background).
    #[inline]
    fn log_depth(&self, log_depth: &[f32], w: usize, i: usize) -> f32 {
        let col = |off: i64| (i as i64 + off).rem_euclid(w as i64) as usize;
        let (c0, c1) = (col(self.col_west), col(self.col_west + 1));
        let [r0, r1] = self.rows.map(|r| r as usize * w);
        let q = [
            log_depth[r0 + c0],
            log_depth[r0 + c1],
            log_depth[r1 + c0],
            log_depth[r1 + c1],
        ];
        if q.iter().any(|v| v.is_nan()) {
            return log_depth[self.row as usize * w + col(self.col)];
        }
        let [fx, fy] = self.frac;
        let top = q[0] + (q[1] - q[0]) * fx;
        let bottom = q[2] + (q[3] - q[2]) * fx;
        top + (bottom - top) * fy
    }
}

/// For each row, where each neighbour lies. Rotation about the polar axis moves a pixel's
/// neighbours with it, so they depend on the row only.
pub fn neighbour_offsets(width: u32, height: u32, angle: f64) -> Vec<[Neighbour; NEIGHBOURS]> {
    let (w, h) = (width as f64, height as f64);
    let (sr, cr) = angle.sin_cos();
    let last = height - 1;
    (0..height)
        .map(|j| {
            let phi = (0.5 - (j as f64 + 0.5) / h) * PI;
            let (sp, cp) = phi.sin_cos();
            // Centre direction at longitude 0 (x east, y forward, z up) and north; east is x.
            let d = [0.0, cp, sp];
            let north = [0.0, -sp, cp];
            std::array::from_fn(|k| {
                let bearing = TAU * k as f64 / NEIGHBOURS as f64;
                let (sb, cb) = bearing.sin_cos();
                let t = [cb, sb * north[1], sb * north[2]];
                let q = [sr * t[0], d[1] * cr + sr * t[1], d[2] * cr + sr * t[2]];
                let lam = q[0].atan2(q[1]);
                let phi_q = q[2].clamp(-1.0, 1.0).asin();
                let y = (0.5 - phi_q / PI) * h;
                // Pixel i's centre is at x = i + 0.5: the neighbour is at x = i + 0.5 + dx.
                let dx = lam / TAU * w;
                let row = (y.floor().max(0.0) as u32).min(last);
                let (sy, sx) = (y - 0.5, dx.floor());
                let r0 = sy.floor();
                let clamp = |r: f64| (r.max(0.0) as u32).min(last);
                Neighbour {
                    row,
                    col: (0.5 + dx).floor() as i64,
                    rows: [clamp(r0), clamp(r0 + 1.0)],
                    col_west: sx as i64,
                    frac: [(dx - sx) as f32, (sy - r0) as f32],
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_at_the_equator_are_the_radius_in_pixels() {
        // 64 x 32: one pixel is pi/32 in both directions at the equator.
        let o = neighbour_offsets(64, 32, 1.4 * PI / 32.0);
        let at = |k: usize| (o[16][k].row, o[16][k].col);
        // Row 16 is just below the equator; east is one column on, north one row up.
        assert_eq!(at(0), (16, 1));
        assert_eq!(at(2), (15, 0));
        assert_eq!(at(4), (16, -1));
        assert_eq!(at(6), (17, 0));
        // Interpolated: 1.4 columns east lies between columns +1 and +2.
        assert_eq!(o[16][0].col_west, 1);
        assert!((o[16][0].frac[0] - 0.4).abs() < 0.01, "{:?}", o[16][0]);
    }

    #[test]
    fn a_neighbour_past_the_pole_is_on_the_opposite_meridian() {
        let o = neighbour_offsets(64, 32, 1.4 * PI / 32.0);
        // Row 0's centre is pi/64 from the north pole; 1.4 pixels north crosses it.
        let n = o[0][2];
        assert_eq!(n.row, 0);
        assert_eq!(n.col.rem_euclid(64), 32);
        // Far east at the top row: many columns away.
        assert!(o[0][0].col > 5, "{:?}", o[0][0]);
    }

    #[test]
    fn smooth_depth_is_interpolated_between_pixels() {
        let n = Neighbour {
            row: 0,
            col: 1,
            rows: [0, 1],
            col_west: 0,
            frac: [0.25, 0.5],
        };
        let ld = [1.0, 2.0, 3.0, 4.0];
        // Columns 0 and 1 of a 2 x 2 image, from column 0.
        assert_eq!(n.log_depth(&ld, 2, 0), 1.0 + 0.25 + 1.0);
        // One background corner: the containing pixel's value.
        let ld = [1.0, f32::NAN, 3.0, 4.0];
        assert!(n.log_depth(&ld, 2, 0).is_nan());
        assert_eq!(n.log_depth(&ld, 2, 1), 1.0);
    }
}
