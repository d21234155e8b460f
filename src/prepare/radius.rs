//! Sphere radii: the `--radius` rule, and the automatic radius from the point spacing.
//!
//! The spacing is the median distance from a point to its nearest distinct neighbour. Half
//! of it is the default radius: spheres of neighbouring points then just touch, so sampled
//! surfaces close without bloating thin features (a larger radius thickens edges and
//! wires; a smaller one lets the background show through).
//!
//! The estimate takes bounded time whatever the cloud size: at most [`MAX_QUERIES`] points
//! (an even stride through the cloud) look up their neighbour in a spatial hash grid over
//! all points, which costs O(n) to build.

use std::collections::HashMap;
use std::str::FromStr;

use glam::{IVec3, Vec3};
use rayon::prelude::*;

use crate::io::LoadOptions;
use crate::scene::{Radii, Scene};

/// A sphere radius choice (`--radius`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RadiusChoice {
    /// One radius for every point, metres.
    Fixed(f32),
    /// Half the median nearest-neighbour spacing ([`auto_radius`]).
    Auto,
}

/// `M` metres (positive) or `auto`.
impl FromStr for RadiusChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("auto") {
            return Ok(RadiusChoice::Auto);
        }
        let v = crate::value::positive_metres(s).map_err(|e| format!("{e} (or `auto`)"))?;
        Ok(RadiusChoice::Fixed(v as f32))
    }
}

/// The radii [`apply_choice`] gave a scene, for sizing later points of the same file alike.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusRule {
    /// Radius of every point without a radius of its own, metres.
    pub radius: f32,
    /// The file's per-point radii are kept.
    pub keep_file_radii: bool,
}

/// Sizes the spheres of a freshly loaded `scene`: a fixed radius; `auto` ([`auto_radius`]);
/// or, with no choice, the file's per-point radii when the scene has them, else `auto`.
pub fn apply_choice(scene: &mut Scene, choice: Option<RadiusChoice>) -> RadiusRule {
    let (radius, keep_file_radii) = match choice {
        Some(RadiusChoice::Fixed(r)) => (r, false),
        // The loader gave invalid per-point radii its default radius.
        None if matches!(scene.radii, Radii::PerPoint(_)) => {
            (LoadOptions::default().default_radius, true)
        }
        Some(RadiusChoice::Auto) | None => (auto_radius(scene), false),
    };
    if !keep_file_radii {
        scene.radii = Radii::Uniform(radius);
    }
    RadiusRule {
        radius,
        keep_file_radii,
    }
}

/// Most points whose nearest neighbour is searched.
pub const MAX_QUERIES: usize = 100_000;

/// Grid cells searched around a query, in rings, before giving it up as isolated.
const MAX_RINGS: i32 = 6;

/// Target mean number of points per occupied grid cell.
const TARGET_OCCUPANCY: f64 = 4.0;

/// Median nearest-neighbour distance between distinct points (metres), or `None` when the
/// scene has fewer than two distinct finite points or no query finds a neighbour.
/// Duplicated points count once: LiDAR files often repeat points, and a zero
/// spacing would give zero-sized spheres.
pub fn median_spacing(scene: &Scene) -> Option<f32> {
    let points = distinct_finite(&scene.positions);
    if points.len() < 2 {
        return None;
    }
    let grid = Grid::build(&points)?;
    let stride = points.len().div_ceil(MAX_QUERIES).max(1);
    let mut distances: Vec<f32> = (0..points.len())
        .into_par_iter()
        .step_by(stride)
        .filter_map(|i| grid.nearest_distinct(&points, points[i]))
        .collect();
    if distances.is_empty() {
        return None;
    }
    let mid = distances.len() / 2;
    let (_, median, _) = distances.select_nth_unstable_by(mid, f32::total_cmp);
    Some(*median)
}

/// Half the median spacing ([`median_spacing`]), the default sphere radius; 0.05 m when the
/// spacing cannot be estimated (a lone point, or all points equal).
pub fn auto_radius(scene: &Scene) -> f32 {
    radius_for_spacing(median_spacing(scene))
}

/// The auto radius for an already measured [`median_spacing`]: half of it, or
/// [`FALLBACK_RADIUS`] when there is none.
pub fn radius_for_spacing(spacing: Option<f32>) -> f32 {
    spacing.map_or(FALLBACK_RADIUS, |s| 0.5 * s)
}

/// Radius used when no spacing can be measured.
pub const FALLBACK_RADIUS: f32 = 0.05;

/// Points bucketed by cubic cell: cell key to a run of `order`.
struct Grid {
    cell: f32,
    origin: Vec3,
    runs: HashMap<IVec3, (u32, u32)>,
    order: Vec<u32>,
}

impl Grid {
    /// A grid whose cell size gives a few points per occupied cell. The first guess assumes
    /// points fill their bounding box; scans sample surfaces, so the size is refined from the
    /// measured occupancy as if the points were two-dimensional.
    fn build(points: &[Vec3]) -> Option<Grid> {
        let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
        let extent = (hi - lo).as_dvec3();
        let longest = extent.max_element();
        if longest <= 0.0 {
            return None;
        }
        let floor = longest * 1e-6;
        let volume = extent.max(glam::DVec3::splat(floor));
        let mut cell = (volume.x * volume.y * volume.z / points.len() as f64).cbrt();
        // Bisection in log scale between cells known to be too small and too large.
        let (mut small, mut large) = (None::<f64>, None::<f64>);
        for _ in 0..12 {
            let occupancy = points.len() as f64 / count_cells(points, lo, cell as f32) as f64;
            if (0.5 * TARGET_OCCUPANCY..=4.0 * TARGET_OCCUPANCY).contains(&occupancy) {
                break;
            }
            if occupancy < 0.5 * TARGET_OCCUPANCY {
                small = Some(cell);
            } else {
                large = Some(cell);
            }
            cell = match (small, large) {
                (Some(s), Some(l)) => (s * l).sqrt(),
                (Some(s), None) => 4.0 * s,
                (_, Some(l)) => 0.25 * l,
                (None, None) => unreachable!("one bound was just set"),
            };
        }
        let cell = (cell as f32).max(f32::MIN_POSITIVE);
        let keys: Vec<IVec3> = points.iter().map(|p| key(*p, lo, cell)).collect();
        let mut runs: HashMap<IVec3, (u32, u32)> = HashMap::new();
        for k in &keys {
            runs.entry(*k).or_insert((0, 0)).1 += 1;
        }
        let mut start = 0u32;
        for run in runs.values_mut() {
            run.0 = start;
            start += run.1;
            run.1 = run.0;
        }
        let mut order = vec![0u32; points.len()];
        for (i, k) in keys.iter().enumerate() {
            let run = runs.get_mut(k).expect("key counted above");
            order[run.1 as usize] = i as u32;
            run.1 += 1;
        }
        // Second field back from "fill cursor" to "length".
        for run in runs.values_mut() {
            run.1 -= run.0;
        }
        Some(Grid {
            cell,
            origin: lo,
            runs,
            order,
        })
    }

    /// Distance from `q` to its nearest point at a non-zero distance, searched ring by ring
    /// until no unsearched cell can hold anything nearer.
    fn nearest_distinct(&self, points: &[Vec3], q: Vec3) -> Option<f32> {
        let center = key(q, self.origin, self.cell);
        let mut best = f32::INFINITY;
        for ring in 0..=MAX_RINGS {
            for dz in -ring..=ring {
                for dy in -ring..=ring {
                    for dx in -ring..=ring {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                            continue;
                        }
                        let Some(&(start, len)) = self.runs.get(&(center + IVec3::new(dx, dy, dz)))
                        else {
                            continue;
                        };
                        for &i in &self.order[start as usize..(start + len) as usize] {
                            let d = points[i as usize].distance_squared(q);
                            if d > 0.0 && d < best {
                                best = d;
                            }
                        }
                    }
                }
            }
            // Every point outside rings 0..=ring is farther than `ring` whole cells.
            let searched = ring as f32 * self.cell;
            if best <= searched * searched {
                break;
            }
        }
        best.is_finite().then(|| best.sqrt())
    }
}

/// The finite points without exact duplicates (which would fool the grid's occupancy).
fn distinct_finite(positions: &[Vec3]) -> Vec<Vec3> {
    let mut bits: Vec<[u32; 3]> = positions
        .par_iter()
        .filter(|p| p.is_finite())
        // +0.0 for -0.0, so equal coordinates have equal bits.
        .map(|p| (*p + Vec3::ZERO).to_array().map(f32::to_bits))
        .collect();
    bits.par_sort_unstable();
    bits.dedup();
    bits.into_iter()
        .map(|b| Vec3::from_array(b.map(f32::from_bits)))
        .collect()
}

#[inline]
fn key(p: Vec3, origin: Vec3, cell: f32) -> IVec3 {
    ((p - origin) / cell).floor().as_ivec3()
}

/// Number of occupied cells of size `cell`.
fn count_cells(points: &[Vec3], origin: Vec3, cell: f32) -> usize {
    let mut keys: Vec<IVec3> = points.par_iter().map(|p| key(*p, origin, cell)).collect();
    keys.par_sort_unstable_by_key(|k| (k.x, k.y, k.z));
    keys.dedup();
    keys.len().max(1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn grid_scene(nx: usize, ny: usize, nz: usize, spacing: f32) -> Scene {
        let mut pts = Vec::new();
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    pts.push(Vec3::new(x as f32, y as f32, z as f32) * spacing);
                }
            }
        }
        Scene::new(DVec3::ZERO, pts, 0.1)
    }

    #[test]
    fn regular_plane_grid_gives_its_spacing() {
        let s = median_spacing(&grid_scene(300, 200, 1, 0.25)).unwrap();
        assert!((s - 0.25).abs() < 1e-5, "spacing {s}");
        assert!((auto_radius(&grid_scene(300, 200, 1, 0.25)) - 0.125).abs() < 1e-5);
    }

    #[test]
    fn regular_volume_grid_and_a_line_give_their_spacing() {
        let s = median_spacing(&grid_scene(40, 40, 40, 0.1)).unwrap();
        assert!((s - 0.1).abs() < 1e-5, "spacing {s}");
        let s = median_spacing(&grid_scene(5000, 1, 1, 0.02)).unwrap();
        assert!((s - 0.02).abs() < 1e-4, "spacing {s}");
    }

    #[test]
    fn large_cloud_is_sampled_and_duplicates_are_skipped() {
        let mut scene = grid_scene(700, 700, 1, 0.05);
        let copy = scene.positions.clone();
        scene.positions.extend(copy);
        let s = median_spacing(&scene).unwrap();
        assert!((s - 0.05).abs() < 1e-5, "spacing {s}");
    }

    #[test]
    fn choices_parse_as_metres_or_auto() {
        assert_eq!("AUTO".parse(), Ok(RadiusChoice::Auto));
        assert_eq!("0.25".parse(), Ok(RadiusChoice::Fixed(0.25)));
        for bad in ["-1", "0", "x", "inf"] {
            let e = bad.parse::<RadiusChoice>().unwrap_err();
            assert!(e.ends_with("(or `auto`)"), "{bad}: {e}");
        }
    }

    #[test]
    fn the_rule_keeps_file_radii_only_without_a_choice() {
        let mut scene = grid_scene(20, 20, 1, 0.5);
        scene.radii = Radii::PerPoint(vec![0.3; scene.len()]);
        let kept = apply_choice(&mut scene.clone(), None);
        assert!(kept.keep_file_radii);
        let fixed = apply_choice(&mut scene, Some(RadiusChoice::Fixed(0.1)));
        assert_eq!((fixed.radius, fixed.keep_file_radii), (0.1, false));
        assert_eq!(scene.radii, Radii::Uniform(0.1));
        let auto = apply_choice(&mut scene, None);
        assert!((auto.radius - 0.25).abs() < 1e-5 && scene.radii == Radii::Uniform(auto.radius));
    }

    #[test]
    fn degenerate_scenes_fall_back() {
        let one = Scene::new(DVec3::ZERO, vec![Vec3::ONE], 0.1);
        assert_eq!(median_spacing(&one), None);
        assert_eq!(auto_radius(&one), FALLBACK_RADIUS);
        let same = Scene::new(DVec3::ZERO, vec![Vec3::ONE; 10], 0.1);
        assert_eq!(median_spacing(&same), None);
    }
}
