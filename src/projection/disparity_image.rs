//! The angular-disparity image of a stereo render and a viewing-comfort summary of it
//! (DESIGN §9).
//!
//! Each left-eye pixel that sees a surface point gets that point's horizontal and vertical
//! disparity between the two views, in arcminutes; pixels that see nothing, or whose point
//! has no projection in one eye, hold NaN.

use std::fmt;

use glam::DVec3;
use rayon::prelude::*;

use super::View;
use super::disparity::{
    ARCMIN_PER_RADIAN, angular_disparity, disparity_gradient, perceived_distance,
};

/// Per-pixel angular disparity of the left eye's image, arcminutes, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DisparityImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Horizontal disparity `wrap(lamL - lamR)`, positive nearer than infinity; NaN where
    /// there is none.
    pub dh: Vec<f32>,
    /// Vertical disparity `phiL - phiR`; NaN where there is none.
    pub dv: Vec<f32>,
}

impl DisparityImage {
    /// Index of pixel `(i, j)` in the row-major buffers.
    #[inline]
    pub fn index(&self, i: u32, j: u32) -> usize {
        j as usize * self.width as usize + i as usize
    }

    /// Pixels with a disparity (a finite `dh`).
    pub fn covered_count(&self) -> usize {
        self.dh.iter().filter(|d| d.is_finite()).count()
    }
}

/// The disparity image of a `width x height` render: `hits(i, j)` is the world point the
/// left-eye pixel `(i, j)` sees (`None` for background), projected into `left` and `right`.
pub fn disparity_image(
    width: u32,
    height: u32,
    hits: impl Fn(u32, u32) -> Option<DVec3> + Sync,
    left: &View,
    right: &View,
) -> DisparityImage {
    disparity_image_of(width, height, |i, j| {
        hits(i, j).and_then(|p| angular_disparity(left, right, p))
    })
}

/// The disparity image whose pixel `(i, j)` has disparity `at(i, j)` (radians).
pub fn disparity_image_of(
    width: u32,
    height: u32,
    at: impl Fn(u32, u32) -> Option<(f64, f64)> + Sync,
) -> DisparityImage {
    let n = width as usize * height as usize;
    let mut dh = vec![f32::NAN; n];
    let mut dv = vec![f32::NAN; n];
    if n > 0 {
        dh.par_chunks_mut(width as usize)
            .zip(dv.par_chunks_mut(width as usize))
            .enumerate()
            .for_each(|(j, (row_h, row_v))| {
                for (i, (h, v)) in row_h.iter_mut().zip(row_v.iter_mut()).enumerate() {
                    if let Some((dh, dv)) = at(i as u32, j as u32) {
                        *h = (dh * ARCMIN_PER_RADIAN) as f32;
                        *v = (dv * ARCMIN_PER_RADIAN) as f32;
                    }
                }
            });
    }
    DisparityImage {
        width,
        height,
        dh,
        dv,
    }
}

/// How comfortable a disparity image is to view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comfort {
    /// Pixels with a disparity.
    pub covered: usize,
    /// Share of the covered pixels perceived nearer than `near_m` (`a / sin(dh/2)`); 0 when
    /// none is covered.
    pub nearer_share: f64,
    /// The distance `nearer_share` is measured against, metres.
    pub near_m: f64,
    /// Largest horizontal disparity, arcminutes; 0 when none is covered.
    pub max_dh_arcmin: f64,
    /// Largest vertical disparity in magnitude, arcminutes; 0 when none is covered.
    pub max_abs_dv_arcmin: f64,
    /// Horizontally adjacent pairs of covered pixels.
    pub gradient_pairs: usize,
    /// Share of those pairs whose disparity gradient exceeds 1 (too steep to fuse); 0 when
    /// there is no pair.
    pub steep_gradient_share: f64,
}

fn share(count: usize, of: usize) -> f64 {
    if of == 0 {
        0.0
    } else {
        count as f64 / of as f64
    }
}

/// The comfort summary of `img` for eyes `2 * half_ipd` apart. The disparity gradient takes
/// the pixel pitch `2 pi / width` of a 360° image; with `wraps` the last and first pixel of a
/// row are neighbours too (a full equirectangular image).
pub fn comfort(img: &DisparityImage, half_ipd: f64, near_m: f64, wraps: bool) -> Comfort {
    let radians = |arcmin: f32| arcmin as f64 / ARCMIN_PER_RADIAN;
    let mut out = Comfort {
        covered: 0,
        nearer_share: 0.0,
        near_m,
        max_dh_arcmin: 0.0,
        max_abs_dv_arcmin: 0.0,
        gradient_pairs: 0,
        steep_gradient_share: 0.0,
    };
    let mut nearer = 0usize;
    for (&dh, &dv) in img.dh.iter().zip(&img.dv) {
        if !dh.is_finite() {
            continue;
        }
        out.covered += 1;
        if perceived_distance(half_ipd, radians(dh)) < near_m {
            nearer += 1;
        }
        out.max_dh_arcmin = out.max_dh_arcmin.max(dh as f64);
        if dv.is_finite() {
            out.max_abs_dv_arcmin = out.max_abs_dv_arcmin.max((dv as f64).abs());
        }
    }
    out.nearer_share = share(nearer, out.covered);

    let mut steep = 0usize;
    if img.width > 0 {
        let width = img.width;
        for row in img.dh.chunks_exact(width as usize) {
            let seam = (wraps && row.len() > 2).then(|| (row[row.len() - 1], row[0]));
            for (a, b) in row.windows(2).map(|w| (w[0], w[1])).chain(seam) {
                if a.is_finite() && b.is_finite() {
                    out.gradient_pairs += 1;
                    if disparity_gradient(radians(a), radians(b), width) > 1.0 {
                        steep += 1;
                    }
                }
            }
        }
    }
    out.steep_gradient_share = share(steep, out.gradient_pairs);
    out
}

impl fmt::Display for Comfort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.covered == 0 {
            return writeln!(f, "disparity: no pixel sees a surface in both eyes");
        }
        writeln!(
            f,
            "disparity: {} pixels, largest {:.2} arcmin horizontal, {:.3} arcmin vertical",
            self.covered, self.max_dh_arcmin, self.max_abs_dv_arcmin
        )?;
        writeln!(
            f,
            "  nearer than {} m: {:.2}% of those pixels",
            self.near_m,
            100.0 * self.nearer_share
        )?;
        writeln!(
            f,
            "  disparity gradient above 1 (hard to fuse): {:.2}% of {} adjacent pairs",
            100.0 * self.steep_gradient_share,
            self.gradient_pairs
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{Camera, Eye, OdsOffset, PoleMerging, Stereo};

    const A: f64 = 0.032;

    fn image(width: u32, dh: Vec<f32>, dv: Vec<f32>) -> DisparityImage {
        DisparityImage {
            width,
            height: dh.len() as u32 / width,
            dh,
            dv,
        }
    }

    #[test]
    fn plain_ods_points_get_two_asin_r_over_rho_in_arcminutes() {
        let camera = Camera::new(DVec3::new(5.0, 1.0, 2.0), 30.0);
        let stereo = Stereo::Ods {
            ipd: 2.0 * A,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
        let (l, r) = (
            View::eye(camera, &stereo, Eye::Left),
            View::eye(camera, &stereo, Eye::Right),
        );
        let b = camera.basis();
        // Column i sees a point at horizontal distance 0.5 (i + 1) m; row 0 sees nothing and
        // column 0 of row 2 a point inside the viewing circle.
        let rho_of = |i: u32, j: u32| {
            if j == 2 && i == 0 {
                0.01
            } else {
                0.5 * (i + 1) as f64
            }
        };
        let hits = |i: u32, j: u32| {
            (j > 0).then(|| {
                let lam = i as f64 - 3.0;
                let rho = rho_of(i, j);
                camera.center
                    + rho * (lam.sin() * b.right + lam.cos() * b.forward)
                    + (j as f64 - 2.0) * b.up
            })
        };
        let img = disparity_image(8, 3, hits, &l, &r);
        assert_eq!((img.width, img.height, img.dh.len()), (8, 3, 24));
        for j in 0..3 {
            for i in 0..8 {
                let k = img.index(i, j);
                if j == 0 || (j == 2 && i == 0) {
                    assert!(img.dh[k].is_nan() && img.dv[k].is_nan(), "({i}, {j})");
                    continue;
                }
                let want = 2.0 * (A / rho_of(i, j)).asin() * ARCMIN_PER_RADIAN;
                assert!(
                    (img.dh[k] as f64 - want).abs() < 2e-5,
                    "({i}, {j}): {}",
                    img.dh[k]
                );
                assert!(img.dv[k].abs() < 1e-9);
            }
        }
        assert_eq!(img.covered_count(), 15);
    }

    #[test]
    fn comfort_counts_near_pixels_and_extremes() {
        // Nearer than 2 m means dh > 2 asin(0.016) = 110.01 arcmin: 120 and 200 are.
        let nan = f32::NAN;
        let img = image(
            4,
            vec![120.0, 60.0, nan, 0.0, 30.0, 30.0, 200.0, 10.0],
            vec![0.0, 0.5, nan, 0.0, -3.5, 0.0, 1.0, 0.0],
        );
        let c = comfort(&img, A, 2.0, false);
        assert_eq!(c.covered, 7);
        assert_eq!(c.nearer_share, 2.0 / 7.0);
        assert_eq!(c.near_m, 2.0);
        assert_eq!(c.max_dh_arcmin, 200.0);
        assert_eq!(c.max_abs_dv_arcmin, 3.5);
        // Row 0: (120, 60), (0 after NaN) none; row 1: three pairs.
        assert_eq!(c.gradient_pairs, 4);
        // The pixel pitch of a 4-pixel row is 5400 arcmin: nothing is steep.
        assert_eq!(c.steep_gradient_share, 0.0);
        // Nearer than 1.5 m: dh > 146.7 arcmin, only 200.
        assert_eq!(comfort(&img, A, 1.5, false).nearer_share, 1.0 / 7.0);
        let text = c.to_string();
        assert!(text.contains("7 pixels, largest 200.00 arcmin"), "{text}");
        assert!(text.contains("nearer than 2 m: 28.57%"), "{text}");
        assert!(text.contains("0.00% of 4 adjacent pairs"), "{text}");
    }

    #[test]
    fn steep_gradients_are_counted_and_the_seam_only_when_asked() {
        // 2160 pixels a row: the pitch is 10 arcmin, so a step above 10 arcmin is steep.
        let mut dh = vec![f32::NAN; 2160];
        dh[..7].copy_from_slice(&[0.0, 5.0, 20.0, f32::NAN, 30.0, 41.0, 50.9]);
        dh[2159] = 100.0;
        let img = image(2160, dh, vec![0.0; 2160]);
        // Pairs: 0-5 (0.5), 5-20 (1.5), 30-41 (1.1), 41-50.9 (0.99); seam 100-0 (10).
        let open = comfort(&img, A, 1.0, false);
        assert_eq!(open.gradient_pairs, 4);
        assert_eq!(open.steep_gradient_share, 2.0 / 4.0);
        let wrapped = comfort(&img, A, 1.0, true);
        assert_eq!(wrapped.gradient_pairs, 5);
        assert_eq!(wrapped.steep_gradient_share, 3.0 / 5.0);
    }

    #[test]
    fn nothing_covered_gives_zeros() {
        let img = image(4, vec![f32::NAN; 8], vec![f32::NAN; 8]);
        let c = comfort(&img, A, 1.0, true);
        assert_eq!((c.covered, c.gradient_pairs), (0, 0));
        assert_eq!((c.nearer_share, c.steep_gradient_share), (0.0, 0.0));
        assert!(c.to_string().contains("no pixel"));
        let empty = disparity_image(
            0,
            0,
            |_, _| None,
            &View::mono(Camera::new(DVec3::ZERO, 0.0)),
            &View::mono(Camera::new(DVec3::ZERO, 0.0)),
        );
        assert!(empty.dh.is_empty());
    }
}
