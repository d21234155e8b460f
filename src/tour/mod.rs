//! Tours: a camera path through a scan, rendered frame by frame (DESIGN §10).
//!
//! [`path`] reads the keyframes (CSV or GeoJSON), [`spline`] draws the curve through them and
//! measures its length, [`poses`] places the frames at constant speed with their headings,
//! [`plan`](plan()) puts it together on a scan (a file, or points already in memory), [`shard`] splits the frames across
//! processes, [`run`] renders and writes the frames (through the scan kept resident by
//! [`crate::renderer`]), and [`manifest`] records them in `tour.json`.

pub mod ground;
pub mod manifest;
pub mod path;
pub mod poses;
pub mod run;
pub mod shard;
pub mod spline;
pub mod stations;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec2};
use indicatif::ProgressBar;

use crate::io::FileInfo;
use crate::prepare::lod::{self, PLAN_SURVEY_POINTS};
use crate::prepare::{EyeHeight, PrepareError, PrepareOptions, prepare, prepare_scene};
use crate::scene::Scene;

pub use manifest::{FrameRecord, StereoLayout, TourManifest};
pub use path::{Keyframe, PathError};
pub use poses::{Heading, Pose, Sampling};
pub use run::{FrameFormat, RunOptions, RunReport, render_frames};
pub use shard::{Shard, ShardChoice, ShardSource};

/// The points a tour is laid out on.
#[derive(Debug, Clone)]
pub enum TourScan {
    /// A LAS, LAZ, COPC or PLY file, loaded once and moved onto the tour's origin.
    File(PathBuf),
    /// Points already in memory, moved onto the tour's origin.
    Points {
        /// The points.
        scene: Arc<Scene>,
        /// Header facts of the file the points were read from, when they were: its bounds
        /// check the keyframes and place the origin as a file's do (else the points' bounds).
        info: Option<Box<FileInfo>>,
        /// How the manifest and messages name the points.
        name: PathBuf,
    },
}

impl TourScan {
    /// The file, or the name of the points.
    pub fn name(&self) -> &Path {
        match self {
            TourScan::File(file) => file,
            TourScan::Points { name, .. } => name,
        }
    }
}

/// What a tour is asked for.
#[derive(Debug, Clone)]
pub struct TourRequest {
    /// The scan.
    pub scan: TourScan,
    /// Where the frames stand: along the curve through keyframes (a path file's or given in
    /// memory), or at an E57 survey's stations.
    pub route: Route,
    /// How the scan is read (its `camera` and `origin` are the tour's to set).
    pub prepare: PrepareOptions,
    /// Eye height above the ground where the path gives no z, file units: the one given, or
    /// `render`'s rule (a person's eye height, raised to 20 median point spacings over
    /// sparse data).
    pub height: EyeHeight,
    /// Frame spacing.
    pub sampling: Sampling,
    /// Metres of path the tangent heading is averaged over (0: the tangent itself).
    pub heading_window: f64,
    /// Degrees added to every heading (90 looks right of the direction of travel).
    pub yaw_offset: f64,
    /// Degrees added to every frame's pitch.
    pub pitch_offset: f64,
    /// Degrees added to every frame's roll.
    pub roll_offset: f64,
}

/// Where a tour's frames stand.
#[derive(Debug, Clone, PartialEq)]
pub enum Route {
    /// Along the curve through a path file's keyframes (CSV or GeoJSON, [`path::read_path`]).
    Path(PathBuf),
    /// Along the curve through keyframes given in memory (each [`Keyframe::at`] names it in
    /// messages).
    Keyframes {
        /// The keyframes, in file coordinates.
        keyframes: Vec<Keyframe>,
        /// How the manifest and messages name them.
        name: PathBuf,
    },
    /// One frame at each station of the E57 scan, with the station's heading.
    Stations,
}

impl std::fmt::Display for Route {
    /// The path file, the keyframes' name, or `stations`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Route::Path(p) | Route::Keyframes { name: p, .. } => write!(f, "{}", p.display()),
            Route::Stations => f.write_str("stations"),
        }
    }
}

/// A tour laid out on a loaded scan.
#[derive(Debug, Clone)]
pub struct Tour {
    /// The scan, its local zero at [`Tour::origin`].
    pub scene: Scene,
    /// The local zero of every frame, file coordinates.
    pub origin: DVec3,
    /// Keyframes with their heights resolved, file coordinates (duplicates dropped).
    pub keyframes: Vec<DVec3>,
    /// Length of the curve, file units.
    pub length: f64,
    /// Eye height above the ground where the path gives no z, file units.
    pub eye_height: f64,
    /// Every frame's camera.
    pub poses: Vec<Pose>,
    /// What loading the scan file did (points dropped for bad coordinates); `None` for
    /// points given in memory.
    pub load_report: Option<crate::io::LoadReport>,
    /// For a tour of a survey's stations: the station each frame stands at, in frame order.
    pub stations: Vec<crate::frames::StationMark>,
    /// Points in the scan file when [`Tour::scene`] holds only its coarse levels (a COPC
    /// file of more than [`PLAN_SURVEY_POINTS`] points, planned on
    /// [`lod::survey`]); `None` when it is the whole scan. [`Tour::load_whole`] reads the rest.
    pub surveyed_from: Option<u64>,
}

impl Tour {
    /// Reads the whole scan into [`Tour::scene`] (around the tour's origin, as `request`
    /// reads it) when the tour was planned on coarse levels; nothing otherwise.
    ///
    /// # Errors
    /// The scan's loading errors.
    pub fn load_whole(
        &mut self,
        request: &TourRequest,
        progress: &ProgressBar,
    ) -> Result<(), TourError> {
        if self.surveyed_from.is_none() {
            return Ok(());
        }
        let TourScan::File(file) = &request.scan else {
            return Ok(());
        };
        let prepared = prepare(file, &tour_options(request, self.origin), progress)?;
        self.scene = prepared.scene;
        self.load_report = Some(prepared.report);
        self.surveyed_from = None;
        Ok(())
    }
}

/// The options `request` reads its scan with for a tour around `origin`.
fn tour_options(request: &TourRequest, origin: DVec3) -> PrepareOptions {
    PrepareOptions {
        origin: Some(origin),
        camera: crate::prepare::CameraChoice::At(origin),
        ..request.prepare
    }
}

/// What a tour is planned on: the scan, what loading it did, its median point spacing (for
/// the eye height), and the file's point count when only its coarse levels were read.
struct PlanningRead {
    scene: Scene,
    report: Option<crate::io::LoadReport>,
    spacing: Option<f32>,
    surveyed_from: Option<u64>,
}

/// Reads `file` for planning a tour around `options.origin`: at most `budget` points of the
/// coarse levels of a larger COPC file ([`lod::survey`]: the ground and the bounds need no
/// more), else every point.
fn planning_read(
    file: &Path,
    options: &PrepareOptions,
    budget: u64,
    progress: &ProgressBar,
) -> Result<PlanningRead, TourError> {
    if let Some(survey) = lod::survey(file, options, budget, progress)? {
        return Ok(PlanningRead {
            scene: survey.prepared.scene,
            report: Some(survey.prepared.report),
            spacing: survey.detail_spacing,
            surveyed_from: Some(survey.points_total),
        });
    }
    let prepared = prepare(file, options, progress)?;
    let spacing = crate::prepare::radius::median_spacing(&prepared.scene);
    Ok(PlanningRead {
        scene: prepared.scene,
        report: Some(prepared.report),
        spacing,
        surveyed_from: None,
    })
}

/// Why a tour could not be laid out.
#[derive(Debug, thiserror::Error)]
pub enum TourError {
    /// The path file could not be read.
    #[error(transparent)]
    Path(#[from] PathError),
    /// The scan could not be read.
    #[error(transparent)]
    Prepare(#[from] PrepareError),
    /// The scan's stations could not be read.
    #[error(transparent)]
    Stations(#[from] stations::StationError),
    /// The path is readable but not usable on this scan.
    #[error("{}: {message}", path.display())]
    BadPath {
        /// The path file, or the name of the keyframes.
        path: PathBuf,
        /// What is wrong, naming the line or feature.
        message: String,
    },
}

/// Reads the path (or takes the keyframes given), loads the scan once around a fixed origin
/// (the centre of the path's keyframes, in whole metres; points in memory are moved onto it)
/// and places every frame on the curve. A path without heights
/// walks `request.height` above the ground (sampled along the curve and smoothed; speed is
/// then measured over the ground plan); a path with some heights puts the missing ones
/// `request.height` above the ground under their keyframes.
///
/// # Errors
/// The path file's errors (naming line or feature), fewer than two distinct keyframes, a
/// keyframe outside the scan's bounds, and the scan's loading errors.
pub fn plan(request: &TourRequest, progress: &ProgressBar) -> Result<Tour, TourError> {
    plan_surveying(request, PLAN_SURVEY_POINTS, progress)
}

/// [`plan`], a COPC file of more than `survey` points planned on its coarse levels.
fn plan_surveying(
    request: &TourRequest,
    survey: u64,
    progress: &ProgressBar,
) -> Result<Tour, TourError> {
    let bad = |message: String| TourError::BadPath {
        path: request.route.to_string().into(),
        message,
    };
    let mut keyframes = match &request.route {
        Route::Path(file) => path::read_path(file)?,
        Route::Keyframes { keyframes, .. } => keyframes.clone(),
        Route::Stations => return plan_stations(request, survey, progress),
    };
    // Consecutive repeats (common in exported lines) add nothing to the curve.
    keyframes.dedup_by(|b, a| a.x == b.x && a.y == b.y && a.z == b.z);
    if keyframes.len() < 2 {
        let at = keyframes.first().map_or("", |k| k.at.as_str());
        return Err(bad(format!(
            "a path needs at least two distinct points; found one ({at})"
        )));
    }

    let header = match &request.scan {
        TourScan::File(file) => header_bounds(file),
        TourScan::Points { scene, info, .. } => info
            .as_ref()
            .and_then(|info| plausible(info.bounds))
            .or_else(|| scene.bounds().map(|(lo, hi)| world_bounds(scene, lo, hi))),
    };
    let origin = path_origin(&keyframes, header);
    let options = tour_options(request, origin);
    let read = match &request.scan {
        TourScan::File(file) => planning_read(file, &options, survey, progress)?,
        TourScan::Points { scene, name, .. } => {
            let scene = prepare_scene(Scene::clone(scene), &options, name)?.scene;
            PlanningRead {
                spacing: crate::prepare::radius::median_spacing(&scene),
                scene,
                report: None,
                surveyed_from: None,
            }
        }
    };
    let scene = read.scene;
    // The header's bounds when it has them (the numbers `omnicloud info` shows; in file axes,
    // so not for a Y-up file), else the points'.
    let header = header.filter(|_| request.prepare.up == crate::io::Up::Z);
    let (lo, hi) = header.unwrap_or_else(|| {
        let (lo, hi) = scene
            .bounds()
            .expect("a prepared scene has at least one point");
        world_bounds(&scene, lo, hi)
    });
    let height = request.height.over(read.spacing);
    let ground = ground::GroundIndex::new(&scene);
    // A path without any height walks over the ground; one with some heights keeps them
    // and puts only the missing ones on the ground.
    let follow_ground = keyframes.iter().all(|k| k.z.is_none());
    let mut resolved = Vec::with_capacity(keyframes.len());
    for k in &keyframes {
        if !(lo.x..=hi.x).contains(&k.x) || !(lo.y..=hi.y).contains(&k.y) {
            let degrees = k.x.abs() <= 180.0 && k.y.abs() <= 90.0 && hi.x.abs() > 360.0;
            return Err(bad(format!(
                "{}: ({}, {}) lies outside the scan's bounds x {:.3} .. {:.3}, y {:.3} .. {:.3} \
                 of {}{}",
                k.at,
                k.x,
                k.y,
                lo.x,
                hi.x,
                lo.y,
                hi.y,
                request.scan.name().display(),
                if degrees {
                    " (the path looks like longitude/latitude: export it in the scan's \
                     coordinate system)"
                } else {
                    ""
                }
            )));
        }
        let z = match k.z {
            Some(z) => z,
            None if follow_ground => 0.0,
            None => {
                let local = Vec2::new((k.x - origin.x) as f32, (k.y - origin.y) as f32);
                let ground = ground.height(local).ok_or_else(|| {
                    bad(format!(
                        "{}: no ground found under ({}, {})",
                        k.at, k.x, k.y
                    ))
                })?;
                origin.z + ground + height
            }
        };
        resolved.push(DVec3::new(k.x, k.y, z));
    }
    resolved.dedup();
    let curve = spline::Spline::new(&resolved).ok_or_else(|| {
        bad("a path needs at least two distinct points after heights are resolved".into())
    })?;
    let heading = match keyframes
        .iter()
        .map(|k| k.yaw)
        .collect::<Option<Vec<f64>>>()
    {
        Some(yaws) if yaws.len() == resolved.len() => Heading::Keyframes(yaws),
        _ => Heading::Tangent {
            window: request.heading_window,
        },
    };
    let mut poses = poses::sample(&curve, request.sampling, &heading, request.yaw_offset);
    let pitches: Vec<f64> = keyframes.iter().map(|k| k.pitch).collect();
    let rolls: Vec<f64> = keyframes.iter().map(|k| k.roll).collect();
    let tilts = (pitches.len() == resolved.len()).then_some((&pitches[..], &rolls[..]));
    poses::tilt(
        &mut poses,
        &curve,
        tilts,
        request.pitch_offset,
        request.roll_offset,
    );
    if follow_ground {
        let local = |s: f64| curve.position(s) - origin;
        let profile = ground::GroundProfile::new(&ground, curve.length(), local).map_err(|s| {
            let p = curve.position(s);
            bad(format!(
                "no ground found under the path at ({:.3}, {:.3}), {s:.1} m from its start",
                p.x, p.y
            ))
        })?;
        let z = |s: f64| origin.z + profile.at(s) + height;
        for pose in &mut poses {
            pose.position[2] = z(pose.arc_length);
        }
        for (i, k) in resolved.iter_mut().enumerate() {
            k.z = z(curve.keyframe_arc_length(i));
        }
    }
    Ok(Tour {
        scene,
        origin,
        keyframes: resolved,
        length: curve.length(),
        eye_height: height,
        poses,
        load_report: read.report,
        stations: Vec::new(),
        surveyed_from: read.surveyed_from,
    })
}

/// One frame at each station of the scan (those its `#scan:` pick names), each with its
/// station's heading plus the request's offsets; the scan loaded once around the stations'
/// centre (in whole metres). Arc lengths run along the straight legs between stations.
fn plan_stations(
    request: &TourRequest,
    survey: u64,
    progress: &ProgressBar,
) -> Result<Tour, TourError> {
    let scan = match &request.scan {
        TourScan::File(file) => file,
        TourScan::Points { name, .. } => {
            return Err(TourError::BadPath {
                path: name.clone(),
                message: "stations are read from an E57 file, not from points in memory".into(),
            });
        }
    };
    let stations = stations::read_stations(scan)?;
    let (lo, hi) = stations
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s.position), hi.max(s.position))
        });
    let origin = ((lo + hi) * 0.5).round();
    let read = planning_read(scan, &tour_options(request, origin), survey, progress)?;
    let mut arc_length = 0.0;
    let mut previous = stations.first().map(|s| s.position);
    let poses = stations
        .iter()
        .map(|s| {
            arc_length += previous.map_or(0.0, |p| p.distance(s.position));
            previous = Some(s.position);
            Pose {
                position: s.position.to_array(),
                yaw: poses::wrap_degrees(s.yaw + request.yaw_offset),
                pitch: request.pitch_offset,
                roll: request.roll_offset,
                arc_length,
            }
        })
        .collect();
    let eye_height = request.height.over(read.spacing);
    Ok(Tour {
        scene: read.scene,
        origin,
        keyframes: stations.iter().map(|s| s.position).collect(),
        length: arc_length,
        eye_height,
        poses,
        load_report: read.report,
        surveyed_from: read.surveyed_from,
        stations: stations
            .iter()
            .enumerate()
            .map(|(frame, s)| crate::frames::StationMark {
                frame,
                scan: s.index,
                name: s.name.clone(),
                position: s.position.to_array(),
            })
            .collect(),
    })
}

/// The XY-plausible bounds of the scan's header, file coordinates.
fn header_bounds(scan: &Path) -> Option<(DVec3, DVec3)> {
    plausible(crate::io::open(scan).ok()?.info().bounds)
}

/// `bounds` when they are finite and not inverted in XY.
fn plausible(bounds: Option<(DVec3, DVec3)>) -> Option<(DVec3, DVec3)> {
    let (lo, hi) = bounds?;
    (lo.is_finite() && hi.is_finite() && lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// Local bounds `lo`, `hi` of `scene` in file coordinates.
fn world_bounds(scene: &Scene, lo: glam::Vec3, hi: glam::Vec3) -> (DVec3, DVec3) {
    (scene.origin + lo.as_dvec3(), scene.origin + hi.as_dvec3())
}

/// The tour's local zero: the centre of the keyframes' bounds in whole metres; its height
/// from the keyframes that give one, else from the scan's `bounds` (0 without them).
fn path_origin(keyframes: &[Keyframe], bounds: Option<(DVec3, DVec3)>) -> DVec3 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for k in keyframes.iter() {
        let p = DVec3::new(k.x, k.y, k.z.unwrap_or(f64::NAN));
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let mut c = (lo + hi) * 0.5;
    if !c.z.is_finite() {
        c.z = bounds.map_or(0.0, |(lo, hi)| (lo.z + hi.z) * 0.5);
    }
    c.round()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{LoadOptions, load_files_with_progress};

    const SCAN: &str = "data/autzen_trim.laz";
    const WALK: &str = "data/tours/autzen_walk.csv";

    fn request(scan: TourScan, route: Route) -> TourRequest {
        TourRequest {
            scan,
            route,
            prepare: PrepareOptions::default(),
            height: EyeHeight::new(None, 1.0 / 0.3048),
            sampling: Sampling::Frames(5),
            heading_window: 2.0,
            yaw_offset: 0.0,
            pitch_offset: 0.0,
            roll_offset: 0.0,
        }
    }

    /// The sample read into memory as a caller holds it, with its header.
    fn points() -> TourScan {
        let file = PathBuf::from(SCAN);
        let (scene, report) = load_files_with_progress(
            std::slice::from_ref(&file),
            &LoadOptions::default(),
            &ProgressBar::hidden(),
        )
        .unwrap();
        TourScan::Points {
            scene: Arc::new(scene),
            info: Some(Box::new(report.info)),
            name: file,
        }
    }

    #[test]
    fn points_and_keyframes_in_memory_plan_the_tour_of_the_files() {
        let from_files = plan(
            &request(TourScan::File(SCAN.into()), Route::Path(WALK.into())),
            &ProgressBar::hidden(),
        )
        .unwrap();
        let keyframes = path::read_path(Path::new(WALK)).unwrap();
        let in_memory = plan(
            &request(
                points(),
                Route::Keyframes {
                    keyframes,
                    name: "walk".into(),
                },
            ),
            &ProgressBar::hidden(),
        )
        .unwrap();
        assert_eq!(from_files.origin, DVec3::new(636600.0, 849175.0, 463.0));
        assert_eq!(in_memory.origin, from_files.origin);
        // The same points after the same rounding: the same ground, so the same poses.
        assert_eq!(in_memory.scene.positions, from_files.scene.positions);
        assert_eq!(in_memory.poses, from_files.poses);
        assert_eq!(in_memory.poses.len(), 5);
        assert!(
            (from_files.length - 461.0).abs() < 0.05,
            "{}",
            from_files.length
        );
        assert!(from_files.load_report.is_some() && in_memory.load_report.is_none());
    }

    #[test]
    fn keyframes_off_the_points_are_refused_naming_the_keyframes() {
        let keyframe = |x: f64, y: f64, at: &str| Keyframe {
            x,
            y,
            z: None,
            yaw: None,
            pitch: 0.0,
            roll: 0.0,
            at: at.into(),
        };
        let path = Route::Keyframes {
            keyframes: vec![
                keyframe(636400.0, 849100.0, "row 0"),
                keyframe(0.0, 0.0, "row 1"),
            ],
            name: "<path array>".into(),
        };
        let e = plan(&request(points(), path), &ProgressBar::hidden()).unwrap_err();
        let message = e.to_string();
        assert!(
            message.starts_with("<path array>: row 1: (0, 0) lies outside the scan's bounds")
                && message.contains(SCAN),
            "{message}"
        );
    }

    #[test]
    fn a_copc_tour_planned_on_its_coarse_levels_walks_where_the_whole_scan_does() {
        let dir = tempfile::tempdir().unwrap();
        let copc = dir.path().join("autzen.copc.laz");
        crate::index::index(
            &[PathBuf::from(SCAN)],
            &copc,
            &crate::index::IndexOptions::default(),
            &ProgressBar::hidden(),
        )
        .unwrap();
        let request = request(TourScan::File(copc.clone()), Route::Path(WALK.into()));
        let hidden = ProgressBar::hidden();
        let whole = plan_surveying(&request, u64::MAX, &hidden).unwrap();
        let mut surveyed = plan_surveying(&request, 1 << 16, &hidden).unwrap();
        let total = whole.scene.len() as u64;
        assert_eq!(whole.surveyed_from, None);
        assert_eq!(surveyed.surveyed_from, Some(total));
        let read = surveyed.scene.len() as u64;
        assert!(read <= 1 << 16 && read * 2 < total, "{read} of {total}");
        assert_eq!(surveyed.origin, whole.origin);
        // The eye height from the spacing of a few full-detail patches against every point's
        // (measured 2.8 % apart).
        let height = surveyed.eye_height / whole.eye_height;
        assert!((height - 1.0).abs() < 0.03, "{height}");
        assert_eq!(surveyed.poses.len(), whole.poses.len());
        // The ground under the walk, from a third of the points: within 0.7 ft (the file is in
        // feet; measured 0.65 ft where a cell of the estimator holds a point or two. A survey
        // of a large file holds tens per cell; from a sixth of Autzen it differed by 5.5 ft).
        let mut worst = 0.0f64;
        for (s, w) in surveyed.poses.iter().zip(&whole.poses) {
            assert_eq!(s.position[..2], w.position[..2]);
            assert_eq!(s.yaw, w.yaw);
            let ground = |p: &Pose, eye: f64| p.position[2] - eye;
            let dz = (ground(s, surveyed.eye_height) - ground(w, whole.eye_height)).abs();
            worst = worst.max(dz);
        }
        assert!(worst < 0.7, "{worst} ft");
        // Reading the rest gives the points a whole read does.
        surveyed.load_whole(&request, &hidden).unwrap();
        assert_eq!(surveyed.surveyed_from, None);
        assert_eq!(surveyed.scene.positions, whole.scene.positions);
    }
}
