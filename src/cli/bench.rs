//! `omnicloud bench`: one scan, or the stability suite, through every rasterizer mode.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use glam::DVec3;
use indicatif::ProgressBar;

use crate::bench::{self, BenchConfig, BenchMode};
use crate::io::Up;
use crate::prepare::filter::ReturnFilter;
use crate::prepare::{LodChoice, PrepareOptions, prepare};
use crate::projection::Image;
use crate::render::{ColorMode, RenderSettings};

use super::options::ViewArgs;
use super::{parse, progress};

/// Options of `omnicloud bench`.
#[derive(Debug, Clone, Args)]
pub struct BenchArgs {
    /// A LAS, LAZ or PLY file to benchmark (or use --suite).
    #[arg(required_unless_present = "suite", conflicts_with = "suite")]
    pub scene: Option<PathBuf>,
    /// Benchmark every scene of the stability suite in DIR (its suite.json).
    #[arg(long, value_name = "DIR")]
    pub suite: Option<PathBuf>,
    /// Image width per eye [1920 for a scan; the manifest's width for --suite].
    #[arg(long, value_parser = parse::width)]
    pub width: Option<u32>,
    /// Scene, camera and stereo (with --suite only --stereo and its ODS options: the manifest
    /// places each view, and the scene and camera options are refused).
    #[command(flatten)]
    pub view: ViewArgs,
    /// Modes to time, comma-separated, as PROXY+IMPOSTER (e.g. quad+sprite,bounds+raycast)
    /// [all ten].
    #[arg(long, value_delimiter = ',', value_parser = BenchMode::parse)]
    pub modes: Option<Vec<BenchMode>>,
    /// Frames rendered before timing starts.
    #[arg(long, default_value = "2")]
    pub warmup: usize,
    /// Frames timed per mode (the report gives their median).
    #[arg(long, default_value = "5", value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub frames: u64,
    /// Output folder for bench.json, bench.csv, bench.md and the charts.
    #[arg(long, default_value = "bench_out")]
    pub out: PathBuf,
    /// With a stereo setting, do not time a mono frame after each stereo frame (the report's
    /// "stereo / mono" row): halves the run.
    #[arg(long)]
    pub no_mono_baseline: bool,
    /// Compare stereo methods instead of timing rasterizer modes: exact ODS, the paper's
    /// per-vertex offset, parallel cameras and cube maps, ray traced; charts their angular
    /// disparity error against exact ODS by longitude and latitude.
    #[arg(long, conflicts_with_all = ["suite", "modes"])]
    pub stereo_methods: bool,
    /// Cube-map face sizes for --stereo-methods.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "256,512,1024",
        value_name = "N,N,..."
    )]
    pub cubemap_faces: Vec<u32>,
    /// Level of detail for a COPC file (.copc.laz), as `render` reads it: `on` (the default)
    /// reads the octree nodes whose point spacing seen from the camera is a pixel or more of
    /// the benchmarked width, a number of pixels sets that threshold, `off` reads every point.
    #[arg(long, value_name = "on|off|PIXELS")]
    pub lod: Option<LodChoice>,
    /// Level of detail: points a view reads at least, where the file holds them; past the
    /// threshold it refines the nodes that look coarsest first (a scan this small is drawn
    /// whole, as with `--lod off`); 0 keeps the threshold alone.
    #[arg(long, default_value_t = crate::prepare::lod::LOD_FLOOR_POINTS, value_name = "POINTS")]
    pub lod_floor: u64,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Width used for a scan when `--width` is not given.
const DEFAULT_WIDTH: u32 = 1920;

/// The modes to time: those given, else all ten; a scan in another projection than the full
/// equirect is drawn with `bounds+raycast` only.
fn modes(args: &BenchArgs) -> Result<Vec<bench::BenchMode>> {
    let projection = args.view.projection;
    let drawn = |m: &bench::BenchMode| {
        args.suite.is_some() || crate::raster::draws(projection, m.proxy, m.imposter)
    };
    let Some(given) = &args.modes else {
        return Ok(bench::BenchMode::all().into_iter().filter(drawn).collect());
    };
    let refused: Vec<String> = given
        .iter()
        .filter(|m| !drawn(m))
        .map(|m| m.label())
        .collect();
    if !refused.is_empty() {
        bail!(
            "--modes {}: the rasterizer draws --projection {projection} with bounds+raycast \
             only (billboard proxies and sprites are equirect-only)",
            refused.join(",")
        );
    }
    Ok(given.clone())
}

/// The scene and camera options `view` sets that `--suite` would ignore: its manifest
/// places each view and prepares each scene.
fn ignored_by_suite(view: &ViewArgs, lod: Option<LodChoice>) -> Vec<&'static str> {
    [
        ("--camera", view.camera.is_some()),
        ("--yaw", view.yaw != 0.0),
        ("--pitch", view.pitch != 0.0),
        ("--roll", view.roll != 0.0),
        ("--projection", !view.projection.is_full_equirect()),
        ("--radius", view.radius.is_some()),
        ("--up", view.up != Up::default()),
        ("--classes", view.classes.is_some()),
        ("--drop-classes", view.drop_classes.is_some()),
        ("--returns", view.returns != ReturnFilter::default()),
        ("--crop", view.crop.is_some()),
        ("--max-distance", view.max_distance.is_some()),
        ("--units", view.units != crate::prepare::Units::default()),
        ("--lod", lod.is_some()),
    ]
    .into_iter()
    .filter_map(|(name, set)| set.then_some(name))
    .collect()
}

/// Runs `omnicloud bench`.
pub fn run(given: &BenchArgs) -> Result<()> {
    // A scan's lengths are converted from `--units` to its unit; a suite's scenes are metric.
    let scale = match &given.scene {
        Some(file) if given.suite.is_none() => {
            Some(given.view.length_scale(&crate::io::read_info(file)?))
        }
        _ => None,
    };
    let converted;
    let args = match &scale {
        Some(scale) => {
            converted = BenchArgs {
                view: given.view.in_file_units(scale),
                ..given.clone()
            };
            &converted
        }
        None => given,
    };
    if args.suite.is_some() {
        let ignored = ignored_by_suite(&args.view, args.lod);
        if !ignored.is_empty() {
            bail!(
                "--suite places each view and prepares each scene from its manifest: {} \
                 would be ignored (drop them, or bench a scan with them)",
                ignored.join(", ")
            );
        }
    }
    let config = BenchConfig {
        width: args.width,
        stereo: args.view.stereo_mode(),
        depth_map: args.view.depth_map()?,
        modes: modes(args)?,
        warmup_frames: args.warmup,
        timed_frames: args.frames as usize,
        mono_baseline: !args.no_mono_baseline,
    };
    let pb = progress::bar(args.quiet, 0, "benchmark");
    let written = if let Some(dir) = &args.suite {
        let report = bench::run_suite(dir, &config, &pb)?;
        pb.finish_and_clear();
        let files = bench::write_suite_outputs(&report, &args.out)?;
        vec![
            files.json,
            files.csv,
            files.markdown,
            files.bands_png,
            files.bands_svg,
        ]
    } else {
        let file = args
            .scene
            .as_ref()
            .expect("clap requires a scene without --suite");
        let say = |m: String| {
            if !args.quiet {
                eprintln!("{m}");
            }
        };
        let width = args.width.unwrap_or(DEFAULT_WIDTH);
        let options = PrepareOptions {
            lod: args
                .lod
                .unwrap_or(LodChoice::Pixels(1.0))
                .at_width(width)
                .with_floor(args.lod_floor),
            // The benchmark colours as `auto` does.
            fields: ColorMode::Auto.fields(),
            ..args.view.prepare_options()
        };
        let prepared = prepare(file, &options, &ProgressBar::hidden())?;
        if let Some(lod) = &prepared.lod {
            say(format!("{}: {lod}", file.display()));
        }
        super::notes::say_load_notes(file, &prepared.report, &say);
        let scale = scale.expect("a scan's scale");
        super::notes::say_units(
            &prepared.report.info,
            &scale,
            &given.view.given_lengths(),
            &say,
        );
        let c = prepared.camera_world;
        say(format!(
            "{}: {} points, camera at ({:.3}, {:.3}, {:.3})",
            file.display(),
            prepared.scene.len(),
            c.x,
            c.y,
            c.z
        ));
        let mut base = RenderSettings::new(width, args.view.camera_at(DVec3::ZERO));
        if args.view.projection.is_map() {
            bail!("bench times views from a camera: --projection map has none");
        }
        base.image = Image::new(args.view.projection, base.image.width)
            .map_err(|e| anyhow!("--width: {e}"))?;
        base.color = ColorMode::Auto;
        let name = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        if args.stereo_methods {
            return stereo_methods(args, &prepared.scene, &base, &pb);
        }
        let mut report = bench::run_bench(&name, &prepared.scene, &base, &config, &pb)?;
        report.metres_per_unit = scale.metres_per_unit;
        report.level_of_detail = prepared.lod;
        pb.finish_and_clear();
        let files = bench::write_outputs(&report, &args.out)?;
        vec![
            files.json,
            files.csv,
            files.markdown,
            files.chart_png,
            files.chart_svg,
        ]
    };
    if !args.quiet {
        if let Some(md) = written
            .iter()
            .find(|p| p.extension().is_some_and(|e| e == "md"))
        {
            println!("{}", std::fs::read_to_string(md)?);
        }
        for p in &written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}

/// `bench --stereo-methods`: every stereo method ray traced at `base`, compared by disparity.
fn stereo_methods(
    args: &BenchArgs,
    scene: &crate::scene::Scene,
    base: &RenderSettings,
    pb: &ProgressBar,
) -> Result<()> {
    if let Some(&n) = args
        .cubemap_faces
        .iter()
        .find(|n| !crate::projection::StereoKind::FACE_SIZES.contains(n))
    {
        anyhow::bail!("--cubemap-faces: a face is 16..=8192 pixels, got {n}");
    }
    let options = bench::stereo_methods::StereoMethodsOptions {
        ipd: args.view.ipd,
        merging: args.view.merging(),
        faces: args.cubemap_faces.clone(),
    };
    let tracer = crate::raytrace::Tracer::new(scene)?;
    let report = bench::stereo_methods::run(&tracer, scene, base, &options, pb)?;
    pb.finish_and_clear();
    let written = bench::stereo_methods::write_outputs(&report, &args.out)?;
    if !args.quiet {
        println!("{}", bench::stereo_methods::markdown(&report));
        for p in &written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}
