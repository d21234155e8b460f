//! The distance from each point to its k-th nearest neighbour, exact, on a uniform grid.
//!
//! The points are sorted into cubic cells sized from their density (a few points per occupied
//! cell, taking the points as samples of surfaces). Each cell's points measure their distances
//! to the points of the 3 × 3 × 3 cells around it: that settles every point whose k-th
//! distance is no longer than the way out of that block. The others (scan edges, lone points)
//! search the cells covering the ball their candidates bound, or, when that is far or they
//! found too few candidates, a k-d tree (`kiddo`). The grid sums a distance's squared axes in
//! the k-d tree's order, so both give the same bits: the grid only decides faster.

use std::ops::Range;

use glam::DVec3;
use rayon::prelude::*;

/// Mean points per occupied cell the cell size aims at, per neighbour wanted: the 3 × 3 × 3
/// block around a surface point then holds several times the neighbours it needs.
const OCCUPANCY_PER_NEIGHBOUR: f64 = 0.5;
/// Points the cell size is first estimated on.
const SAMPLE: usize = 1 << 16;
/// Bits of one axis in a cell key.
const AXIS_BITS: u32 = 21;
/// Cells along one axis at most (a key's axis also holds one cell of padding on each side).
const MAX_CELLS: f64 = ((1u64 << AXIS_BITS) - 4) as f64;
/// Rows of cells a point left unsettled by its block may search before the k-d tree takes it.
const MAX_ROWS: usize = 256;
/// Cells handed to one task.
const CELLS_PER_TASK: usize = 2048;
/// Relative slack for rounding when deciding that no point beyond a bound can be nearer.
const SLACK: f64 = 1e-5;

/// Squared distance, summed axis by axis from zero as `kiddo`'s `SquaredEuclidean` sums it.
#[inline(always)]
fn distance2(a: &[f32; 3], b: &[f32; 3]) -> f32 {
    let mut d = 0.0f32;
    for axis in 0..3 {
        let t = a[axis] - b[axis];
        d += t * t;
    }
    d
}

/// For each point `points[from..]`: the squared distance to its `k + 1`-th nearest point of
/// `points`, itself counted (so to its `k`-th neighbour; repeated points count each time).
///
/// # Panics
/// When `points` holds `k` points or fewer, or a coordinate is not finite.
pub fn kth_distances2(points: &[[f32; 3]], from: usize, k: usize) -> Vec<f32> {
    kth_with_paths(points, from, k).0
}

/// How many points each search settled.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Paths {
    /// By their 3 × 3 × 3 block of cells.
    block: usize,
    /// By the cells covering their candidates' ball.
    ball: usize,
    /// By the k-d tree.
    tree: usize,
}

/// [`kth_distances2`], and how many points each search settled.
fn kth_with_paths(points: &[[f32; 3]], from: usize, k: usize) -> (Vec<f32>, Paths) {
    let wanted = k + 1;
    assert!(
        points.len() >= wanted,
        "{} points, {k} neighbours",
        points.len()
    );
    assert!(
        points.iter().flatten().all(|v| v.is_finite()),
        "non-finite coordinate"
    );
    let mut paths = Paths::default();
    if from >= points.len() {
        return (Vec::new(), paths);
    }
    let grid = Grid::new(points, (wanted as f64 * OCCUPANCY_PER_NEIGHBOUR).max(2.0));
    let mut found = vec![f32::NAN; points.len()];
    let tasks: Vec<Range<usize>> = (0..grid.keys.len())
        .step_by(CELLS_PER_TASK)
        .map(|a| a..(a + CELLS_PER_TASK).min(grid.keys.len()))
        .collect();
    let per_task: Vec<Settled> = tasks
        .into_par_iter()
        .map(|cells| grid.settle(cells, from, wanted))
        .collect();
    let mut unsettled = Vec::new();
    for task in per_task {
        paths.block += task.by_block;
        paths.ball += task.found.len() - task.by_block;
        for (i, d) in task.found {
            found[i as usize] = d;
        }
        unsettled.extend(task.left);
    }
    paths.tree = unsettled.len();
    if !unsettled.is_empty() {
        for (i, d) in unsettled
            .iter()
            .zip(kd_tree_kth(points, &unsettled, wanted))
        {
            found[*i as usize] = d;
        }
    }
    (found.split_off(from), paths)
}

/// What one task of cells settled.
struct Settled {
    /// `(input index, squared distance)` of each point settled.
    found: Vec<(u32, f32)>,
    /// How many of them their block settled.
    by_block: usize,
    /// Input indices of the points left to the k-d tree.
    left: Vec<u32>,
}

/// The squared distance to the `wanted`-th nearest point of `points` for the points
/// `queries` (indices), from a k-d tree.
fn kd_tree_kth(points: &[[f32; 3]], queries: &[u32], wanted: usize) -> Vec<f32> {
    let tree = kiddo::ImmutableKdTree::<f32, 3>::new_from_slice(points)
        .expect("a slice's indices fit the tree's item type");
    let wanted = std::num::NonZero::new(wanted).expect("wanted > 0");
    queries
        .par_iter()
        .map(|i| {
            let near = tree
                .query(&points[*i as usize])
                .nearest_n::<kiddo::SquaredEuclidean<f32>>(wanted)
                .execute();
            near.last().map_or(f32::INFINITY, |n| n.distance)
        })
        .collect()
}

/// Points sorted into occupied cells.
struct Grid {
    /// Low corner of the cell with index 1 on every axis (index 0 is padding).
    origin: DVec3,
    /// Side of a cell.
    cell: f64,
    /// Occupied cells' keys, ascending.
    keys: Vec<u64>,
    /// Where each cell's points start in `by_axis`, and the end after the last.
    starts: Vec<u32>,
    /// The points, cell by cell, axis by axis (so that a block copies whole rows of cells).
    by_axis: [Vec<f32>; 3],
    /// Each sorted point's index in the input.
    index: Vec<u32>,
}

/// Key step of one cell along y and z (x is the lowest field).
const Y: u64 = 1 << AXIS_BITS;
const Z: u64 = 1 << (2 * AXIS_BITS);

fn pack(c: [u64; 3]) -> u64 {
    c[0] | c[1] << AXIS_BITS | c[2] << (2 * AXIS_BITS)
}

impl Grid {
    /// A grid of about `occupancy` points per occupied cell.
    fn new(points: &[[f32; 3]], occupancy: f64) -> Grid {
        let (lo, hi) = bounds(points);
        let longest = (hi - lo).max_element();
        let least = (longest / MAX_CELLS).max(f64::MIN_POSITIVE);
        let mut cell = estimate_cell(points, lo, hi, occupancy).max(least);
        let mut grid = Grid::with_cell(points, lo, cell);
        // The estimate took the points for surfaces; lines or volumes correct it once.
        let found = points.len() as f64 / grid.keys.len() as f64;
        if !(occupancy / 3.0..=occupancy * 3.0).contains(&found) && longest > 0.0 {
            cell = (cell * (occupancy / found).sqrt()).max(least);
            grid = Grid::with_cell(points, lo, cell);
        }
        grid
    }

    fn with_cell(points: &[[f32; 3]], lo: DVec3, cell: f64) -> Grid {
        let origin = lo - DVec3::splat(cell);
        let mut keyed: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(i, p)| (key_of(p, origin, cell), i as u32))
            .collect();
        keyed.par_sort_unstable();
        let mut keys = Vec::new();
        let mut starts = Vec::new();
        for (at, (key, _)) in keyed.iter().enumerate() {
            if keys.last() != Some(key) {
                keys.push(*key);
                starts.push(at as u32);
            }
        }
        starts.push(keyed.len() as u32);
        let index: Vec<u32> = keyed.iter().map(|(_, i)| *i).collect();
        let by_axis =
            std::array::from_fn(|a| index.iter().map(|i| points[*i as usize][a]).collect());
        Grid {
            origin,
            cell,
            keys,
            starts,
            by_axis,
            index,
        }
    }

    /// Settles the points of `cells` from their 3 × 3 × 3 blocks, else their balls.
    fn settle(&self, cells: Range<usize>, from: usize, wanted: usize) -> Settled {
        let mut settled = Vec::new();
        let mut by_block = 0;
        let mut left = Vec::new();
        let mut best = vec![f32::INFINITY; wanted];
        // One cursor per row of the block (dy, dz): the rows' first keys grow with the cell's.
        let mut cursors = [0usize; 9];
        // The cell's own row first: its near candidates make later ones fail the first test.
        let offsets: [u64; 9] = std::array::from_fn(|r| {
            let r = (r + 4) % 9;
            (r % 3) as u64 * Y + (r / 3) as u64 * Z
        });
        let first = self.keys[cells.start] - 1 - Y - Z;
        for (cursor, offset) in cursors.iter_mut().zip(offsets) {
            *cursor = self.keys.partition_point(|k| *k < first + offset);
        }
        let mut rows: [Range<usize>; 9] = Default::default();
        let mut block = Block::default();
        for c in cells {
            let key = self.keys[c];
            let points = self.starts[c] as usize..self.starts[c + 1] as usize;
            if !self.index[points.clone()]
                .iter()
                .any(|i| *i as usize >= from)
            {
                continue;
            }
            let row_start = key - 1 - Y - Z;
            for ((cursor, offset), row) in cursors.iter_mut().zip(offsets).zip(&mut rows) {
                let (a, b) = (row_start + offset, row_start + offset + 2);
                while self.keys.get(*cursor).is_some_and(|k| *k < a) {
                    *cursor += 1;
                }
                let mut end = *cursor;
                while self.keys.get(end).is_some_and(|k| *k <= b) {
                    end += 1;
                }
                *row = self.starts[*cursor] as usize..self.starts[end] as usize;
            }
            block.gather(&self.by_axis, &rows);
            let block_low = self.low_corner(key) - DVec3::splat(self.cell);
            let block_high = block_low + DVec3::splat(3.0 * self.cell);
            for at in points {
                let i = self.index[at];
                if (i as usize) < from {
                    continue;
                }
                let q = &self.point(at);
                let kth = block.kth(q, &mut best);
                let qd = DVec3::from_array(q.map(f64::from));
                let way_out = (qd - block_low).min(block_high - qd).min_element();
                if f64::from(kth) <= way_out * way_out * (1.0 - SLACK) {
                    settled.push((i, kth));
                    by_block += 1;
                } else if let Some(d) = self.search_ball(q, kth, &mut best) {
                    settled.push((i, d));
                } else {
                    left.push(i);
                }
            }
        }
        Settled {
            found: settled,
            by_block,
            left,
        }
    }

    /// The `best.len()`-th squared distance from `q` among every point of the cells covering
    /// the ball of squared radius `bound` (which holds that many points); `None` when the
    /// bound is infinite or the ball spans more than [`MAX_ROWS`] rows of cells.
    fn search_ball(&self, q: &[f32; 3], bound: f32, best: &mut [f32]) -> Option<f32> {
        if !bound.is_finite() {
            return None;
        }
        let reach = f64::from(bound).sqrt() * (1.0 + SLACK) + f64::MIN_POSITIVE;
        let qd = DVec3::from_array(q.map(f64::from));
        let low = self.cell_of(qd - DVec3::splat(reach));
        let high = self.cell_of(qd + DVec3::splat(reach));
        let rows = (high[1] - low[1] + 1) * (high[2] - low[2] + 1);
        if rows as usize > MAX_ROWS {
            return None;
        }
        best.fill(f32::INFINITY);
        for z in low[2]..=high[2] {
            for y in low[1]..=high[1] {
                let a = self.keys.partition_point(|k| *k < pack([low[0], y, z]));
                let b = self.keys.partition_point(|k| *k <= pack([high[0], y, z]));
                let points = self.starts[a] as usize..self.starts[b] as usize;
                nearest(points.map(|at| self.point(at)), q, best);
            }
        }
        Some(best[best.len() - 1])
    }

    /// The sorted point `at`.
    fn point(&self, at: usize) -> [f32; 3] {
        self.by_axis.each_ref().map(|axis| axis[at])
    }

    /// Padded cell indices of `p`, clamped to the keys' range.
    fn cell_of(&self, p: DVec3) -> [u64; 3] {
        let c = ((p - self.origin) / self.cell).floor();
        let top = MAX_CELLS + 2.0;
        [c.x, c.y, c.z].map(|v| v.clamp(0.0, top) as u64)
    }

    /// Low corner of the cell `key`.
    fn low_corner(&self, key: u64) -> DVec3 {
        let mask = Y - 1;
        let c = [
            key & mask,
            (key >> AXIS_BITS) & mask,
            key >> (2 * AXIS_BITS),
        ];
        self.origin + DVec3::from_array(c.map(|v| v as f64)) * self.cell
    }
}

/// Candidates measured a lane group at a time.
const LANES: usize = 8;

/// The points of a cell's 3 × 3 × 3 block, axis by axis, padded to whole lane groups with
/// points at infinity (never nearer than anything), so that a query measures its distances
/// to them [`LANES`] at a time.
#[derive(Default)]
struct Block {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
}

impl Block {
    /// Takes the points of `rows` of the coordinates `by_axis`, in that order.
    fn gather(&mut self, by_axis: &[Vec<f32>; 3], rows: &[Range<usize>]) {
        let points: usize = rows.iter().map(ExactSizeIterator::len).sum();
        let padded = points.next_multiple_of(LANES);
        for (axis, from) in [&mut self.x, &mut self.y, &mut self.z]
            .into_iter()
            .zip(by_axis)
        {
            axis.clear();
            for r in rows {
                axis.extend_from_slice(&from[r.clone()]);
            }
            axis.resize(padded, f32::INFINITY);
        }
    }

    /// The `scratch.len()`-th smallest squared distance from `q` to the block's points:
    /// [`nearest`]'s distances, measured a lane group at a time, a group merged only when it
    /// holds one below the current bound. `scratch` holds the nearest when more are wanted
    /// than [`SHORT`].
    fn kth(&self, q: &[f32; 3], scratch: &mut [f32]) -> f32 {
        let wanted = scratch.len();
        if wanted > SHORT {
            scratch.fill(f32::INFINITY);
            self.merge(q, scratch, |b: &[f32]| b[wanted - 1], insert);
            return scratch[wanted - 1];
        }
        // A fixed array, merged without branches; its entries past `wanted` only ever hold
        // larger distances, so the bound is still entry `wanted - 1`.
        if wanted <= SHORTER {
            self.kth_short::<SHORTER>(q, wanted)
        } else {
            self.kth_short::<SHORT>(q, wanted)
        }
    }

    /// [`Self::kth`] for `wanted` at most `N`, kept in an `N`-entry array.
    #[inline(always)]
    fn kth_short<const N: usize>(&self, q: &[f32; 3], wanted: usize) -> f32 {
        let mut short = [f32::INFINITY; N];
        self.merge(q, &mut short, |b| b[wanted - 1], insert_short);
        short[wanted - 1]
    }

    /// Measures the block's points from `q` a lane group at a time and hands `merge` each
    /// distance of a group holding one below `bound` of the nearest so far.
    #[inline(always)]
    fn merge<S: ?Sized>(
        &self,
        q: &[f32; 3],
        nearest: &mut S,
        bound: impl Fn(&S) -> f32,
        mut merge: impl FnMut(f32, &mut S),
    ) {
        let groups = self
            .x
            .chunks_exact(LANES)
            .zip(self.y.chunks_exact(LANES))
            .zip(self.z.chunks_exact(LANES));
        for ((x, y), z) in groups {
            let d: [f32; LANES] = std::array::from_fn(|l| distance2(q, &[x[l], y[l], z[l]]));
            let last = bound(nearest);
            let mut any = false;
            for v in d {
                any |= v < last;
            }
            if any {
                for v in d {
                    merge(v, nearest);
                }
            }
        }
    }
}

/// Neighbours wanted up to which a query keeps its nearest in a fixed array.
const SHORT: usize = 16;
/// A smaller fixed array for the default neighbour count and below: less to merge.
const SHORTER: usize = 12;

/// [`insert`] into a fixed array, without branches: entry `i` becomes the smaller of itself
/// and the larger of its predecessor and `d`.
#[inline(always)]
fn insert_short<const N: usize>(d: f32, best: &mut [f32; N]) {
    let old = *best;
    let pick_min = |a: f32, b: f32| if a < b { a } else { b };
    let pick_max = |a: f32, b: f32| if a > b { a } else { b };
    best[0] = pick_min(old[0], d);
    for i in 1..N {
        best[i] = pick_min(old[i], pick_max(old[i - 1], d));
    }
}

/// Puts `d` into `best` (ascending) when it is below the last, dropping the last.
#[inline(always)]
fn insert(d: f32, best: &mut [f32]) {
    let last = best.len() - 1;
    if d < best[last] {
        let mut at = last;
        while at > 0 && best[at - 1] > d {
            best[at] = best[at - 1];
            at -= 1;
        }
        best[at] = d;
    }
}

/// Merges `candidates` into `best`, the ascending smallest squared distances from `q` so far.
#[inline]
fn nearest(candidates: impl IntoIterator<Item = [f32; 3]>, q: &[f32; 3], best: &mut [f32]) {
    for p in candidates {
        insert(distance2(q, &p), best);
    }
}

/// The key of the cell holding `p`.
#[inline]
fn key_of(p: &[f32; 3], origin: DVec3, cell: f64) -> u64 {
    // At least 1: the cells below the lowest point's stay empty padding. The quotient is
    // positive there, so truncation floors it.
    let axis = |v: f32, o: f64| ((f64::from(v) - o) / cell).clamp(1.0, MAX_CELLS + 2.0) as u64;
    pack([
        axis(p[0], origin.x),
        axis(p[1], origin.y),
        axis(p[2], origin.z),
    ])
}

fn bounds(points: &[[f32; 3]]) -> (DVec3, DVec3) {
    points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            let p = DVec3::from_array(p.map(f64::from));
            (lo.min(p), hi.max(p))
        })
}

/// A cell side giving about `target` points per occupied cell, estimated on an even sample
/// of at most [`SAMPLE`] points as if they sampled surfaces (occupancy grows with the cell's
/// area).
fn estimate_cell(points: &[[f32; 3]], lo: DVec3, hi: DVec3, target: f64) -> f64 {
    let extent = hi - lo;
    let longest = extent.max_element();
    if longest <= 0.0 {
        return 1.0;
    }
    let stride = points.len().div_ceil(SAMPLE).max(1);
    let sample: Vec<[f32; 3]> = points.iter().step_by(stride).copied().collect();
    let mut sides = extent.max(DVec3::splat(longest * 1e-6)).to_array();
    sides.sort_by(f64::total_cmp);
    let mut cell = (sides[1] * sides[2] / sample.len() as f64 * target).sqrt();
    let mut keys = Vec::with_capacity(sample.len());
    for _ in 0..12 {
        keys.clear();
        keys.extend(
            sample
                .iter()
                .map(|p| key_of(p, lo - DVec3::splat(cell), cell)),
        );
        keys.sort_unstable();
        keys.dedup();
        let occupancy = sample.len() as f64 / keys.len() as f64;
        if (target * 0.7..=target * 1.4).contains(&occupancy) {
            break;
        }
        cell *= (target / occupancy).sqrt().clamp(0.25, 4.0);
        cell = cell.clamp(longest / MAX_CELLS, longest);
    }
    // A sample `stride` times sparser: the same occupancy at a cell `√stride` times larger.
    cell / (stride as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{LoadOptions, load_scene};

    /// Every point's answer from the k-d tree alone, as the radii were decided before the grid.
    fn reference(points: &[[f32; 3]], from: usize, k: usize) -> Vec<f32> {
        let all: Vec<u32> = (from as u32..points.len() as u32).collect();
        kd_tree_kth(points, &all, k + 1)
    }

    fn same_bits(grid: &[f32], tree: &[f32]) {
        assert_eq!(grid.len(), tree.len());
        for (i, (g, t)) in grid.iter().zip(tree).enumerate() {
            assert_eq!(g.to_bits(), t.to_bits(), "point {i}: grid {g}, tree {t}");
        }
    }

    #[test]
    fn autzen_gives_the_k_d_trees_bits() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz");
        let (scene, _) = load_scene(&path, &LoadOptions::default()).unwrap();
        let points: Vec<[f32; 3]> = scene.positions.iter().map(|p| p.to_array()).collect();
        assert!(points.len() > 100_000, "{}", points.len());
        for (from, k) in [(0, 8), (0, 1), (0, 24), (points.len() / 3, 8)] {
            let (grid, paths) = kth_with_paths(&points, from, k);
            same_bits(&grid, &reference(&points, from, k));
            eprintln!("k {k}, from {from}: {paths:?}");
            // The grid settles nearly every point itself.
            let queries = (points.len() - from) as f64;
            assert!(paths.block as f64 > 0.9 * queries, "k {k}: {paths:?}");
        }
    }

    #[test]
    fn edges_lone_points_and_repeats_give_the_k_d_trees_bits() {
        // A plane 0.1 m apart, a sparse line off it, a far cluster, lone points, repeats.
        let mut points: Vec<[f32; 3]> = (0..200 * 200)
            .map(|i| [(i % 200) as f32 * 0.1, (i / 200) as f32 * 0.1, 0.0])
            .collect();
        points.extend((0..300).map(|i| [i as f32 * 0.37, -3.0, 1.0]));
        points.extend((0..20).map(|i| [500.0 + i as f32 * 0.01, 500.0, 80.0]));
        points.extend([[-400.0, 7.0, 3.0], [900.0, -900.0, -50.0]]);
        points.extend(vec![[5.0, 5.0, 0.0]; 30]);
        let mut ball = 0;
        for k in [1, 8, 11, 12, 15, 40] {
            let (grid, paths) = kth_with_paths(&points, 0, k);
            same_bits(&grid, &reference(&points, 0, k));
            // The lone points leave the grid for the tree.
            assert!(paths.tree >= 2, "k {k}: {paths:?}");
            ball += paths.ball;
        }
        assert!(ball > 0);
        // Repeated points: distance 0 up to the repeats' count.
        let d = kth_distances2(&points, points.len() - 1, 8);
        assert_eq!(d, vec![0.0]);
    }

    #[test]
    fn degenerate_sets_are_answered() {
        // All points equal; a straight line; the fewest points allowed.
        same_bits(&kth_distances2(&[[1.0; 3]; 50], 0, 8), &[0.0; 50]);
        let line: Vec<[f32; 3]> = (0..5000).map(|i| [i as f32 * 0.02, 0.0, 0.0]).collect();
        same_bits(&kth_distances2(&line, 0, 8), &reference(&line, 0, 8));
        let two = [[0.0, 0.0, 0.0], [3.0, 4.0, 0.0]];
        assert_eq!(kth_distances2(&two, 0, 1), vec![25.0, 25.0]);
        assert!(kth_distances2(&two, 2, 1).is_empty());
    }
}
