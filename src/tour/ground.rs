//! The ground along a path, for paths without heights: [`placement::ground_height`] (the one
//! ground estimator) sampled every few metres along the curve and smoothed, so the camera
//! walks over the terrain without copying every bump of it.

use std::collections::HashMap;

use glam::{DVec3, Vec2, Vec3};

use crate::prepare::placement;
use crate::scene::Scene;

/// Metres between ground samples along the path.
pub const SAMPLE_STEP: f64 = 2.0;
/// Half-width of the moving average over the samples, metres: steps and curbs become ramps.
pub const SMOOTHING: f64 = 4.0;

/// Ground heights (local frame) near any XY point of a scene, from its points bucketed once so
/// that each estimate reads only the neighbourhood the estimator looks at.
pub struct GroundIndex<'s> {
    scene: &'s Scene,
    extent: f32,
    cell: f32,
    buckets: HashMap<(i32, i32), Vec<u32>>,
}

impl<'s> GroundIndex<'s> {
    /// Buckets the points of `scene` (local frame).
    pub fn new(scene: &'s Scene) -> Self {
        let extent = scene.bounds().map_or(1.0, |(lo, hi)| {
            (hi.truncate() - lo.truncate()).max_element()
        });
        // The estimator's first disc is extent/64 wide and rarely needs to double more than
        // twice; cells of that size keep each gather small.
        let cell = (extent / 64.0).max(1.0);
        let mut buckets: HashMap<(i32, i32), Vec<u32>> = HashMap::new();
        for (i, p) in scene.positions.iter().enumerate() {
            buckets
                .entry(key(p.truncate(), cell))
                .or_default()
                .push(i as u32);
        }
        GroundIndex {
            scene,
            extent,
            cell,
            buckets,
        }
    }

    /// The ground height (local frame) under `xy` (local frame), estimated from the points
    /// within four first-disc radii of it; `None` where none is.
    pub fn height(&self, xy: Vec2) -> Option<f64> {
        let (cx, cy) = key(xy, self.cell);
        let reach = 4;
        let mut near: Vec<Vec3> = Vec::new();
        for i in cx - reach..=cx + reach {
            for j in cy - reach..=cy + reach {
                if let Some(b) = self.buckets.get(&(i, j)) {
                    near.extend(b.iter().map(|&k| self.scene.positions[k as usize]));
                }
            }
        }
        let local = Scene::new(self.scene.origin, near, 0.0);
        placement::ground_height(&local, xy, self.extent)
    }
}

fn key(p: Vec2, cell: f32) -> (i32, i32) {
    ((p.x / cell).floor() as i32, (p.y / cell).floor() as i32)
}

/// Smoothed ground heights along a horizontal curve: `at(s)` for arc length `s` gives the
/// height (local frame) of the ground there.
pub struct GroundProfile {
    step: f64,
    heights: Vec<f64>,
}

impl GroundProfile {
    /// Samples the ground every [`SAMPLE_STEP`] metres of a curve `length` metres long whose
    /// point at arc length `s` is `point(s)` (local frame), and smooths the samples.
    /// `Err(s)`: no ground near the curve at arc length `s`.
    pub fn new(
        index: &GroundIndex<'_>,
        length: f64,
        point: impl Fn(f64) -> DVec3,
    ) -> Result<GroundProfile, f64> {
        let n = (length / SAMPLE_STEP).ceil().max(1.0) as usize;
        let step = length / n as f64;
        let raw = (0..=n)
            .map(|i| {
                let s = i as f64 * step;
                index.height(point(s).truncate().as_vec2()).ok_or(s)
            })
            .collect::<Result<Vec<f64>, f64>>()?;
        let half = if step > 0.0 {
            (SMOOTHING / step).round() as isize
        } else {
            0
        };
        let heights = (0..raw.len() as isize)
            .map(|i| {
                let (a, b) = ((i - half).max(0), (i + half).min(raw.len() as isize - 1));
                let window = &raw[a as usize..=b as usize];
                window.iter().sum::<f64>() / window.len() as f64
            })
            .collect();
        Ok(GroundProfile { step, heights })
    }

    /// The smoothed ground height at arc length `s` (linear between samples).
    pub fn at(&self, s: f64) -> f64 {
        if self.step <= 0.0 || self.heights.len() < 2 {
            return self.heights[0];
        }
        let x = (s / self.step).clamp(0.0, (self.heights.len() - 1) as f64);
        let i = (x.floor() as usize).min(self.heights.len() - 2);
        let f = x - i as f64;
        self.heights[i] * (1.0 - f) + self.heights[i + 1] * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ground rising 0.1 m per metre along x over a 200 m square, 0.5 m point spacing.
    fn slope() -> Scene {
        let mut pts = Vec::new();
        for i in 0..400 {
            for j in 0..400 {
                let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
                pts.push(Vec3::new(x, y, 0.1 * x));
            }
        }
        Scene::new(DVec3::ZERO, pts, 0.1)
    }

    #[test]
    fn the_indexed_estimate_is_the_estimators() {
        let scene = slope();
        let index = GroundIndex::new(&scene);
        let (lo, hi) = scene.bounds().unwrap();
        let extent = (hi.truncate() - lo.truncate()).max_element();
        for xy in [Vec2::new(50.0, 50.0), Vec2::new(120.5, 10.0)] {
            let full = placement::ground_height(&scene, xy, extent).unwrap();
            assert_eq!(index.height(xy), Some(full));
            assert!((full - 0.1 * f64::from(xy.x)).abs() < 0.3, "{full}");
        }
    }

    #[test]
    fn the_profile_follows_a_slope_and_smooths_a_step() {
        let scene = slope();
        let index = GroundIndex::new(&scene);
        // Along x from 20 to 180 m at y = 100.
        let profile =
            GroundProfile::new(&index, 160.0, |s| DVec3::new(20.0 + s, 100.0, 0.0)).unwrap();
        for s in [0.0, 55.0, 160.0] {
            let want = 0.1 * (20.0 + s);
            assert!((profile.at(s) - want).abs() < 0.3, "{s}: {}", profile.at(s));
        }
        let e = GroundProfile::new(&index, 50.0, |s| DVec3::new(500.0 + s, 0.0, 0.0));
        assert_eq!(e.err(), Some(0.0));
    }
}
