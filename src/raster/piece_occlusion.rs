//! Whole pieces of a gathered frame skipped before any of their points is touched: once the
//! nearer pieces are drawn, the frame's occlusion tiles (`shaders/occlusion.wgsl`) are read
//! back, and a piece whose box lies beyond the tiles it could show in, in every eye, is left
//! out. The image stays bit for bit the same: each of its spheres would have been hidden by
//! the per-sphere test, which it never reaches.
//!
//! A piece is its box of sphere extents (centres plus radii). Every ray of an eye starts
//! within `h` (half the IPD; 0 for mono) of C and points along its pixel's direction
//! (DESIGN §3), so a ray from `o` meeting the box at `X` has `X - o` in the box grown by `h`:
//! the pixels it can show in are the directions from C to the grown box, and no hit on it is
//! nearer than the grown box's distance from C.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DVec2, DVec3};

use super::constants::TILE_SIDE;
use super::splat::tiles_along;
use crate::projection::View;

/// Relative slack on the nearest distance a box can be hit at: more than the f32 rounding of
/// the shaders' distances.
const NEAR_SLACK: f64 = 1e-4;
/// Pixels added to every side of a box's pixel range, for the shaders' f32 angles.
const PIXEL_SLACK: i64 = 1;

/// The occlusion tiles of every eye of a frame, read back: per tile `!distance bits` of a
/// distance within which each of its pixels shows a hit (0: nothing known).
pub(crate) struct OcclusionTiles {
    width: u32,
    height: u32,
    eyes: Vec<(View, Vec<u32>)>,
}

impl OcclusionTiles {
    /// The tiles of a `width x height` equirect frame, one array per eye with its view.
    pub(crate) fn new(width: u32, height: u32, eyes: Vec<(View, Vec<u32>)>) -> Self {
        OcclusionTiles {
            width,
            height,
            eyes,
        }
    }

    /// True when, in every eye, spheres within the box `lo..hi` (relative to C, radii
    /// included) can only show behind what the tiles already hold.
    pub(crate) fn hide(&self, lo: DVec3, hi: DVec3) -> bool {
        !self.eyes.is_empty()
            && self
                .eyes
                .iter()
                .all(|(view, tiles)| self.eye_hides(view, tiles, lo, hi))
    }

    fn eye_hides(&self, view: &View, tiles: &[u32], lo: DVec3, hi: DVec3) -> bool {
        let h = ray_origin_reach(view);
        let (lo, hi) = (lo - DVec3::splat(h), hi + DVec3::splat(h));
        let near = DVec3::ZERO.clamp(lo, hi).length() * (1.0 - NEAR_SLACK);
        if near.is_nan() || near <= 0.0 {
            return false;
        }
        let Some(px) = box_pixels(view, (self.width, self.height), lo, hi) else {
            return false;
        };
        // A tile hides the box when its distance is nearer than the box's nearest hit.
        let key = !(near as f32).to_bits();
        let across = tiles_along(self.width) as usize;
        let side = i64::from(TILE_SIDE);
        let (ty0, ty1) = (px.y0 / side, px.y1 / side);
        columns(px.x0, px.x1, i64::from(self.width)).all(|(first, last)| {
            (ty0..=ty1).all(|ty| {
                (first / side..=last / side)
                    .all(|tx| tiles[ty as usize * across + tx as usize] > key)
            })
        })
    }
}

/// How far from C the rays of `view` start: half the IPD for a stereo eye, 0 for mono (as
/// `ray_origin_reach` in `shaders/occlusion.wgsl`).
fn ray_origin_reach(view: &View) -> f64 {
    if view.eye_sign != 0.0 {
        view.half_ipd
    } else {
        0.0
    }
}

/// Pixels (columns unwrapped, rows clipped) whose centre rays can point into a box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pixels {
    x0: i64,
    x1: i64,
    y0: i64,
    y1: i64,
}

/// The pixels of a `size` equirect image of `view` whose directions from C point into the
/// box `lo..hi` (relative to C), widened by [`PIXEL_SLACK`]; `None` when the box holds C.
fn box_pixels(view: &View, size: (u32, u32), lo: DVec3, hi: DVec3) -> Option<Pixels> {
    let b = view.basis();
    let corners: Vec<DVec3> = (0..8)
        .map(|k| {
            let c = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            DVec3::new(c.dot(b.right), c.dot(b.forward), c.dot(b.up))
        })
        .collect();
    let (lam, rho_min) = longitudes(&corners);
    let rho_max = corners.iter().map(|c| c.x.hypot(c.y)).fold(0.0, f64::max);
    let z_lo = corners.iter().map(|c| c.z).fold(f64::INFINITY, f64::min);
    let z_hi = corners
        .iter()
        .map(|c| c.z)
        .fold(f64::NEG_INFINITY, f64::max);
    if rho_min == 0.0 && z_lo <= 0.0 && z_hi >= 0.0 {
        return None;
    }
    // Over the box the latitude atan2(z, rho) grows with z, and falls with rho where z > 0.
    let phi_hi = z_hi.atan2(if z_hi > 0.0 { rho_min } else { rho_max });
    let phi_lo = z_lo.atan2(if z_lo < 0.0 { rho_min } else { rho_max });
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let x = |lam: f64| (lam / TAU + 0.5) * w;
    let y = |phi: f64| (0.5 - phi / PI) * h;
    let (x0, x1) = match lam {
        Some(r) => (
            (x(r.x) - 0.5).ceil() as i64 - PIXEL_SLACK,
            (x(r.y) - 0.5).floor() as i64 + PIXEL_SLACK,
        ),
        None => (0, i64::from(size.0) - 1),
    };
    let y0 = ((y(phi_hi.min(FRAC_PI_2)) - 0.5).ceil() as i64 - PIXEL_SLACK).max(0);
    let y1 =
        ((y(phi_lo.max(-FRAC_PI_2)) - 0.5).floor() as i64 + PIXEL_SLACK).min(i64::from(size.1) - 1);
    Some(Pixels { x0, x1, y0, y1 })
}

/// The longitudes `(lo, hi)` of the directions from the vertical axis to the box whose
/// corners, in the view's frame, are `corners` (unwrapped: `hi - lo < pi`), and the box's
/// least distance from the axis; no range (every longitude) and 0 when the box's footprint
/// holds the axis.
fn longitudes(corners: &[DVec3]) -> (Option<DVec2>, f64) {
    let feet: Vec<DVec2> = corners.iter().map(|c| DVec2::new(c.x, c.y)).collect();
    let mut lams: Vec<f64> = feet.iter().map(|f| f.x.atan2(f.y)).collect();
    lams.sort_by(f64::total_cmp);
    // The footprint (the hull of the corners' feet) misses the axis exactly when its
    // directions leave a gap wider than a half turn: the range is the rest.
    let n = lams.len();
    let (gap, after) = (0..n)
        .map(|k| {
            let next = if k + 1 < n {
                lams[k + 1]
            } else {
                lams[0] + TAU
            };
            (next - lams[k], (k + 1) % n)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .expect("eight corners");
    if gap <= PI || feet.contains(&DVec2::ZERO) {
        return (None, 0.0);
    }
    let lo = lams[after];
    let hi = lo + (TAU - gap);
    // The hull's distance from the axis: the nearest of the segments between its feet.
    let mut rho = f64::INFINITY;
    for (i, a) in feet.iter().enumerate() {
        for b in &feet[i..] {
            rho = rho.min(segment_distance(*a, *b));
        }
    }
    (Some(DVec2::new(lo, hi)), rho)
}

/// Distance from the origin to the segment `a..b`.
fn segment_distance(a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        (-a.dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + t * ab).length()
}

/// The wrapped column ranges of unwrapped columns `x0..=x1` of an image `w` wide: one, or
/// two across the seam.
fn columns(x0: i64, x1: i64, w: i64) -> impl Iterator<Item = (i64, i64)> {
    let parts = if x1 - x0 + 1 >= w {
        [(0, w - 1), (1, 0)]
    } else {
        let a = x0.rem_euclid(w);
        let b = a + (x1 - x0);
        if b < w {
            [(a, b), (1, 0)]
        } else {
            [(a, w - 1), (0, b - w)]
        }
    };
    parts.into_iter().filter(|(a, b)| a <= b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{Camera, Equirect, Stereo};
    use crate::render::RenderSettings;

    /// The views of a `width` frame of `stereo`, level camera at the origin facing +y.
    fn views(width: u32, stereo: Stereo) -> Vec<View> {
        RenderSettings {
            stereo,
            ..RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0))
        }
        .views()
    }

    /// Tiles that all hold a hit within `far`.
    fn tiles_within(width: u32, far: f32) -> Vec<u32> {
        vec![!far.to_bits(); (tiles_along(width) * tiles_along(width / 2)) as usize]
    }

    #[test]
    fn a_box_behind_a_wall_of_hits_is_hidden_and_one_before_it_is_not() {
        let width = 256;
        for stereo in [Stereo::Mono, Stereo::DEFAULT_ODS] {
            let eyes = |far| {
                let vs = views(width, stereo);
                let tiles = vs.iter().map(|v| (*v, tiles_within(width, far))).collect();
                OcclusionTiles::new(width, width / 2, tiles)
            };
            let lo = DVec3::new(-5.0, 20.0, -1.0);
            let hi = DVec3::new(5.0, 30.0, 4.0);
            assert!(eyes(10.0).hide(lo, hi), "{stereo:?}");
            // The box is 20 m away (less the eyes' reach and a slack of 1e-4 of it).
            assert!(!eyes(19.999).hide(lo, hi), "{stereo:?}");
            assert!(!eyes(25.0).hide(lo, hi), "{stereo:?}");
            // A box around the camera is never hidden.
            assert!(!eyes(1.0).hide(DVec3::splat(-1.0), DVec3::splat(1.0)));
        }
    }

    #[test]
    fn a_single_open_tile_in_the_box_s_directions_shows_it() {
        let width = 512;
        let v = views(width, Stereo::Mono)[0];
        let (lo, hi) = (DVec3::new(-5.0, 20.0, -1.0), DVec3::new(5.0, 30.0, 4.0));
        let px = box_pixels(&v, (width, width / 2), lo, hi).unwrap();
        let across = tiles_along(width) as i64;
        let side = i64::from(TILE_SIDE);
        // Every tile the box's pixels touch must be covered; one left open shows it, one
        // outside its pixels does not matter.
        for (tx, ty, shows) in [
            (px.x0 / side, px.y0 / side, true),
            (px.x1 / side, px.y1 / side, true),
            ((px.x1 / side + 3) % across, px.y0 / side, false),
        ] {
            let mut tiles = tiles_within(width, 10.0);
            tiles[(ty * across + tx) as usize] = 0;
            let t = OcclusionTiles::new(width, width / 2, vec![(v, tiles)]);
            assert_eq!(!t.hide(lo, hi), shows, "tile ({tx}, {ty})");
        }
    }

    #[test]
    fn the_pixels_of_a_box_hold_every_ray_that_meets_it() {
        // Sample points of boxes around the camera and check the pixel each projects to
        // (its direction from the eye's ray origin) lies in the box's pixels.
        let width = 360;
        let size = (width, width / 2);
        let boxes = [
            (DVec3::new(-5.0, 20.0, -1.0), DVec3::new(5.0, 30.0, 4.0)),
            // Across the seam (behind the camera).
            (DVec3::new(-3.0, -40.0, -2.0), DVec3::new(3.0, -35.0, 30.0)),
            // Over the camera's head, off to the side.
            (DVec3::new(2.0, -1.0, 3.0), DVec3::new(6.0, 1.0, 9.0)),
            // Below the horizon, far.
            (
                DVec3::new(100.0, 100.0, -2.0),
                DVec3::new(140.0, 150.0, -1.5),
            ),
        ];
        for stereo in [Stereo::Mono, Stereo::DEFAULT_ODS] {
            for camera in [
                Camera::new(DVec3::ZERO, 0.0),
                Camera::new(DVec3::ZERO, 73.0).with_orientation(20.0, -10.0),
            ] {
                let settings = RenderSettings {
                    stereo,
                    ..RenderSettings::new(width, camera)
                };
                for v in settings.views() {
                    for (lo, hi) in boxes {
                        let h = ray_origin_reach(&v);
                        let grown = (lo - DVec3::splat(h), hi + DVec3::splat(h));
                        let px = box_pixels(&v, size, grown.0, grown.1).unwrap();
                        let image = Equirect {
                            width,
                            height: width / 2,
                        };
                        for i in 0..width {
                            for j in 0..width / 2 {
                                let (o, d) = v.pixel_ray(&image, i, j);
                                if !ray_meets_box(o, d, lo, hi) {
                                    continue;
                                }
                                let inside = columns(px.x0, px.x1, i64::from(width))
                                    .any(|(a, b)| (a..=b).contains(&i64::from(i)))
                                    && (px.y0..=px.y1).contains(&i64::from(j));
                                assert!(inside, "{stereo:?} pixel ({i}, {j}) of box {lo}..{hi}");
                            }
                        }
                    }
                }
            }
        }
    }

    /// Whether the ray from `o` along `d` meets the box `lo..hi` in front of `o` (slabs).
    fn ray_meets_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for k in 0..3 {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }

    #[test]
    fn column_ranges_wrap_at_the_seam() {
        assert_eq!(columns(3, 7, 10).collect::<Vec<_>>(), [(3, 7)]);
        assert_eq!(columns(8, 12, 10).collect::<Vec<_>>(), [(8, 9), (0, 2)]);
        assert_eq!(columns(-2, 1, 10).collect::<Vec<_>>(), [(8, 9), (0, 1)]);
        assert_eq!(columns(-5, 20, 10).collect::<Vec<_>>(), [(0, 9)]);
    }
}
