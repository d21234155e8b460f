//! Fewer points for the same picture: keep every N-th point, or (`auto`) drop the points whose
//! spheres are too small to matter at the render's resolution and lie behind nearer ones.
//!
//! `auto` model, no more than a one-sample-per-pixel render needs: a sphere whose angular
//! diameter seen from the camera centre is at least one pixel is always kept. Smaller
//! ("sub-pixel") spheres are binned by the equirect pixel their centre projects to, and only
//! the [`AUTO_KEEP_PER_PIXEL`] nearest in each pixel are kept: a pixel's single centre ray
//! stops at the first sphere it meets, and sub-pixel spheres further back in the same pixel
//! are hidden behind the nearer ones or missed by the ray anyway. The binning uses the
//! camera centre; ODS eyes sit `ipd/2` away, which moves a sub-pixel point by at most
//! `asin(ipd/2 / d)`, under a pixel for every point farther than `ipd/2 / pixel angle`
//! (5.0 m at 3840 px wide), i.e. for nearly all sub-pixel points.

use std::str::FromStr;

use crate::projection::{Camera, Equirect, equirect};
use crate::scene::Scene;

/// Sub-pixel points kept per pixel, nearest first. Measured on autzen_trim and the lion scan
/// (see tests/robust_subsample.rs): 1 loses visible coverage where the nearest centre misses
/// the pixel ray, 4 keeps the coverage IoU above 0.99.
pub const AUTO_KEEP_PER_PIXEL: usize = 4;

/// How to thin a cloud before rendering.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subsample {
    /// Keep every N-th point (N ≥ 1) in file order.
    Every(u64),
    /// Keep what can matter at the render's resolution (see the module docs).
    Auto,
}

/// `N` (a positive integer) or `auto`.
impl FromStr for Subsample {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("auto") {
            return Ok(Subsample::Auto);
        }
        match t.parse::<u64>() {
            Ok(n) if n >= 1 => Ok(Subsample::Every(n)),
            _ => Err(format!(
                "'{s}' is neither a positive whole number (keep every N-th point) nor 'auto'"
            )),
        }
    }
}

/// Flags every N-th point (the first, the N+1-th, ...).
pub fn every_nth(len: usize, n: u64) -> Vec<bool> {
    let n = n.max(1) as usize;
    (0..len).map(|i| i % n == 0).collect()
}

/// Flags the points the `auto` model keeps for a `image`-sized render from `camera`
/// (positions are relative to `scene.origin`; `camera.center` in the same local frame).
pub fn auto_keep(scene: &Scene, camera: &Camera, width: u32) -> Vec<bool> {
    // Pixel footprints are those of the full panorama this wide, whatever the projection.
    let image = Equirect::from_width(width);
    let basis = camera.basis();
    let pixel_angle = std::f64::consts::TAU / f64::from(image.width.max(1));
    let mut keep = vec![true; scene.len()];
    // (pixel, distance, index) of the sub-pixel points.
    let mut small: Vec<(u32, f32, u32)> = Vec::new();
    for (i, p) in scene.positions.iter().enumerate() {
        let v = p.as_dvec3() - camera.center;
        let d = v.length();
        let r = f64::from(scene.radii.get(i));
        if !(d.is_finite() && d > 0.0) || 2.0 * r >= d * pixel_angle {
            continue;
        }
        let (lam, phi) = equirect::angles(&basis, v / d);
        let (x, y) = image.position_of_angles(lam, phi);
        let col = (x.floor() as i64).clamp(0, i64::from(image.width) - 1) as u32;
        let row = (y.floor() as i64).clamp(0, i64::from(image.height) - 1) as u32;
        small.push((row * image.width + col, d as f32, i as u32));
    }
    small.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut run = 0usize;
    for k in 0..small.len() {
        run = if k > 0 && small[k - 1].0 == small[k].0 {
            run + 1
        } else {
            0
        };
        if run >= AUTO_KEEP_PER_PIXEL {
            keep[small[k].2 as usize] = false;
        }
    }
    keep
}

/// Applies `how` to `scene` for a render from `camera` at `image`; returns the thinned scene
/// (a copy; `scene` is left as it is).
pub fn apply(scene: &Scene, how: Subsample, camera: &Camera, width: u32) -> Scene {
    let keep = match how {
        Subsample::Every(n) => every_nth(scene.len(), n),
        Subsample::Auto => auto_keep(scene, camera, width),
    };
    scene.select(&keep)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Radii;
    use glam::{DVec3, Vec3};

    #[test]
    fn parses_counts_and_auto() {
        assert_eq!("3".parse(), Ok(Subsample::Every(3)));
        assert_eq!("AUTO".parse(), Ok(Subsample::Auto));
        for bad in ["0", "-2", "1.5", "", "all"] {
            assert!(bad.parse::<Subsample>().is_err(), "{bad}");
        }
    }

    #[test]
    fn every_nth_keeps_the_first_of_each_run() {
        assert_eq!(
            every_nth(7, 3),
            [true, false, false, true, false, false, true]
        );
        let mut s = Scene::new(
            DVec3::ZERO,
            (0..5).map(|i| Vec3::splat(i as f32)).collect(),
            0.1,
        );
        s.attributes.intensity = Some(vec![0, 1, 2, 3, 4]);
        s.radii = Radii::PerPoint(vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        let t = apply(&s, Subsample::Every(2), &Camera::new(DVec3::ZERO, 0.0), 16);
        assert_eq!(t.len(), 3);
        assert_eq!(t.attributes.intensity, Some(vec![0, 2, 4]));
        assert_eq!(t.radii, Radii::PerPoint(vec![1.0, 3.0, 5.0]));
    }

    #[test]
    fn auto_keeps_big_spheres_and_the_nearest_small_ones_per_pixel() {
        // Ten tiny spheres straight ahead at 10..19 m (one pixel), one big one at 50 m.
        let mut positions: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new(0.0, 10.0 + i as f32, 0.0))
            .collect();
        positions.push(Vec3::new(0.0, 50.0, 0.0));
        let mut s = Scene::new(DVec3::ZERO, positions, 0.001);
        let mut r = vec![0.001; 10];
        r.push(10.0);
        s.radii = Radii::PerPoint(r);
        let keep = auto_keep(&s, &Camera::new(DVec3::ZERO, 0.0), 64);
        let kept: Vec<usize> = (0..11).filter(|&i| keep[i]).collect();
        let mut expected: Vec<usize> = (0..AUTO_KEEP_PER_PIXEL).collect();
        expected.push(10);
        assert_eq!(kept, expected);
    }
}
