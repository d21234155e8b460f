//! Holes: background that coverage surrounds, where a surface should have closed.
//!
//! A pixel is a *hole* when it is not hit (coverage under one half) and a hit pixel lies
//! within `reach` pixels of it in each of the four directions: left and right (wrapping
//! around the panorama's seam) and up and down (not past the poles). Open sky above a
//! horizon has no hit above it and is not a hole; a gap between sphere splats on a wall,
//! or the ground seen between sparse ground spheres, is. The *hole share* is holes over all
//! pixels of the image. A square image is a top-bottom ODS pair: each eye is measured on its
//! own and the counts are summed.

use super::Samples;

/// Holes in an image ([`holes`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HoleStats {
    /// Pixels that are holes.
    pub holes: usize,
    /// Pixels hit.
    pub covered: usize,
    /// Pixels in the image.
    pub pixels: usize,
    /// Reach in pixels the holes were found with.
    pub reach: usize,
}

impl HoleStats {
    /// Holes over all pixels (0 for an empty image).
    pub fn hole_share(&self) -> f64 {
        self.holes as f64 / self.pixels.max(1) as f64
    }

    /// Hit pixels over all pixels (0 for an empty image).
    pub fn coverage(&self) -> f64 {
        self.covered as f64 / self.pixels.max(1) as f64
    }
}

/// The default reach for an image `width` pixels wide: 1/128 of it (2.8° of the panorama,
/// 30 px at 3840), at least 2, so the measure means the same at every width.
pub fn default_reach(width: u32) -> usize {
    (width as usize / 128).max(2)
}

/// Counts the holes of `image` within `reach` pixels (see the module docs).
pub fn holes<S: Samples>(image: &S, reach: usize) -> HoleStats {
    let (w, h) = image.size();
    let (w, h) = (w as usize, h as usize);
    let hit: Vec<bool> = (0..w * h).map(|k| image.hit(k)).collect();
    let eyes = if w == h && h.is_multiple_of(2) { 2 } else { 1 };
    let eye_h = h / eyes;
    let mut stats = HoleStats {
        reach,
        pixels: w * h,
        covered: hit.iter().filter(|x| **x).count(),
        holes: 0,
    };
    for e in 0..eyes {
        stats.holes += eye_holes(&hit[e * w * eye_h..(e + 1) * w * eye_h], w, eye_h, reach);
    }
    stats
}

/// Holes of one equirectangular eye, `hit` row-major `w` × `h`.
fn eye_holes(hit: &[bool], w: usize, h: usize, reach: usize) -> usize {
    if w == 0 || h == 0 {
        return 0;
    }
    // Per pixel: is a hit within `reach` along each direction? Runs of misses are measured
    // from the last hit seen scanning that way.
    let mut left = vec![false; w * h];
    let mut right = vec![false; w * h];
    let mut up = vec![false; w * h];
    let mut down = vec![false; w * h];
    for y in 0..h {
        let row = &hit[y * w..(y + 1) * w];
        if !row.iter().any(|x| *x) {
            continue;
        }
        // Two laps around the row, so the seam wraps.
        let mut since = usize::MAX;
        for i in 0..2 * w {
            let x = i % w;
            if row[x] {
                since = 0;
            } else {
                since = since.saturating_add(1);
            }
            if i >= w {
                left[y * w + x] = since <= reach;
            }
        }
        since = usize::MAX;
        for i in (0..2 * w).rev() {
            let x = i % w;
            if row[x] {
                since = 0;
            } else {
                since = since.saturating_add(1);
            }
            if i < w {
                right[y * w + x] = since <= reach;
            }
        }
    }
    for x in 0..w {
        let mut since = usize::MAX;
        for y in 0..h {
            since = if hit[y * w + x] {
                0
            } else {
                since.saturating_add(1)
            };
            up[y * w + x] = since <= reach;
        }
        since = usize::MAX;
        for y in (0..h).rev() {
            since = if hit[y * w + x] {
                0
            } else {
                since.saturating_add(1)
            };
            down[y * w + x] = since <= reach;
        }
    }
    (0..w * h)
        .filter(|&k| !hit[k] && left[k] && right[k] && up[k] && down[k])
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Frame;

    fn frame(w: u32, h: u32, hit: impl Fn(u32, u32) -> bool) -> Frame {
        let mut f = Frame::new(w, h);
        for y in 0..h {
            for x in 0..w {
                if hit(x, y) {
                    let k = f.index(x, y);
                    f.color[k] = [255, 255, 255, 255];
                }
            }
        }
        f
    }

    #[test]
    fn a_gap_inside_a_surface_is_a_hole_and_open_sky_is_not() {
        // Ground over the bottom half, with a 3×3 gap; sky above.
        let f = frame(64, 32, |x, y| {
            y >= 16 && !((20..23).contains(&x) && (24..27).contains(&y))
        });
        let s = holes(&f, 4);
        assert_eq!(s.holes, 9);
        assert_eq!(s.covered, 64 * 16 - 9);
        assert!((s.hole_share() - 9.0 / 2048.0).abs() < 1e-12);
        // A gap wider than the reach is not closed by coverage.
        assert_eq!(holes(&f, 1).holes, 0);
    }

    #[test]
    fn holes_wrap_around_the_seam_but_not_over_the_poles() {
        // A band of rows with a gap across the seam (columns 0 and 63).
        let band = frame(64, 32, |x, y| (10..20).contains(&y) && x != 0 && x != 63);
        assert_eq!(
            holes(&band, 2).holes,
            0,
            "nothing above or below row 10..20's gap"
        );
        let closed = frame(64, 32, |x, y| {
            (10..20).contains(&y) && (x != 0 && x != 63 || y == 10 || y == 19)
        });
        assert_eq!(holes(&closed, 8).holes, 2 * 8);
        // At the top row nothing lies above: not a hole.
        let top = frame(64, 32, |x, y| y < 4 && x != 5);
        assert_eq!(holes(&top, 4).holes, 0);
    }

    #[test]
    fn ods_eyes_are_measured_apart() {
        // Rows 6 (top eye) and 9 (bottom eye) do not enclose the misses between them across
        // the eye boundary; rows 2 and 5 of one eye do.
        let f = frame(16, 16, |x, y| y == 6 || y == 9 || x % 4 == 0);
        assert_eq!(holes(&f, 4).holes, 0);
        let g = frame(16, 16, |x, y| y == 2 || y == 5 || x % 4 == 0);
        assert_eq!(holes(&g, 4).holes, 2 * 12);
    }

    #[test]
    fn reach_scales_with_width() {
        assert_eq!(default_reach(3840), 30);
        assert_eq!(default_reach(256), 2);
        assert_eq!(default_reach(64), 2);
    }
}
