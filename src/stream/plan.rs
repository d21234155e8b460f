//! Planning a streamed render from a survey of the whole file: the camera, the sphere radius,
//! the colour ranges and the 16-bit colour scale are decided once, before any chunk is drawn,
//! so every chunk is placed, sized and coloured alike.
//!
//! A file of at most [`PlanOptions::survey_points`] points is read whole by
//! [`crate::prepare::prepare`]: the decisions are then exactly the in-core path's (that and
//! `render::base_colors`) and the cloud is kept for drawing. A larger file
//! is surveyed in up to [`SURVEY_BLOCKS`] evenly spaced contiguous blocks: contiguous so the
//! median spacing (auto radius) measures the real local density, not a thinned one; spread
//! so the sample covers the file's whole extent. The camera's XY centre comes from the
//! header bounds when the format has trustworthy ones (the sample may miss the edges).
//!
//! Several files ([`plan_files`]) are planned as one cloud: their declared counts add up for
//! the choice between reading whole and surveying, the survey budget is shared in proportion
//! to each file's count, and the header extent is the union of theirs.

use super::StreamError;
use crate::io::{self, ColorScale, LoadError, LoadOptions, PointReader, RawChunk, RawRgb, Up};
use crate::prepare::filter::{Stage, files_to_read};
use crate::prepare::{
    CameraChoice, FilterCounts, FilterError, PointFilter, PrepareError, PrepareOptions, Prepared,
    RadiusRule, placement, prepare_files, radius,
};
use crate::render::{ColorMode, ColorRule};
use crate::scene::{Attributes, Radii, Returns, Scene, extend_masked, masked};
use glam::DVec3;
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};

/// Points read by the survey at most.
pub const SURVEY_POINTS: usize = 1 << 21;

/// Most blocks the survey reads.
pub const SURVEY_BLOCKS: usize = 32;

/// Fewest points per survey block when the budget allows: a block must hold whole
/// neighbourhoods for the spacing it shows to be the local one.
pub const MIN_BLOCK_POINTS: usize = 4096;

/// Points decoded per read while surveying.
const READ_POINTS: usize = 65_536;

/// What a plan may be told; the rest is decided from the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanOptions {
    /// Camera, up axis and radius rule, as the in-core [`prepare`] takes them.
    pub prepare: PrepareOptions,
    /// Colour mode, resolved on the survey.
    pub color: ColorMode,
    /// Points the survey reads at most; files this small are read whole.
    pub survey_points: usize,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            prepare: PrepareOptions::default(),
            color: ColorMode::Auto,
            survey_points: SURVEY_POINTS,
        }
    }
}

/// Everything a stream needs decided before its first chunk.
#[derive(Debug, Clone)]
pub struct StreamPlan {
    /// The (first) file.
    pub path: PathBuf,
    /// Its header facts (format, coordinate system and its units).
    pub info: io::FileInfo,
    /// Every file, streamed in this order.
    pub paths: Vec<PathBuf>,
    /// Point count from the header (the sum over all files).
    pub declared: u64,
    /// Up axis of the file.
    pub up: Up,
    /// Camera world position (given or automatic).
    pub camera: DVec3,
    /// How spheres are sized: adaptive radii are found within each streamed chunk
    /// (`--radius adaptive`), and the rule's `radius` is then the survey's median.
    pub radii: RadiusRule,
    /// Colour mode with its ranges fixed on the survey (heights relative to the camera).
    pub color: ColorRule,
    /// How 16-bit colour becomes 8-bit, from the survey's largest channel value.
    pub color_scale: ColorScale,
    /// Points the survey read.
    pub surveyed: u64,
    /// The whole cloud when the survey read every point: relative to `camera`, radii applied,
    /// unusable points dropped. The stream then draws it without reading the file again.
    pub whole: Option<Scene>,
    /// Unusable points (NaN/inf/absurd coordinates) the survey saw.
    pub dropped: u64,
    /// The filters, applied to each streamed chunk.
    pub filter: PointFilter,
    /// Points each filter removed from `whole`, files skipped included (only the skipped
    /// files' when the files are streamed: the stream counts the rest).
    pub filtered: FilterCounts,
    /// What the files skipped unread ([`crate::prepare::filter::files_to_read`]) count for.
    pub skipped: FilterCounts,
    /// What a view-dependent COPC read chose (the plan then holds the read cloud whole);
    /// `None` when every point is drawn.
    pub lod: Option<crate::prepare::LodReport>,
}

impl StreamPlan {
    /// A chunk as a scene relative to the camera, sized by the plan's radius rule; returns it
    /// and the number of unusable points dropped.
    pub fn chunk_scene(&self, chunk: io::PointChunk) -> (Scene, u64) {
        super::chunk_scene(chunk, self.camera, self.up, &self.radii)
    }
}

/// Surveys `path` and decides the camera, radius and colours of a streamed render (see the
/// module docs). `progress` counts the points surveyed.
///
/// # Errors
/// A [`LoadError`] from reading (also when no point is usable), a colour mode whose attribute
/// the file lacks, or a camera that cannot be placed automatically.
pub fn plan(
    path: &Path,
    options: &PlanOptions,
    progress: &ProgressBar,
) -> Result<StreamPlan, StreamError> {
    plan_files(&[path.to_path_buf()], options, progress)
}

/// [`plan`] for several files streamed as one scene (see the module docs).
///
/// # Errors
/// As [`plan`], naming the file at fault; a filter whose attribute a file lacks.
///
/// # Panics
/// When `paths` is empty.
pub fn plan_files(
    paths: &[PathBuf],
    options: &PlanOptions,
    progress: &ProgressBar,
) -> Result<StreamPlan, StreamError> {
    let mut infos = Vec::with_capacity(paths.len());
    for p in paths {
        let info = io::open(p)?.info().clone();
        options
            .prepare
            .filter
            .check(&info)
            .map_err(PrepareError::from)?;
        infos.push(info);
    }
    let (read, skipped) = files_to_read(paths, &infos, &options.prepare);
    if read.is_empty() {
        return Err(PrepareError::from(FilterError::NothingLeft { counts: skipped }).into());
    }
    let infos: Vec<io::FileInfo> = infos
        .into_iter()
        .filter(|i| read.contains(&i.path))
        .collect();
    let declared = infos.iter().map(|i| i.point_count).sum();
    // A view-dependent COPC read holds only what the view needs: it is read whole.
    let lod = options.prepare.lod != crate::prepare::Lod::Off && infos.iter().all(io::is_copc);
    let mut plan = if lod || declared <= options.survey_points as u64 {
        plan_whole(&read, declared, options, progress)?
    } else {
        plan_sampled(&read, &infos, options, progress)?
    };
    plan.filtered += skipped;
    plan.skipped = skipped;
    Ok(plan)
}

/// The whole file read as the in-core path reads it.
fn plan_whole(
    paths: &[PathBuf],
    declared: u64,
    options: &PlanOptions,
    progress: &ProgressBar,
) -> Result<StreamPlan, StreamError> {
    let Prepared {
        scene,
        camera_world,
        radii,
        report,
        filtered,
        lod,
    } = prepare_files(paths, &options.prepare, progress)?;
    let color = ColorRule::for_scene(&scene, options.color)?;
    Ok(StreamPlan {
        path: paths[0].clone(),
        info: report.info,
        paths: paths.to_vec(),
        declared,
        up: options.prepare.up,
        camera: camera_world,
        radii,
        color,
        color_scale: report.color_scale.unwrap_or(ColorScale::Direct8),
        surveyed: report.points_read,
        whole: Some(scene),
        dropped: report.dropped_nonfinite,
        filter: options.prepare.filter,
        filtered,
        skipped: FilterCounts::default(),
        lod,
    })
}

/// `(first point, points)` of the survey blocks: evenly spaced, centred in equal segments of
/// the file, ascending and disjoint when `declared > survey_points`.
pub fn survey_blocks(declared: u64, survey_points: usize) -> Vec<(u64, u64)> {
    let survey_points = survey_points.max(1);
    let count = (survey_points / MIN_BLOCK_POINTS).clamp(1, SURVEY_BLOCKS) as u64;
    let len = (survey_points as u64 / count).min(declared);
    (0..count)
        .map(|k| {
            let mid = ((2 * k + 1) as u128 * declared as u128 / (2 * count) as u128) as u64;
            (mid.saturating_sub(len / 2).min(declared - len), len)
        })
        .collect()
}

/// Usable points of the survey, world coordinates, with their raw attributes.
#[derive(Debug, Default, PartialEq)]
struct Sample {
    world: Vec<DVec3>,
    rgb: Option<RawRgb>,
    intensity: Option<Vec<u16>>,
    classification: Option<Vec<u8>>,
    returns: Option<Vec<Returns>>,
    radius: Option<Vec<f32>>,
    read: u64,
    dropped: u64,
}

impl Sample {
    fn push(&mut self, raw: RawChunk, up: Up) {
        self.push_where(raw, up, &|_| true);
    }

    /// [`Sample::push`], keeping only the usable points `inside` accepts (world coordinates).
    fn push_where(&mut self, raw: RawChunk, up: Up, inside: &dyn Fn(DVec3) -> bool) {
        self.read += raw.positions.len() as u64;
        let world: Vec<DVec3> = raw.positions.iter().map(|p| up.to_world(*p)).collect();
        let usable: Vec<bool> = world.iter().map(|p| io::usable(*p)).collect();
        self.dropped += usable.iter().filter(|k| !**k).count() as u64;
        let kept: Vec<bool> = world
            .iter()
            .zip(&usable)
            .map(|(p, u)| *u && inside(*p))
            .collect();
        self.world.extend(masked(&world, &kept));
        match (raw.rgb, &mut self.rgb) {
            (Some(RawRgb::Bits8(c)), Some(RawRgb::Bits8(acc))) => acc.extend(masked(&c, &kept)),
            (Some(RawRgb::Bits16(c)), Some(RawRgb::Bits16(acc))) => acc.extend(masked(&c, &kept)),
            (Some(RawRgb::Bits8(c)), acc @ None) => {
                *acc = Some(RawRgb::Bits8(masked(&c, &kept).collect()));
            }
            (Some(RawRgb::Bits16(c)), acc @ None) => {
                *acc = Some(RawRgb::Bits16(masked(&c, &kept).collect()));
            }
            // A reader keeps one colour kind per file.
            _ => {}
        }
        extend_masked(&mut self.intensity, raw.intensity.as_deref(), &kept);
        extend_masked(
            &mut self.classification,
            raw.classification.as_deref(),
            &kept,
        );
        extend_masked(&mut self.returns, raw.returns.as_deref(), &kept);
        extend_masked(&mut self.radius, raw.radius.as_deref(), &kept);
    }

    /// Appends another file's sample.
    fn append(&mut self, other: Sample) {
        fn join<T>(a: &mut Option<Vec<T>>, b: Option<Vec<T>>) {
            match (a.as_mut(), b) {
                (Some(a), Some(b)) => a.extend(b),
                (None, Some(b)) => *a = Some(b),
                _ => {}
            }
        }
        self.world.extend(other.world);
        match (&mut self.rgb, other.rgb) {
            (Some(RawRgb::Bits8(a)), Some(RawRgb::Bits8(b))) => a.extend(b),
            (Some(RawRgb::Bits16(a)), Some(RawRgb::Bits16(b))) => a.extend(b),
            (a @ None, b) => *a = b,
            _ => {}
        }
        join(&mut self.intensity, other.intensity);
        join(&mut self.classification, other.classification);
        join(&mut self.returns, other.returns);
        join(&mut self.radius, other.radius);
        self.read += other.read;
        self.dropped += other.dropped;
    }

    /// Leaves out attributes that do not cover every point (some file lacks them).
    fn drop_partial_attributes(&mut self) {
        fn whole<T>(v: &mut Option<Vec<T>>, n: usize) {
            if v.as_ref().is_some_and(|v| v.len() != n) {
                *v = None;
            }
        }
        let n = self.world.len();
        let rgb_len = match &self.rgb {
            Some(RawRgb::Bits8(v)) => v.len(),
            Some(RawRgb::Bits16(v)) => v.len(),
            None => n,
        };
        if rgb_len != n {
            self.rgb = None;
        }
        whole(&mut self.intensity, n);
        whole(&mut self.classification, n);
        whole(&mut self.returns, n);
        whole(&mut self.radius, n);
    }
}

/// Reads the survey blocks; seeks between them (when `seekable`), or reads past the gaps
/// when the file cannot seek (a LAZ file without a chunk table).
fn survey(
    path: &Path,
    mut reader: PointReader,
    blocks: &[(u64, u64)],
    up: Up,
    progress: &ProgressBar,
    mut seekable: bool,
) -> Result<Sample, LoadError> {
    let mut sample = Sample::default();
    let mut at = 0u64;
    'blocks: for &(start, len) in blocks {
        if start != at && seekable {
            match reader.seek(start) {
                Ok(()) => at = start,
                Err(_) => {
                    // The reader's position is unknown after a failed seek: start again.
                    seekable = false;
                    reader = io::open(path)?;
                    at = 0;
                }
            }
        }
        while at < start {
            let n = (start - at).min(READ_POINTS as u64) as usize;
            match reader.next_raw(n)? {
                Some(raw) => at += raw.positions.len() as u64,
                None => break 'blocks,
            }
        }
        let end = start + len;
        while at < end {
            let n = (end - at).min(READ_POINTS as u64) as usize;
            let Some(raw) = reader.next_raw(n)? else {
                break 'blocks;
            };
            let got = raw.positions.len() as u64;
            at += got;
            progress.inc(got);
            sample.push(raw, up);
        }
    }
    Ok(sample)
}

/// Reads the files in order and keeps the usable points `inside` accepts, up to `budget` of
/// them: the survey of a region the evenly spaced blocks may miss.
fn survey_inside(
    paths: &[PathBuf],
    up: Up,
    budget: usize,
    progress: &ProgressBar,
    inside: &dyn Fn(DVec3) -> bool,
) -> Result<Sample, LoadError> {
    let mut sample = Sample::default();
    for path in paths {
        let mut reader = io::open(path)?;
        progress.inc_length(reader.info().point_count);
        while let Some(raw) = reader.next_raw(READ_POINTS)? {
            progress.inc(raw.positions.len() as u64);
            sample.push_where(raw, up, inside);
            if sample.world.len() >= budget {
                return Ok(sample);
            }
        }
    }
    Ok(sample)
}

/// Large files planned from their survey blocks.
fn plan_sampled(
    paths: &[PathBuf],
    infos: &[io::FileInfo],
    options: &PlanOptions,
    progress: &ProgressBar,
) -> Result<StreamPlan, StreamError> {
    let path = paths[0].as_path();
    let declared: u64 = infos.iter().map(|i| i.point_count).sum();
    let up = options.prepare.up;
    let budget = |n: u64| {
        ((options.survey_points as u128 * n as u128 / declared.max(1) as u128) as usize).max(1)
    };
    let blocks: Vec<Vec<(u64, u64)>> = infos
        .iter()
        .map(|i| survey_blocks(i.point_count, budget(i.point_count)))
        .collect();
    progress.set_length(blocks.iter().flatten().map(|b| b.1).sum());
    let mut sample = Sample::default();
    for (p, blocks) in paths.iter().zip(&blocks) {
        let reader = io::open(p)?;
        sample.append(survey(p, reader, blocks, up, progress, true)?);
    }
    // A small crop may miss every survey block: survey the points inside it instead.
    if let Some(crop) = options.prepare.filter.crop {
        let inside = sample
            .world
            .iter()
            .filter(|w| crop.contains(**w, up))
            .count();
        if inside < MIN_BLOCK_POINTS {
            sample = survey_inside(paths, up, options.survey_points, progress, &|w| {
                crop.contains(w, up)
            })?;
        }
    }
    sample.drop_partial_attributes();
    if sample.world.is_empty() {
        return Err(if sample.read == 0 {
            LoadError::NoPoints {
                path: path.to_path_buf(),
            }
        } else {
            LoadError::NoFinitePoints {
                path: path.to_path_buf(),
                dropped: sample.dropped,
            }
        }
        .into());
    }
    let (lo, hi) = sample
        .world
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    // Header bounds are trusted as the cloud's extent only if plausible and the sample lies
    // inside them (load_scene's test for its origin).
    let header = io::header_extent(infos, up)
        .filter(|(blo, bhi)| {
            io::usable(*blo)
                && io::usable(*bhi)
                && (*bhi - *blo).max_element() <= io::MAX_HEADER_EXTENT
        })
        .filter(|(blo, bhi)| {
            let slack = DVec3::splat(1.0) + (*bhi - *blo) * 0.01;
            lo.cmpge(*blo - slack).all() && hi.cmple(*bhi + slack).all()
        });
    let (extent_lo, extent_hi) = header.unwrap_or((lo, hi));
    let origin = (extent_lo + extent_hi) * 0.5;
    // The camera stands in the cropped part of the extent.
    let (extent_lo, extent_hi) = match options.prepare.filter.crop {
        Some(crop) => {
            let (a, b) = crop.world_rect(up);
            let lo = extent_lo.truncate().max(a).min(b);
            let hi = extent_hi.truncate().min(b).max(lo);
            (lo.extend(extent_lo.z), hi.extend(extent_hi.z))
        }
        None => (extent_lo, extent_hi),
    };

    let color_scale = sample
        .rgb
        .as_ref()
        .and_then(RawRgb::max_16)
        .map_or(ColorScale::Direct8, ColorScale::detect_16);
    let radii = Radii::from_file(sample.radius, LoadOptions::default().default_radius);
    let scene = Scene {
        origin,
        positions: sample
            .world
            .iter()
            .map(|p| (*p - origin).as_vec3())
            .collect(),
        radii,
        attributes: Attributes {
            rgb: sample.rgb.map(|c| c.into_u8(color_scale)),
            intensity: sample.intensity,
            classification: sample.classification,
            returns: sample.returns,
        },
    };
    let filter = options.prepare.filter;
    // Counts on the survey only say why nothing is left; the stream counts the real ones.
    let (mut scene, sample_counts) = filter.apply(scene, up, Stage::BeforeCamera);
    if scene.is_empty() {
        return Err(PrepareError::from(FilterError::NothingLeft {
            counts: sample_counts,
        })
        .into());
    }
    let camera = match options.prepare.camera {
        CameraChoice::At(c) => c,
        choice => {
            let centre = ((extent_lo + extent_hi) * 0.5 - origin)
                .truncate()
                .as_vec2();
            let extent = (extent_hi - extent_lo).truncate().max_element() as f32;
            // A survey reads blocks of the file, not every point near the eye: it cannot tell
            // open space, so `auto` stands at the centre at its default height.
            let given = options.prepare.height;
            let height = match choice {
                CameraChoice::Auto => placement::EyeHeight {
                    given: Some(given.over(radius::median_spacing(&scene))),
                    ..given
                },
                _ => given,
            };
            origin
                + placement::camera_position_in(
                    &scene,
                    centre,
                    extent,
                    CameraChoice::Center,
                    height,
                )
                .ok_or_else(|| PrepareError::CameraPlacement {
                    path: path.to_path_buf(),
                })?
        }
    };
    scene.recenter(camera);
    let (mut scene, after) = filter.apply(scene, up, Stage::AfterCamera);
    if scene.is_empty() {
        let mut counts = sample_counts;
        counts += after;
        return Err(PrepareError::from(FilterError::NothingLeft { counts }).into());
    }
    let radii = radius::apply_choice(&mut scene, options.prepare.radius);
    let color = ColorRule::for_scene(&scene, options.color)?;
    Ok(StreamPlan {
        path: path.to_path_buf(),
        info: infos[0].clone(),
        paths: paths.to_vec(),
        declared,
        up,
        camera,
        radii,
        color,
        color_scale,
        surveyed: sample.read,
        whole: None,
        dropped: sample.dropped,
        filter,
        filtered: FilterCounts::default(),
        skipped: FilterCounts::default(),
        lod: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::{RadiusChoice, prepare};
    use crate::render::base_colors;

    /// The generated building the integration tests read too (an ASCII PLY with properties
    /// a reader skips).
    mod building {
        include!("../../tests/data_common/building.rs");
    }

    /// A file of laspy's test data, kept in tests/data/laspy/.
    fn laspy(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/laspy")
            .join(name)
    }

    /// [`building`] written into a temporary folder (kept while the guard lives).
    fn building_ply() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("building.ply");
        building::write_building_ply(&path).unwrap();
        (dir, path)
    }

    /// A file small enough to be read whole is planned exactly as the in-core path
    /// ([`prepare`] + `base_colors`) would render it: same camera, radii, positions and
    /// colours.
    #[test]
    fn small_files_are_planned_exactly_as_in_core() {
        let autzen = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz");
        let (_dir, building) = building_ply();
        let cases: Vec<(PathBuf, Option<DVec3>, Option<RadiusChoice>, ColorMode)> = vec![
            (autzen.clone(), None, None, ColorMode::Auto),
            (autzen.clone(), None, None, ColorMode::Elevation),
            (
                autzen,
                None,
                Some(RadiusChoice::Fixed(0.3)),
                ColorMode::Intensity,
            ),
            (laspy("simple.las"), None, None, ColorMode::Auto),
            (
                laspy("simple.laz"),
                None,
                Some(RadiusChoice::Auto),
                ColorMode::Classification,
            ),
            (laspy("simple1_4.las"), None, None, ColorMode::Elevation),
            (laspy("vegetation_1_3.las"), None, None, ColorMode::Auto),
            (laspy("1_4_w_evlr.laz"), None, None, ColorMode::Intensity),
            // A given camera: the header bounds' centre, off the ground.
            (
                laspy("vegetation_1_3.las"),
                Some(DVec3::NAN),
                None,
                ColorMode::Elevation,
            ),
            (building, None, None, ColorMode::Auto),
        ];
        for (path, camera, radius, color) in cases {
            let camera = camera.map(|_| {
                let (lo, hi) = io::open(&path).unwrap().info().bounds.unwrap();
                (lo + hi) * 0.5 + DVec3::new(0.3, -0.2, 1.0)
            });
            let prepare_options = PrepareOptions {
                camera: camera.map_or(CameraChoice::Auto, CameraChoice::At),
                up: Up::Z,
                radius,
                ..PrepareOptions::default()
            };
            let options = PlanOptions {
                prepare: prepare_options,
                color,
                ..PlanOptions::default()
            };
            let plan = plan(&path, &options, &ProgressBar::hidden()).unwrap();
            let core = prepare(&path, &prepare_options, &ProgressBar::hidden()).unwrap();
            let name = path.display();
            assert_eq!(plan.camera, core.camera_world, "{name}");
            let whole = plan.whole.as_ref().expect("a small file is read whole");
            assert_eq!(plan.surveyed, plan.declared, "{name}");
            assert_eq!(whole.origin, core.scene.origin, "{name}");
            assert_eq!(whole.positions, core.scene.positions, "{name}");
            assert_eq!(whole.radii, core.scene.radii, "{name}");
            match &core.scene.radii {
                Radii::Uniform(r) => {
                    assert!(plan.radii.radius == *r && !plan.radii.keep_file_radii)
                }
                Radii::PerPoint(_) => {
                    assert!(plan.radii.keep_file_radii || plan.radii.adaptive.is_some())
                }
            }
            assert_eq!(
                plan.color.colors(whole).unwrap(),
                base_colors(&core.scene, color).unwrap(),
                "{name}"
            );
        }
    }

    /// Reading past the gaps (the fallback for files that cannot seek) surveys the same
    /// points as seeking.
    #[test]
    fn survey_by_seeking_equals_survey_by_reading_past_gaps() {
        let (_dir, building) = building_ply();
        for path in [
            Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz"),
            building,
            laspy("simple1_4.las"),
        ] {
            let declared = io::open(&path).unwrap().info().point_count;
            let blocks = survey_blocks(declared, 9_000);
            let hidden = ProgressBar::hidden();
            let read = |seek| {
                let reader = io::open(&path).unwrap();
                survey(&path, reader, &blocks, Up::Z, &hidden, seek).unwrap()
            };
            let (sought, sequential) = (read(true), read(false));
            assert_eq!(sought.read, 9_000, "{}", path.display());
            assert!(sought == sequential, "{}", path.display());
        }
    }

    #[test]
    fn blocks_are_spread_disjoint_and_inside_the_file() {
        for (declared, budget) in [
            (200_000u64, 20_000usize),
            (50_000_000, SURVEY_POINTS),
            (5, 4),
        ] {
            let blocks = survey_blocks(declared, budget);
            let total: u64 = blocks.iter().map(|b| b.1).sum();
            assert!(total <= budget as u64 && total + blocks.len() as u64 > budget as u64);
            for w in blocks.windows(2) {
                assert!(w[0].0 + w[0].1 <= w[1].0, "{blocks:?}");
            }
            let (first, last) = (blocks[0], blocks[blocks.len() - 1]);
            assert!(last.0 + last.1 <= declared);
            // Centred in equal segments: the first starts within one segment of the start,
            // symmetric to the last's end.
            let segment = declared / blocks.len() as u64;
            assert!(first.0 < segment && declared - (last.0 + last.1) < segment);
            assert!(
                first.0.abs_diff(declared - (last.0 + last.1)) <= 2,
                "{blocks:?}"
            );
        }
        assert_eq!(survey_blocks(200_000, 20_000).len(), 4);
        assert_eq!(
            survey_blocks(50_000_000, SURVEY_POINTS).len(),
            SURVEY_BLOCKS
        );
    }
}
