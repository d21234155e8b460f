//! View-dependent level of detail for COPC files: a panorama reads only the octree nodes it
//! needs.
//!
//! A COPC node at depth `d` holds a subsample of its cube with points about
//! `spacing / 2^d` apart, and the union of a node with its ancestors is that cube at that
//! density. Walking down from the root, a node's detail is enough when its spacing, seen
//! from the camera at the node's nearest point, spans less than the threshold angle (a pixel
//! of the panorama, `2π / width`, by default): its children are not read. Every node on the
//! way down is read (their points are part of the picture). A view that selects fewer points
//! than a floor ([`LOD_FLOOR_POINTS`] by default) refines on past the threshold, the nodes
//! that look coarsest first, while it stays within the floor: a scan that small is drawn
//! whole, exactly as without level of detail, and a larger one spends the floor where the
//! stopped surface is coarsest.
//!
//! Points where refinement stopped stand for the denser points left unread, so their
//! spheres grow to [`LOD_RADIUS_FACTOR`] times their level's spacing (never below the
//! cloud's own radius): the surface stays closed where the full cloud would close it. Points
//! at full detail keep the cloud's radius, measured (for `auto`) on those points only, so
//! it matches the full cloud's.

use std::collections::{BinaryHeap, HashMap, HashSet};
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use glam::DVec3;
use indicatif::ProgressBar;

use super::filter::Stage;
use super::radius::{self, RadiusChoice, RadiusRule};
use super::{CameraChoice, EyeHeight, PrepareError, PrepareOptions, placement};
use crate::io::{
    self, FileInfo, LoadError, LoadOptions, LoadReport, NodeKey, Octree, Up, load_files_with_reader,
};
use crate::scene::{Radii, Scene};

/// Sphere radius of a point where refinement stopped, in units of its level's spacing.
pub const LOD_RADIUS_FACTOR: f64 = 0.7;

/// Points a view reads before level of detail spares any: below this the drawing costs little
/// on any adapter, and a stopped node's closing spheres differ from the points they stand for.
pub const LOD_FLOOR_POINTS: u64 = 1_000_000;

/// Points read at most to place the camera automatically (whole levels from the root).
pub const CAMERA_SURVEY_POINTS: u64 = 1 << 18;

/// Points read at most to plan a tour of a COPC file (whole levels from the root): the
/// ground under its path and its bounds come from them, not from every point.
pub const PLAN_SURVEY_POINTS: u64 = 1 << 22;

/// Full-detail patches [`detail_spacing`] measures the point spacing in.
pub const SPACING_PATCHES: usize = 4;

/// Level of detail for COPC input (other formats are always read whole).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Lod {
    /// Every point.
    #[default]
    Off,
    /// Refine until a node's spacing seen from the camera spans less than `pixels` pixels of
    /// a panorama `width` pixels wide, then on while the view reads at most `floor` points.
    Pixels {
        /// Panorama width (per eye).
        width: u32,
        /// Threshold in pixels.
        pixels: f64,
        /// Points a view reads at least, where the scan holds them ([`select`]).
        floor: u64,
    },
}

impl Lod {
    /// The threshold angle in radians; `None` when off.
    pub fn threshold(self) -> Option<f64> {
        match self {
            Lod::Off => None,
            Lod::Pixels { width, pixels, .. } => {
                Some(std::f64::consts::TAU / f64::from(width.max(1)) * pixels)
            }
        }
    }

    /// The same level of detail with another floor (points); no change when off.
    pub fn with_floor(self, floor: u64) -> Lod {
        match self {
            Lod::Off => Lod::Off,
            Lod::Pixels { width, pixels, .. } => Lod::Pixels {
                width,
                pixels,
                floor,
            },
        }
    }
}

/// The `--lod` value: `on` (one pixel), `off`, or a threshold in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LodChoice {
    /// Full detail.
    Off,
    /// Threshold in pixels.
    Pixels(f64),
}

impl LodChoice {
    /// The level of detail for a panorama `width` pixels wide, with the default floor
    /// ([`LOD_FLOOR_POINTS`]).
    pub fn at_width(self, width: u32) -> Lod {
        match self {
            LodChoice::Off => Lod::Off,
            LodChoice::Pixels(pixels) => Lod::Pixels {
                width,
                pixels,
                floor: LOD_FLOOR_POINTS,
            },
        }
    }
}

impl FromStr for LodChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "off" => Ok(LodChoice::Off),
            "on" => Ok(LodChoice::Pixels(1.0)),
            other => match other.parse::<f64>() {
                Ok(p) if p.is_finite() && p > 0.0 => Ok(LodChoice::Pixels(p)),
                _ => Err(format!(
                    "expected on, off or a positive number of pixels, got `{s}`"
                )),
            },
        }
    }
}

/// The nodes a view reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Selected nodes; `true` where refinement stopped above existing children.
    pub nodes: HashMap<NodeKey, bool>,
    /// Selected nodes that hold points, to read.
    pub read: Vec<NodeKey>,
    /// Points in `read`.
    pub points: u64,
}

impl Selection {
    /// The selected nodes where refinement stopped above existing children.
    pub fn stopped(&self) -> HashSet<NodeKey> {
        self.nodes
            .iter()
            .filter(|(_, stopped)| **stopped)
            .map(|(k, _)| *k)
            .collect()
    }
}

/// A node where refinement stopped, ordered by the angle its spacing spans from the camera.
struct Stopped {
    angle: f64,
    key: NodeKey,
}

impl PartialEq for Stopped {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for Stopped {}

impl PartialOrd for Stopped {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Stopped {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.angle
            .total_cmp(&other.angle)
            .then_with(|| other.key.cmp(&self.key))
    }
}

/// Walks `octree` from the root with the camera at `camera` (file coordinates) and keeps
/// refining while a node's spacing, seen from the camera at the node's nearest point, spans
/// at least `threshold` radians. Then, while the selection holds fewer than `floor` points,
/// it refines the stopped node whose spacing spans the widest angle (all its children at
/// once) as long as their points keep it within `floor`.
pub fn select(octree: &Octree, camera: DVec3, threshold: f64, floor: u64) -> Selection {
    let angle = |key: NodeKey| octree.node_spacing(key.depth) / octree.distance(key, camera);
    let mut nodes = HashMap::new();
    let mut stopped = BinaryHeap::new();
    let mut points = 0;
    let mut pending = vec![NodeKey::ROOT];
    while let Some(key) = pending.pop() {
        let Some(&n) = octree.nodes.get(&key) else {
            continue;
        };
        points += n;
        let distance = octree.distance(key, camera);
        let spacing = octree.node_spacing(key.depth);
        let fine_enough = spacing < threshold * distance;
        let children = octree.has_children(key);
        nodes.insert(key, fine_enough && children);
        if !fine_enough && children {
            pending.extend(key.children());
        } else if children {
            // Fine enough at a distance above zero: a finite angle.
            stopped.push(Stopped {
                angle: spacing / distance,
                key,
            });
        }
    }
    while let Some(Stopped { key, .. }) = stopped.pop() {
        let below: u64 = key.children().filter_map(|c| octree.nodes.get(&c)).sum();
        if points + below > floor {
            break;
        }
        points += below;
        nodes.insert(key, false);
        for child in key.children().filter(|c| octree.nodes.contains_key(c)) {
            let children = octree.has_children(child);
            nodes.insert(child, children);
            if children {
                stopped.push(Stopped {
                    angle: angle(child),
                    key: child,
                });
            }
        }
    }
    let mut read: Vec<NodeKey> = nodes
        .keys()
        .copied()
        .filter(|k| octree.nodes.get(k).is_some_and(|n| *n > 0))
        .collect();
    read.sort_unstable();
    Selection {
        nodes,
        read,
        points,
    }
}

/// Whole levels from the root holding at most `budget` points together (the root level at
/// least): a coarse, even sample of the cloud.
pub fn coarse_nodes(octree: &Octree, budget: u64) -> Vec<NodeKey> {
    let mut per_level: Vec<u64> = vec![0; octree.depth() as usize + 1];
    for (k, n) in &octree.nodes {
        per_level[k.depth as usize] += n;
    }
    let mut total = 0;
    let mut levels = 0;
    for n in per_level {
        if levels > 0 && total + n > budget {
            break;
        }
        total += n;
        levels += 1;
    }
    let mut keys: Vec<NodeKey> = octree
        .nodes
        .iter()
        .filter(|(k, n)| (k.depth as usize) < levels && **n > 0)
        .map(|(k, _)| *k)
        .collect();
    keys.sort_unstable();
    keys
}

/// Up to [`SPACING_PATCHES`] leaves of `octree` (nodes with points and no children), spread
/// over the file's points: the leaves in key order, picked at evenly spaced shares of their
/// points, so dense parts count as they do among all points.
fn spacing_patches(octree: &Octree) -> Vec<NodeKey> {
    let mut leaves: Vec<(NodeKey, u64)> = octree
        .nodes
        .iter()
        .filter(|(k, n)| **n > 0 && !octree.has_children(**k))
        .map(|(k, n)| (*k, *n))
        .collect();
    leaves.sort_unstable();
    let total: u64 = leaves.iter().map(|(_, n)| n).sum();
    let mut picked = Vec::new();
    let mut seen = 0;
    let mut next = 0;
    for (key, n) in leaves {
        seen += n;
        // Pick the leaf holding the point at share (next + 1/2) / SPACING_PATCHES.
        while next < SPACING_PATCHES
            && (2 * next as u64 + 1) * total < 2 * seen * SPACING_PATCHES as u64
        {
            if picked.last() != Some(&key) {
                picked.push(key);
            }
            next += 1;
        }
    }
    picked
}

/// The median spacing ([`radius::median_spacing`]) of the COPC file `path`'s points at full
/// detail, in file units, measured without reading them all: inside the cubes of a few
/// leaves ([`spacing_patches`]), each read with its ancestors, which together hold every
/// point of the file inside the leaf's cube. `None` as for `median_spacing`.
///
/// # Errors
/// A [`LoadError`] (a corrupt node names the file).
pub fn detail_spacing(path: &Path, octree: &Octree) -> Result<Option<f32>, LoadError> {
    let patches = spacing_patches(octree);
    let mut keys: Vec<NodeKey> = Vec::new();
    for &leaf in &patches {
        let mut key = Some(leaf);
        while let Some(k) = key {
            if octree.nodes.get(&k).is_some_and(|n| *n > 0) {
                keys.push(k);
            }
            key = k.parent();
        }
    }
    keys.sort_unstable();
    keys.dedup();
    if keys.is_empty() {
        return Ok(None);
    }
    let (scene, _) = load_files_with_reader(
        &[path.to_path_buf()],
        &LoadOptions::default(),
        &ProgressBar::hidden(),
        &|p| io::open_nodes(p, &keys),
    )?;
    let cubes: Vec<(DVec3, DVec3)> = patches.iter().map(|k| octree.bounds(*k)).collect();
    let inside: Vec<bool> = scene
        .positions
        .iter()
        .map(|p| {
            let f = scene.origin + p.as_dvec3();
            cubes
                .iter()
                .any(|(lo, hi)| f.cmpge(*lo).all() && f.cmplt(*hi).all())
        })
        .collect();
    Ok(radius::median_spacing(&scene.select(&inside)))
}

/// A tour's planning read of a COPC file: whole levels from the root, prepared as
/// [`super::prepare_scene`] prepares points (filters, the given camera, the local zero).
#[derive(Debug, Clone)]
pub struct Survey {
    /// The points read, prepared (`lod` is `None`: no view chose them).
    pub prepared: super::Prepared,
    /// The file's median spacing at full detail ([`detail_spacing`]); `None` where it cannot
    /// be measured.
    pub detail_spacing: Option<f32>,
    /// Points in the file.
    pub points_total: u64,
}

/// Reads the coarse levels of the COPC file `path` holding at most `budget` points
/// ([`coarse_nodes`]) and prepares them with `options` (its `lod` does not apply). `None`
/// when `path` is not COPC or holds no more than `budget` points: read it whole. Radii a
/// survey does not need are not measured: a neighbour-searched radius becomes the auto
/// radius of the full-detail spacing, as a node stream draws it. An automatic camera stands
/// at the eye height of the full-detail spacing, as it would over every point.
///
/// # Errors
/// A [`LoadError`] naming the file, or a filter's error.
pub fn survey(
    path: &Path,
    options: &PrepareOptions,
    budget: u64,
    progress: &ProgressBar,
) -> Result<Option<Survey>, PrepareError> {
    let info = io::read_info(path)?;
    if !io::is_copc(&info) {
        return Ok(None);
    }
    let octree = io::read_octree(path)?;
    if octree.point_count <= budget {
        return Ok(None);
    }
    options.filter.check(&info)?;
    let keys = coarse_nodes(&octree, budget);
    // Read around the file's own origin, then moved onto the tour's, as `prepare_files`
    // reads the whole scan: the same rounding, so the same positions.
    let load = LoadOptions {
        origin: None,
        up: options.up,
        ..LoadOptions::default()
    };
    let (scene, report) = load_files_with_reader(&[path.to_path_buf()], &load, progress, &|p| {
        io::open_nodes(p, &keys)
    })?;
    let detail = detail_spacing(path, &octree)?;
    let stored = info.attributes.radius && matches!(scene.radii, Radii::PerPoint(_));
    let radius = match options.radius {
        None if stored => None,
        Some(RadiusChoice::Fixed(r)) => Some(RadiusChoice::Fixed(r)),
        _ => Some(RadiusChoice::Fixed(radius::radius_for_spacing(detail))),
    };
    // The automatic camera's height rule counts point spacings: those of full detail, not
    // the survey's coarser ones.
    let height = match options.camera {
        CameraChoice::Auto => EyeHeight::new(Some(options.height.over(detail)), 1.0),
        _ => options.height,
    };
    let prepared = super::prepare_scene(
        scene,
        &PrepareOptions {
            radius,
            height,
            lod: Lod::Off,
            ..*options
        },
        path,
    )?;
    Ok(Some(Survey {
        prepared: super::Prepared {
            scene: prepared.scene,
            camera_world: prepared.camera_world,
            radii: prepared.radii,
            report,
            filtered: prepared.filtered,
            lod: None,
        },
        detail_spacing: detail,
        points_total: octree.point_count,
    }))
}

/// What a view-dependent read did, for the summary.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LodReport {
    /// Points read.
    pub points_read: u64,
    /// Points in the files.
    pub points_total: u64,
    /// Nodes read.
    pub nodes_read: usize,
    /// Nodes holding points in the files.
    pub nodes_total: usize,
    /// Deepest level read.
    pub deepest: u32,
    /// Deepest level in the files.
    pub depth: u32,
    /// The threshold in pixels.
    pub pixels: f64,
    /// Points a view reads at least, where the files hold them.
    #[serde(default)]
    pub floor: u64,
}

impl fmt::Display for LodReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "level of detail ({} px): read {} of {} points ({} nodes of {}, levels 0-{} of 0-{}; \
             floor {} points)",
            self.pixels,
            self.points_read,
            self.points_total,
            self.nodes_read,
            self.nodes_total,
            self.deepest,
            self.depth,
            self.floor
        )
    }
}

/// A view-dependent read of COPC files: the octrees and what was chosen from them.
#[derive(Debug, Clone)]
pub struct LodRead {
    /// The camera's world position the selection was made for.
    pub camera_world: DVec3,
    /// Per file: its octree and selection.
    pub files: Vec<(PathBuf, Octree, Selection)>,
    /// The summary.
    pub report: LodReport,
}

/// File coordinates of a world (Z-up) point: the inverse of [`Up::to_world`].
pub fn to_file(up: Up, w: DVec3) -> DVec3 {
    match up {
        Up::Z => w,
        Up::Y => DVec3::new(w.x, w.z, -w.y),
    }
}

/// Reads the nodes of `paths` (all COPC) the view needs, after placing the camera on a
/// coarse read when it is not given. `None` when `lod` is off or some file is not COPC
/// (the caller then reads every point).
///
/// # Errors
/// A [`LoadError`] (a corrupt hierarchy names the file), or
/// [`PrepareError::CameraPlacement`].
pub fn read(
    paths: &[PathBuf],
    infos: &[FileInfo],
    options: &PrepareOptions,
    progress: &ProgressBar,
) -> Result<Option<(Scene, LoadReport, LodRead)>, PrepareError> {
    let (Some(threshold), Lod::Pixels { pixels, floor, .. }) =
        (options.lod.threshold(), options.lod)
    else {
        return Ok(None);
    };
    if infos.is_empty() || !infos.iter().all(io::is_copc) {
        return Ok(None);
    }
    let octrees = paths
        .iter()
        .map(|p| io::read_octree(p))
        .collect::<Result<Vec<_>, _>>()?;
    let nodes_for = |p: &Path, pick: &dyn Fn(&Octree) -> Vec<NodeKey>| {
        let i = paths.iter().position(|q| q == p).unwrap_or(0);
        io::open_nodes(p, &pick(&octrees[i]))
    };
    let camera_world = match options.camera.given() {
        Some(c) => c,
        None => {
            let load = LoadOptions {
                origin: options.origin,
                up: options.up,
                ..LoadOptions::default()
            };
            let (coarse, _) = load_files_with_reader(paths, &load, &ProgressBar::hidden(), &|p| {
                nodes_for(p, &|o| coarse_nodes(o, CAMERA_SURVEY_POINTS))
            })?;
            let (coarse, _) = options
                .filter
                .apply(coarse, options.up, Stage::BeforeCamera);
            placement::camera_position(&coarse, options.camera, options.height)
                .map(|c| coarse.origin + c)
                .ok_or_else(|| PrepareError::CameraPlacement {
                    path: paths[0].clone(),
                })?
        }
    };
    let camera_file = to_file(options.up, camera_world);
    let fields = options.fields_read();
    // The view's floor is shared among the files as their points are.
    let total: u64 = octrees.iter().map(|o| o.point_count).sum::<u64>().max(1);
    let files: Vec<(PathBuf, Octree, Selection)> = paths
        .iter()
        .zip(octrees)
        .map(|(p, o)| {
            let share = (u128::from(floor) * u128::from(o.point_count) / u128::from(total)) as u64;
            let s = select(&o, camera_file, threshold, share);
            (p.clone(), o, s)
        })
        .collect();
    let load = LoadOptions {
        origin: options.origin.or(Some(camera_world)),
        up: options.up,
        ..LoadOptions::default()
    };
    let (scene, report) = load_files_with_reader(paths, &load, progress, &|p| {
        let (_, _, s) = files
            .iter()
            .find(|(q, _, _)| q == p)
            .ok_or_else(|| LoadError::NotFound { path: p.into() })?;
        Ok(io::open_nodes_stopping(p, &s.read, &s.stopped())?.decode_only(fields))
    })?;
    let report_lod = LodReport {
        points_read: files.iter().map(|(_, _, s)| s.points).sum(),
        points_total: files.iter().map(|(_, o, _)| o.point_count).sum(),
        nodes_read: files.iter().map(|(_, _, s)| s.read.len()).sum(),
        nodes_total: files.iter().map(|(_, o, _)| o.nonempty_nodes()).sum(),
        deepest: files
            .iter()
            .flat_map(|(_, _, s)| s.read.iter().map(|k| k.depth))
            .max()
            .unwrap_or(0),
        depth: files.iter().map(|(_, o, _)| o.depth()).max().unwrap_or(0),
        pixels,
        floor,
    };
    Ok(Some((
        scene,
        report,
        LodRead {
            camera_world,
            files,
            report: report_lod,
        },
    )))
}

/// How the spheres of a node read on its own are sized.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeRadii {
    /// The radii the file stores: each point's full-detail radius, or its node's closing
    /// radius where refinement stopped (an index made by `omnicloud index`).
    File,
    /// This radius at full detail, at least [`LOD_RADIUS_FACTOR`] times the level's spacing
    /// where refinement stopped.
    Base(f32),
}

/// Node `key` of the COPC file `copc` as a scene around `options.origin`, filtered by
/// `options.filter` and sized by `radii`; `stopped` says that refinement stopped at it, so
/// its points stand for the unread ones below. The same points, positions and radii as a
/// read of the whole selection.
///
/// # Errors
/// A [`LoadError`] (a corrupt node names the file).
pub fn node_scene(
    copc: &io::CopcFile,
    key: NodeKey,
    stopped: bool,
    options: &PrepareOptions,
    radii: NodeRadii,
) -> Result<Scene, PrepareError> {
    // Read around the file's own origin, then moved onto the tour's, exactly as
    // `prepare_files` reads the whole scan: the same rounding, so the same positions.
    let load = LoadOptions {
        origin: None,
        up: options.up,
        ..LoadOptions::default()
    };
    let stop: HashSet<NodeKey> = if stopped {
        HashSet::from([key])
    } else {
        HashSet::new()
    };
    let paths = [copc.path().to_path_buf()];
    let (mut scene, _) = load_files_with_reader(&paths, &load, &ProgressBar::hidden(), &|_| {
        Ok(copc
            .read_nodes(&[key], &stop)?
            .decode_only(options.fields_read()))
    })?;
    if let Some(origin) = options.origin {
        scene.recenter(origin);
    }
    let (mut scene, _) = options.filter.apply(scene, options.up, Stage::All);
    if let NodeRadii::Base(r) = radii {
        let r = if stopped {
            r.max((copc.octree().node_spacing(key.depth) * LOD_RADIUS_FACTOR) as f32)
        } else {
            r
        };
        scene.radii = Radii::Uniform(r);
    }
    Ok(scene)
}

impl LodRead {
    /// The level-of-detail spacing at world point `w`: the spacing of the selected node
    /// holding it where refinement stopped; `None` where the point is at full detail.
    fn stopped_spacing(&self, up: Up, w: DVec3) -> Option<f64> {
        let p = to_file(up, w);
        let (_, octree, selection) = self.files.iter().find(|(_, o, _)| {
            let (lo, hi) = o.bounds(NodeKey::ROOT);
            p.cmpge(lo).all() && p.cmple(hi).all()
        })?;
        let mut key = NodeKey::ROOT;
        loop {
            match selection.nodes.get(&key) {
                Some(true) => return Some(octree.node_spacing(key.depth)),
                Some(false) if key.depth < io::copc::MAX_DEPTH => {
                    let child = octree.child_at(key, p);
                    if !selection.nodes.contains_key(&child) {
                        return None;
                    }
                    key = child;
                }
                _ => return None,
            }
        }
    }

    /// Sizes the spheres of the read scene. Without a choice, radii the files store (an
    /// index made by `omnicloud index`: each point's full-detail radius, or where refinement
    /// stopped its node's closing radius) are kept as read: no neighbour search. Otherwise the
    /// radius rule's radius (`auto`, also for `adaptive` and no choice, measured on the points
    /// at full detail: a selection's neighbours are not the file's) for points at full
    /// detail, and at least [`LOD_RADIUS_FACTOR`] times their level's spacing where refinement
    /// stopped.
    pub fn apply_radii(
        &self,
        scene: &mut Scene,
        choice: Option<RadiusChoice>,
        up: Up,
    ) -> RadiusRule {
        if choice.is_none() && matches!(scene.radii, Radii::PerPoint(_)) {
            return RadiusRule {
                radius: LoadOptions::default().default_radius,
                keep_file_radii: true,
                adaptive: None,
            };
        }
        let spacing: Vec<Option<f64>> = scene
            .positions
            .iter()
            .map(|p| self.stopped_spacing(up, scene.origin + p.as_dvec3()))
            .collect();
        let base = match choice {
            Some(RadiusChoice::Fixed(r)) => r,
            Some(RadiusChoice::Auto | RadiusChoice::Adaptive { .. }) | None => {
                let full: Vec<bool> = spacing.iter().map(Option::is_none).collect();
                let detailed = scene.select(&full);
                if detailed.len() >= 2 {
                    radius::auto_radius(&detailed)
                } else {
                    radius::auto_radius(scene)
                }
            }
        };
        let radii = spacing
            .iter()
            .map(|s| s.map_or(base, |s| base.max((s * LOD_RADIUS_FACTOR) as f32)))
            .collect();
        scene.radii = Radii::PerPoint(radii);
        RadiusRule {
            radius: base,
            keep_file_radii: true,
            adaptive: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// A full octree of `depth` levels over a 64 m cube at the origin, 10 points a node.
    fn full(depth: u32) -> Octree {
        let mut nodes = HashMap::new();
        let mut level = vec![NodeKey::ROOT];
        for _ in 0..=depth {
            let mut next = Vec::new();
            for k in level {
                nodes.insert(k, 10);
                next.extend(k.children());
            }
            level = next;
        }
        Octree {
            center: DVec3::ZERO,
            halfsize: 32.0,
            spacing: 1.0,
            point_count: 10 * nodes.len() as u64,
            nodes,
        }
    }

    #[test]
    fn spacing_patches_are_leaves_spread_over_the_points() {
        let mut o = full(3);
        // One dense leaf holding as many points as all the others: two of the four shares
        // fall in it, so it is picked once and the others spread over the rest.
        let dense = NodeKey {
            depth: 3,
            x: 7,
            y: 7,
            z: 7,
        };
        *o.nodes.get_mut(&dense).unwrap() = 10 * 511;
        let picked = spacing_patches(&o);
        assert_eq!(picked.len(), 3, "{picked:?}");
        assert!(picked.iter().all(|k| k.depth == 3));
        assert!(picked.contains(&dense));
        assert!(picked.windows(2).all(|w| w[0] < w[1]));
        // Evenly filled leaves: four distinct ones, a quarter of the leaves apart.
        let even = spacing_patches(&full(3));
        assert_eq!(even.len(), SPACING_PATCHES);
        let mut leaves: Vec<NodeKey> = full(3).nodes.into_keys().filter(|k| k.depth == 3).collect();
        leaves.sort_unstable();
        let at: Vec<usize> = even
            .iter()
            .map(|k| leaves.binary_search(k).unwrap())
            .collect();
        assert_eq!(at, [64, 192, 320, 448]);
        assert_eq!(
            dense.parent(),
            Some(NodeKey {
                depth: 2,
                x: 3,
                y: 3,
                z: 3
            })
        );
        assert_eq!(NodeKey::ROOT.parent(), None);
        assert!(dense.children().all(|c| c.parent() == Some(dense)));
    }

    #[test]
    fn refines_near_the_camera_only() {
        let o = full(4);
        let camera = DVec3::new(1.0, 1.0, 1.0);
        // One pixel of a 256-wide panorama: 0.0245 rad.
        let s = select(
            &o,
            camera,
            Lod::Pixels {
                width: 256,
                pixels: 1.0,
                floor: 0,
            }
            .threshold()
            .unwrap(),
            0,
        );
        // The node holding the camera is refined to the bottom.
        let deepest = s.read.iter().map(|k| k.depth).max().unwrap();
        assert_eq!(deepest, 4);
        // A node is fine enough beyond spacing / threshold: 20.4 m at depth 1 (0.5 m), 10.2 m
        // at depth 2, 5.1 m at depth 3. With the camera near the centre, at each of depths
        // 1-3 only the 8 nodes around the camera are nearer: each level below reads their
        // 64 children, and nothing else.
        let per_depth: Vec<usize> = (0..=4)
            .map(|d| s.read.iter().filter(|k| k.depth == d).count())
            .collect();
        assert_eq!(per_depth, [1, 8, 64, 64, 64]);
        assert_eq!(s.points, 2010);
        // Every selected node's parent is selected too.
        for k in s.nodes.keys().filter(|k| k.depth > 0) {
            let parent = NodeKey {
                depth: k.depth - 1,
                x: k.x / 2,
                y: k.y / 2,
                z: k.z / 2,
            };
            assert!(s.nodes.contains_key(&parent));
        }
        // A threshold of zero reads everything.
        assert_eq!(select(&o, camera, 0.0, 0).points, o.point_count);
    }

    #[test]
    fn a_floor_refines_the_coarsest_looking_nodes_within_it() {
        let o = full(4);
        let camera = DVec3::new(1.0, 1.0, 1.0);
        let threshold = TAU / 256.0;
        let angle = |k: &NodeKey| o.node_spacing(k.depth) / o.distance(*k, camera);
        let alone = select(&o, camera, threshold, 0);
        // A floor below what the threshold reads changes nothing.
        assert_eq!(select(&o, camera, threshold, alone.points), alone);
        // A floor of the whole scan reads it whole, nothing stopped, as a zero threshold.
        let whole = select(&o, camera, threshold, o.point_count);
        assert_eq!(whole.points, o.point_count);
        assert!(whole.stopped().is_empty());
        assert_eq!(whole, select(&o, camera, 0.0, 0));
        for floor in [3_000, 10_000, 30_000] {
            let s = select(&o, camera, threshold, floor);
            assert!(
                s.points <= floor && s.points > alone.points,
                "{floor}: {}",
                s.points
            );
            assert_eq!(s.points, s.read.iter().map(|k| o.nodes[k]).sum::<u64>());
            // Every node the threshold read is read.
            assert!(alone.read.iter().all(|k| s.nodes.contains_key(k)));
            // The nodes still stopped look no coarser than any refined past the threshold,
            // and refining the coarsest of them would pass the floor.
            let stopped = s.stopped();
            let refined_past = s.nodes.iter().filter(|(k, stop)| {
                !**stop
                    && o.has_children(**k)
                    && o.node_spacing(k.depth) < threshold * o.distance(**k, camera)
            });
            let finest_refined = refined_past
                .map(|(k, _)| angle(k))
                .fold(f64::INFINITY, f64::min);
            let coarsest = stopped
                .iter()
                .max_by(|a, b| angle(a).total_cmp(&angle(b)))
                .unwrap();
            assert!(angle(coarsest) <= finest_refined, "{floor}");
            let below: u64 = coarsest.children().map(|c| o.nodes[&c]).sum();
            assert!(s.points + below > floor, "{floor}");
        }
    }

    #[test]
    fn coarse_levels_fit_the_budget() {
        let o = full(3);
        assert_eq!(coarse_nodes(&o, 0).len(), 1);
        assert_eq!(coarse_nodes(&o, 90).len(), 9);
        assert_eq!(coarse_nodes(&o, 1000).len(), 73);
    }

    #[test]
    fn file_coordinates_invert_the_up_swap() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        for up in [Up::Z, Up::Y] {
            assert_eq!(to_file(up, up.to_world(p)), p);
        }
    }

    #[test]
    fn lod_values_parse() {
        assert_eq!("off".parse::<LodChoice>(), Ok(LodChoice::Off));
        assert_eq!("ON".parse::<LodChoice>(), Ok(LodChoice::Pixels(1.0)));
        assert_eq!("2.5".parse::<LodChoice>(), Ok(LodChoice::Pixels(2.5)));
        assert!("0".parse::<LodChoice>().is_err());
        assert!("fast".parse::<LodChoice>().is_err());
        let t = LodChoice::Pixels(2.0).at_width(512).threshold().unwrap();
        assert!((t - std::f64::consts::TAU / 256.0).abs() < 1e-12);
        assert_eq!(LodChoice::Off.at_width(512).threshold(), None);
    }
}
