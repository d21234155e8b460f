//! One bucket's part of the octree, built in memory: points sampled into nodes from the root
//! down, and their radii decided.
//!
//! Sampling: a node keeps one point per cell of a [`GRID`]³ grid over its cube (the first in
//! input order, so the result is deterministic) and hands the rest to its children; a node
//! with at most [`LEAF_POINTS`] points left (or at [`MAX_INDEX_DEPTH`]) keeps them all. A
//! node at depth `d` thus samples its cube about `spacing / 2^d` apart, as COPC readers
//! expect. The rule is local to each node's cube, so a bucket (one cube of a coarse level)
//! computes its share of every level, the levels above its own included, without the other
//! buckets.
//!
//! Radii: every point gets its full-detail radius from its neighbours among all the bucket's
//! points ([`crate::prepare::radius::adaptive_radii`]), or the fixed radius given, or the
//! file's own. A point of an inner node also gets the radius that closes the surface drawn
//! when a view stops refining there: its adaptive radius among the points of its level and
//! the levels above, never below its full-detail radius.

use glam::{DVec3, Vec3};

use super::record::{Layout, Quantizer};
use crate::io::NodeKey;
use crate::prepare::radius::{self, DEFAULT_K};

/// Cells per axis of a node's sampling grid.
pub const GRID: u32 = 128;
/// A node with at most this many points left keeps them all.
pub const LEAF_POINTS: usize = 16_384;
/// Deepest level an index builds (a pile of repeated points ends there).
pub const MAX_INDEX_DEPTH: u32 = 24;

/// The root cube of an index, file coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cube {
    /// Centre.
    pub center: DVec3,
    /// Half the side.
    pub halfsize: f64,
}

impl Cube {
    /// `(low corner, side)` of a node.
    pub fn node(&self, key: NodeKey) -> (DVec3, f64) {
        let side = 2.0 * self.halfsize / f64::from(key.depth).exp2();
        let low = self.center - DVec3::splat(self.halfsize)
            + DVec3::new(f64::from(key.x), f64::from(key.y), f64::from(key.z)) * side;
        (low, side)
    }

    /// The node at `depth` holding `p` (clamped into the cube).
    pub fn key_at(&self, depth: u32, p: DVec3) -> NodeKey {
        let n = f64::from(depth).exp2();
        let low = self.center - DVec3::splat(self.halfsize);
        // Clamped to zero or more, truncation floors (and needs no libm call without SSE4.1).
        let cell =
            |v: f64, lo: f64| ((v - lo) / (2.0 * self.halfsize) * n).clamp(0.0, n - 1.0) as u32;
        NodeKey {
            depth,
            x: cell(p.x, low.x),
            y: cell(p.y, low.y),
            z: cell(p.z, low.z),
        }
    }

    /// Distance between the root's points ([`GRID`] cells across the cube).
    pub fn spacing(&self) -> f64 {
        2.0 * self.halfsize / f64::from(GRID)
    }
}

/// How the full-detail radius is decided.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RadiusRule {
    /// From the `k` nearest neighbours.
    Adaptive(usize),
    /// One radius, file units.
    Fixed(f32),
    /// The radius each point came with (PLY `radius`); adaptive where one is missing.
    FromFile,
}

/// Occupied cells of one node's grid: a bit set reused from node to node.
struct Cells {
    bits: Vec<u64>,
    touched: Vec<u32>,
}

impl Cells {
    fn new() -> Cells {
        Cells {
            bits: vec![0; (GRID * GRID * GRID / 64) as usize],
            touched: Vec::new(),
        }
    }

    /// Marks `cell`; true when it was free.
    fn take(&mut self, cell: u32) -> bool {
        let (word, bit) = ((cell / 64) as usize, 1u64 << (cell % 64));
        let free = self.bits[word] & bit == 0;
        if free {
            self.bits[word] |= bit;
            self.touched.push(cell / 64);
        }
        free
    }

    fn clear(&mut self) {
        for w in self.touched.drain(..) {
            self.bits[w as usize] = 0;
        }
    }
}

/// A built node: its points (indices into the bucket) and whether the bucket gave it
/// children.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Address.
    pub key: NodeKey,
    /// Indices of its points in the bucket.
    pub points: Vec<u32>,
    /// True when points were handed to children.
    pub inner: bool,
}

/// Samples `positions` (the bucket's points, file coordinates) into nodes from the root down.
pub fn sample(cube: &Cube, positions: &[DVec3]) -> Vec<Node> {
    let mut cells = Cells::new();
    let mut nodes = Vec::new();
    let mut pending = vec![(
        NodeKey::ROOT,
        (0..positions.len() as u32).collect::<Vec<u32>>(),
    )];
    while let Some((key, points)) = pending.pop() {
        if points.len() <= LEAF_POINTS || key.depth >= MAX_INDEX_DEPTH {
            nodes.push(Node {
                key,
                points,
                inner: false,
            });
            continue;
        }
        let (low, side) = cube.node(key);
        let per_cell = f64::from(GRID) / side;
        let mid = low + DVec3::splat(side * 0.5);
        let mut kept = Vec::new();
        let mut children: [Vec<u32>; 8] = Default::default();
        for i in points {
            let p = positions[i as usize];
            // Clamped to zero or more, truncation floors.
            let c = (p - low) * per_cell;
            let axis = |v: f64| v.clamp(0.0, f64::from(GRID - 1)) as u32;
            let cell = (axis(c.z) * GRID + axis(c.y)) * GRID + axis(c.x);
            if cells.take(cell) {
                kept.push(i);
            } else {
                let octant = usize::from(p.x >= mid.x)
                    | usize::from(p.y >= mid.y) << 1
                    | usize::from(p.z >= mid.z) << 2;
                children[octant].push(i);
            }
        }
        cells.clear();
        let inner = children.iter().any(|c| !c.is_empty());
        nodes.push(Node {
            key,
            points: kept,
            inner,
        });
        for (child, points) in key.children().zip(children) {
            if !points.is_empty() {
                pending.push((child, points));
            }
        }
    }
    nodes
}

/// Decides both radii of every point of a bucket and stores them in its records.
pub fn store_radii(
    layout: Layout,
    records: &mut [u8],
    positions: &[DVec3],
    nodes: &[Node],
    rule: RadiusRule,
) {
    let n = positions.len();
    if n == 0 {
        return;
    }
    // Local f32 coordinates: the bucket is small enough for f32 precision around its centre.
    let (lo, hi) = positions
        .iter()
        .fold((positions[0], positions[0]), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let centre = (lo + hi) * 0.5;
    let local: Vec<Vec3> = positions.iter().map(|p| (*p - centre).as_vec3()).collect();
    let stored: Vec<f32> = records
        .chunks_exact(layout.len)
        .map(|r| layout.radius(r))
        .collect();
    let usable = |r: f32| r.is_finite() && r > 0.0;
    let adaptive = |k: usize| radius::adaptive_radii(&local, k);
    let fine: Vec<f32> = match rule {
        RadiusRule::Fixed(r) => vec![r; n],
        RadiusRule::Adaptive(k) => adaptive(k).unwrap_or_else(|| vec![radius::FALLBACK_RADIUS; n]),
        RadiusRule::FromFile if stored.iter().all(|r| usable(*r)) => stored,
        RadiusRule::FromFile => {
            let guess = adaptive(DEFAULT_K).unwrap_or_else(|| vec![radius::FALLBACK_RADIUS; n]);
            stored
                .iter()
                .zip(guess)
                .map(|(s, g)| if usable(*s) { *s } else { g })
                .collect()
        }
    };
    let mut lod = fine.clone();
    // Level by level: the points drawn when a view stops at depth d are those of depth <= d.
    let deepest = nodes.iter().map(|n| n.key.depth).max().unwrap_or(0);
    let mut drawn: Vec<u32> = Vec::new();
    for depth in 0..=deepest {
        let level = nodes.iter().filter(|n| n.key.depth == depth);
        drawn.extend(level.clone().filter(|n| !n.inner).flat_map(|n| &n.points));
        let from = drawn.len();
        drawn.extend(level.filter(|n| n.inner).flat_map(|n| &n.points));
        if from == drawn.len() {
            continue;
        }
        let set: Vec<Vec3> = drawn.iter().map(|i| local[*i as usize]).collect();
        if let Some(radii) = radius::adaptive_radii_from(&set, from, DEFAULT_K) {
            for (i, r) in drawn[from..].iter().zip(radii) {
                let i = *i as usize;
                lod[i] = r.max(fine[i]);
            }
        }
    }
    for (i, record) in records.chunks_exact_mut(layout.len).enumerate() {
        layout.set_radii(record, fine[i], lod[i]);
    }
}

/// The file coordinates of a bucket's records.
pub fn positions(layout: Layout, records: &[u8], q: &Quantizer) -> Vec<DVec3> {
    records
        .chunks_exact(layout.len)
        .map(|r| q.position(Layout::xyz(r)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Cube {
        Cube {
            center: DVec3::ZERO,
            halfsize: 64.0,
        }
    }

    /// A 300 x 300 grid 0.1 m apart on the plane z = 0.05.
    fn plane() -> Vec<DVec3> {
        (0..300 * 300)
            .map(|i| DVec3::new(f64::from(i % 300) * 0.1, f64::from(i / 300) * 0.1, 0.05))
            .collect()
    }

    #[test]
    fn keys_and_nodes_agree() {
        let c = cube();
        let k = c.key_at(3, DVec3::new(-1.0, 1.0, 63.9));
        assert_eq!((k.depth, k.x, k.y, k.z), (3, 3, 4, 7));
        let (low, side) = c.node(k);
        assert_eq!((low, side), (DVec3::new(-16.0, 0.0, 48.0), 16.0));
        // Outside the cube: clamped to the edge node.
        assert_eq!(c.key_at(1, DVec3::splat(1e6)).x, 1);
        assert_eq!(c.spacing(), 1.0);
    }

    #[test]
    fn every_point_lands_in_one_node_inside_its_cube() {
        let c = cube();
        let p = plane();
        let nodes = sample(&c, &p);
        let mut seen = vec![0u32; p.len()];
        for n in &nodes {
            let (low, side) = c.node(n.key);
            for i in &n.points {
                seen[*i as usize] += 1;
                let q = p[*i as usize];
                assert!(q.cmpge(low).all() && q.cmple(low + side).all());
            }
            // A node samples one point per cell: at most GRID^2 on a plane.
            if n.inner {
                assert!(
                    n.points.len() <= (GRID * GRID) as usize,
                    "{}",
                    n.points.len()
                );
            }
        }
        assert!(seen.iter().all(|s| *s == 1));
        // The root samples the 1 m cells the 30 m plane crosses: 30 x 30 of them.
        let root = nodes.iter().find(|n| n.key == NodeKey::ROOT).unwrap();
        assert_eq!(root.points.len(), 900);
        assert!(root.inner);
        // 90,000 points in leaves of at most LEAF_POINTS.
        assert!(
            nodes
                .iter()
                .filter(|n| !n.inner)
                .all(|n| n.points.len() <= LEAF_POINTS)
        );
    }

    #[test]
    fn coarse_points_close_their_level() {
        let c = cube();
        let p = plane();
        let nodes = sample(&c, &p);
        let layout = Layout::new(false);
        let q = Quantizer {
            scale: DVec3::splat(0.001),
            offset: DVec3::ZERO,
        };
        let mut records = Vec::new();
        for x in &p {
            layout.push(&mut records, q.ints(*x).unwrap(), &Default::default());
        }
        store_radii(layout, &mut records, &p, &nodes, RadiusRule::Adaptive(8));
        let radius = |i: u32, lod: bool| {
            let r = &records[i as usize * layout.len..(i as usize + 1) * layout.len];
            let at = layout.base_len() + if lod { 4 } else { 0 };
            f32::from_le_bytes(r[at..at + 4].try_into().unwrap())
        };
        // Full detail: half the 0.1 m spacing.
        let fine: Vec<f32> = (0..p.len() as u32).map(|i| radius(i, false)).collect();
        let mut sorted = fine.clone();
        sorted.sort_by(f32::total_cmp);
        assert!(
            (sorted[sorted.len() / 2] - 0.05).abs() < 0.002,
            "{}",
            sorted[sorted.len() / 2]
        );
        // The root's points stand 1 m apart: their stopping radius is about half of that.
        let root = nodes.iter().find(|n| n.key == NodeKey::ROOT).unwrap();
        let mut lod: Vec<f32> = root.points.iter().map(|i| radius(*i, true)).collect();
        lod.sort_by(f32::total_cmp);
        assert!(
            (lod[lod.len() / 2] - 0.5).abs() < 0.05,
            "{}",
            lod[lod.len() / 2]
        );
        // Leaves: the stopping radius is the full-detail one.
        for n in nodes.iter().filter(|n| !n.inner) {
            for i in &n.points {
                assert_eq!(radius(*i, true), radius(*i, false));
            }
        }
    }
}
