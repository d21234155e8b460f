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
//!
//! `adaptive[:K]` gives each point its own radius from its K nearest neighbours
//! ([`adaptive_radii`]): sparse regions close while dense ones stay sharp.

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
    /// Each point's own radius from its `k` nearest neighbours ([`adaptive_radii`]).
    Adaptive {
        /// Neighbours counted.
        k: usize,
    },
}

impl RadiusChoice {
    /// The same choice with a fixed radius times `factor` (positive): given in another unit
    /// of length. `auto` and `adaptive` follow the points and stay as they are.
    pub fn scaled(self, factor: f64) -> RadiusChoice {
        match self {
            RadiusChoice::Fixed(r) => RadiusChoice::Fixed((f64::from(r) * factor) as f32),
            other => other,
        }
    }
}

/// `M` metres (positive), `auto`, or `adaptive[:K]` (K from 1 to [`MAX_K`]).
impl FromStr for RadiusChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("auto") {
            return Ok(RadiusChoice::Auto);
        }
        let lower = t.to_ascii_lowercase();
        if let Some(rest) = lower.strip_prefix("adaptive") {
            let k = match rest.strip_prefix(':') {
                None if rest.is_empty() => DEFAULT_K,
                Some(k) => k
                    .trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|k| (1..=MAX_K).contains(k))
                    .ok_or_else(|| {
                        format!("adaptive:K needs K, the neighbours counted, from 1 to {MAX_K}; got `{s}`")
                    })?,
                None => return Err(format!("expected `adaptive` or `adaptive:K`, got `{s}`")),
            };
            return Ok(RadiusChoice::Adaptive { k });
        }
        let v = crate::value::positive_metres(s)
            .map_err(|e| format!("{e} (or `auto`, `adaptive[:K]`)"))?;
        Ok(RadiusChoice::Fixed(v as f32))
    }
}

/// As `--radius` spells it (parses back to the same choice).
impl std::fmt::Display for RadiusChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RadiusChoice::Fixed(v) => write!(f, "{v}"),
            RadiusChoice::Auto => f.write_str("auto"),
            RadiusChoice::Adaptive { k } => write!(f, "adaptive:{k}"),
        }
    }
}

/// Neighbours `adaptive` counts without `:K`: 8 rings a point of a square grid with its 4
/// edge and 4 diagonal neighbours, so the estimate sees the local surface, not one scan line.
pub const DEFAULT_K: usize = 8;

/// Most neighbours `adaptive:K` may count.
pub const MAX_K: usize = 64;

/// Adaptive radii are clamped to this many times the median adaptive radius: an isolated
/// outlier stays a point instead of a sphere as large as its distance to the cloud.
pub const ADAPTIVE_MAX: f32 = 3.0;

/// Adaptive radii are clamped to at least this share of the median adaptive radius: repeated
/// points (distance 0) keep a visible sphere.
pub const ADAPTIVE_MIN: f32 = 0.25;

/// Per-point sphere radii from each point's `k` nearest neighbours (the point itself not
/// counted), in `positions` order; `None` with fewer than two distinct points.
///
/// The `k` neighbours lie within the distance d_k to the k-th of them, so each point's share
/// of that disc of the surface has area π·d_k²/k: its radius is the radius of that share,
/// d_k/√k. On a regular grid of spacing s, d_8 = √2·s gives s/2, the `auto` radius; where the
/// sampling thins, the radius grows with it. Radii are clamped to [[`ADAPTIVE_MIN`],
/// [`ADAPTIVE_MAX`]] times their median.
pub fn adaptive_radii(positions: &[Vec3], k: usize) -> Option<Vec<f32>> {
    adaptive_radii_from(positions, 0, k)
}

/// [`adaptive_radii`] of the points `positions[from..]` among all of `positions`: their
/// neighbours are searched in the whole set, and the clamp follows their own median. An
/// index sizes the points of a level this way among the points drawn with them.
pub fn adaptive_radii_from(positions: &[Vec3], from: usize, k: usize) -> Option<Vec<f32>> {
    let points: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| {
            if p.is_finite() {
                p.to_array()
            } else {
                [0.0; 3]
            }
        })
        .collect();
    if points.len() < 2 || k == 0 || from >= points.len() {
        return None;
    }
    let k = k.min(points.len() - 1);
    let mut radii = super::knn::kth_distances2(&points, from, k);
    for r in &mut radii {
        *r = r.sqrt() / (k as f32).sqrt();
    }
    let mut positive: Vec<f32> = radii.iter().copied().filter(|r| *r > 0.0).collect();
    if positive.is_empty() {
        return None;
    }
    let mid = positive.len() / 2;
    let median = *positive.select_nth_unstable_by(mid, f32::total_cmp).1;
    let (lo, hi) = (ADAPTIVE_MIN * median, ADAPTIVE_MAX * median);
    for r in &mut radii {
        *r = r.clamp(lo, hi);
    }
    Some(radii)
}

/// The radii [`apply_choice`] gave a scene, for sizing later points of the same file alike.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusRule {
    /// Radius of every point without a radius of its own, metres.
    pub radius: f32,
    /// The file's per-point radii are kept.
    pub keep_file_radii: bool,
    /// Per-point radii from this many nearest neighbours ([`adaptive_radii`]); `radius` is
    /// then their median.
    pub adaptive: Option<usize>,
}

impl RadiusRule {
    /// How the summaries say it, lengths in `unit`: `0.4000 ft`, `adaptive:8 (median 1.2154
    /// ft)` or `per point` (the file's radii).
    pub fn describe(&self, unit: &str) -> String {
        match (self.keep_file_radii, self.adaptive) {
            (true, _) => "per point".into(),
            (false, Some(k)) => format!("adaptive:{k} (median {:.4} {unit})", self.radius),
            (false, None) => format!("{:.4} {unit}", self.radius),
        }
    }
}

/// Sizes the spheres of a freshly loaded `scene`: a fixed radius; `auto` ([`auto_radius`]);
/// `adaptive` ([`adaptive_radii`]); or, with no choice, the file's per-point radii when the
/// scene has them, else `adaptive` with [`DEFAULT_K`] neighbours.
pub fn apply_choice(scene: &mut Scene, choice: Option<RadiusChoice>) -> RadiusRule {
    // Without a choice or file radii: adaptive, which leaves fewer holes than `auto` (see
    // docs/PICTURES.md).
    let choice = match choice {
        None if !matches!(scene.radii, Radii::PerPoint(_)) => {
            Some(RadiusChoice::Adaptive { k: DEFAULT_K })
        }
        c => c,
    };
    if let Some(RadiusChoice::Adaptive { k }) = choice
        && let Some(radii) = adaptive_radii(&scene.positions, k)
    {
        let mut sorted = radii.clone();
        let mid = sorted.len() / 2;
        let median = *sorted.select_nth_unstable_by(mid, f32::total_cmp).1;
        scene.radii = Radii::PerPoint(radii);
        return RadiusRule {
            radius: median,
            keep_file_radii: false,
            adaptive: Some(k),
        };
    }
    let (radius, keep_file_radii) = match choice {
        Some(RadiusChoice::Fixed(r)) => (r, false),
        // The loader gave invalid per-point radii its default radius.
        None if matches!(scene.radii, Radii::PerPoint(_)) => {
            (LoadOptions::default().default_radius, true)
        }
        // Adaptive on a scene too small for neighbours: the auto radius.
        Some(RadiusChoice::Auto | RadiusChoice::Adaptive { .. }) | None => {
            (auto_radius(scene), false)
        }
    };
    if !keep_file_radii {
        scene.radii = Radii::Uniform(radius);
    }
    RadiusRule {
        radius,
        keep_file_radii,
        adaptive: None,
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
            assert!(e.ends_with("(or `auto`, `adaptive[:K]`)"), "{bad}: {e}");
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
        // No choice, no file radii: adaptive, whose median on this grid is half the spacing.
        let default = apply_choice(&mut scene, None);
        assert!((default.radius - 0.25).abs() < 1e-5, "{}", default.radius);
        assert_eq!(default.adaptive, Some(DEFAULT_K));
        assert!(matches!(scene.radii, Radii::PerPoint(_)));
    }

    #[test]
    fn a_fixed_radius_scales_and_the_rules_stay() {
        let feet = 1.0 / 0.3048;
        assert_eq!(
            RadiusChoice::Fixed(0.4).scaled(feet),
            RadiusChoice::Fixed((f64::from(0.4f32) * feet) as f32)
        );
        assert_eq!(RadiusChoice::Auto.scaled(feet), RadiusChoice::Auto);
        let adaptive = RadiusChoice::Adaptive { k: 8 };
        assert_eq!(adaptive.scaled(feet), adaptive);
    }

    #[test]
    fn adaptive_choices_parse_and_print_back() {
        assert_eq!(
            "adaptive".parse(),
            Ok(RadiusChoice::Adaptive { k: DEFAULT_K })
        );
        assert_eq!("Adaptive:12".parse(), Ok(RadiusChoice::Adaptive { k: 12 }));
        for bad in [
            "adaptive:0",
            "adaptive:65",
            "adaptive:x",
            "adaptive:",
            "adaptivex",
        ] {
            let e = bad.parse::<RadiusChoice>().unwrap_err();
            assert!(e.contains("adaptive"), "{bad}: {e}");
        }
        for c in [
            RadiusChoice::Auto,
            RadiusChoice::Fixed(0.25),
            RadiusChoice::Adaptive { k: 5 },
        ] {
            assert_eq!(c.to_string().parse(), Ok(c));
        }
    }

    #[test]
    fn adaptive_radius_of_a_regular_grid_is_half_its_spacing() {
        let scene = grid_scene(60, 40, 1, 0.25);
        let radii = adaptive_radii(&scene.positions, DEFAULT_K).unwrap();
        // Away from the edges every point sees the same 8 neighbours: exactly s/2.
        let inner = (0..scene.len()).filter(|i| {
            let (x, y) = (i % 60, i / 60);
            (2..58).contains(&x) && (2..38).contains(&y)
        });
        for i in inner {
            assert!((radii[i] - 0.125).abs() < 1e-5, "point {i}: {}", radii[i]);
        }
        // Edges and corners see farther neighbours, within the clamp.
        assert!(
            radii
                .iter()
                .all(|r| (0.125..=0.125 * ADAPTIVE_MAX + 1e-6).contains(r))
        );
    }

    #[test]
    fn adaptive_radius_grows_where_sampling_thins_and_clamps_outliers() {
        // A dense grid (0.1 m) beside a sparse one (0.25 m), and one far outlier.
        let mut pts: Vec<Vec3> = grid_scene(50, 50, 1, 0.1).positions;
        pts.extend(
            grid_scene(20, 20, 1, 0.25)
                .positions
                .iter()
                .map(|p| *p + Vec3::new(20.0, 0.0, 0.0)),
        );
        pts.push(Vec3::new(500.0, 500.0, 50.0));
        let radii = adaptive_radii(&pts, DEFAULT_K).unwrap();
        let dense = radii[25 * 50 + 25];
        let sparse = radii[2500 + 10 * 20 + 10];
        assert!((dense - 0.05).abs() < 1e-5, "{dense}");
        assert!((sparse - 0.125).abs() < 1e-5, "{sparse}");
        // The median is the dense radius: the outlier gets at most 3 times it.
        let outlier = *radii.last().unwrap();
        assert!((outlier - ADAPTIVE_MAX * 0.05).abs() < 1e-5, "{outlier}");
        // Repeated points keep a quarter of the median.
        let mut dup = grid_scene(30, 30, 1, 0.2).positions;
        dup.extend(vec![Vec3::new(1.0, 1.0, 0.0); 20]);
        let radii = adaptive_radii(&dup, DEFAULT_K).unwrap();
        assert!((radii.last().unwrap() - ADAPTIVE_MIN * 0.1).abs() < 1e-5);
    }

    #[test]
    fn adaptive_rule_gives_per_point_radii_and_their_median() {
        let mut scene = grid_scene(30, 30, 1, 0.2);
        let rule = apply_choice(&mut scene, Some(RadiusChoice::Adaptive { k: 8 }));
        assert_eq!(rule.adaptive, Some(8));
        assert!((rule.radius - 0.1).abs() < 1e-5, "{}", rule.radius);
        assert!(matches!(scene.radii, Radii::PerPoint(ref r) if r.len() == 900));
        // Too few points for neighbours: the auto radius.
        let mut one = Scene::new(DVec3::ZERO, vec![Vec3::ONE], 0.1);
        let rule = apply_choice(&mut one, Some(RadiusChoice::Adaptive { k: 8 }));
        assert_eq!((rule.radius, rule.adaptive), (FALLBACK_RADIUS, None));
    }

    #[test]
    fn degenerate_scenes_fall_back() {
        let one = Scene::new(DVec3::ZERO, vec![Vec3::ONE], 0.1);
        assert_eq!(median_spacing(&one), None);
        assert_eq!(auto_radius(&one), FALLBACK_RADIUS);
        let same = Scene::new(DVec3::ZERO, vec![Vec3::ONE; 10], 0.1);
        assert_eq!(median_spacing(&same), None);
    }

    #[test]
    fn rules_describe_themselves_in_the_files_unit() {
        let rule = |keep_file_radii, adaptive| RadiusRule {
            radius: 0.4,
            keep_file_radii,
            adaptive,
        };
        assert_eq!(rule(false, None).describe("ft"), "0.4000 ft");
        assert_eq!(
            rule(false, Some(8)).describe("m"),
            "adaptive:8 (median 0.4000 m)"
        );
        assert_eq!(rule(true, None).describe("m"), "per point");
    }
}
