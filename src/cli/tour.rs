//! `omnicloud tour`: a camera path through a scan, one frame per pose, resumable and
//! shardable across batch schedulers.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;

use crate::memory;
use crate::prepare::lod::NodeRadii;
use crate::prepare::{LengthScale, LodChoice, RadiusChoice};
use crate::projection::Image;
use crate::render::RendererKind;
use crate::renderer::{DrawsFrames, Resident};
use crate::scene::Radii;
use crate::tour::{
    self, FrameFormat, RunOptions, Sampling, Shard, ShardChoice, TourRequest, TourScan, shard,
};

use super::options::{DrawArgs, LookArgs, ViewArgs};
use super::progress;
use super::render_args::RenderArgs;

/// Options of `omnicloud tour`.
#[derive(Debug, Clone, Args)]
#[command(
    mut_arg("yaw", |a| a.help(
        "Degrees added to every frame's heading (90 looks right of the direction of travel)"
    )),
    mut_arg("camera", |a| a.hide(true)),
)]
pub struct TourArgs {
    /// A LAS, LAZ, PLY or E57 file.
    pub file: PathBuf,
    /// The camera path: CSV with a header (x,y[,z][,yaw,pitch,roll]) or a GeoJSON
    /// LineString/MultiLineString, in the scan's coordinates.
    #[arg(
        long,
        value_name = "PATH.csv|PATH.geojson",
        required_unless_present = "stations",
        conflicts_with = "stations"
    )]
    pub path: Option<PathBuf>,
    /// One frame at each station of an E57 file instead of a path: where each scan's
    /// scanner stood, with its heading (--yaw is added; --scan picks the stations).
    #[arg(long)]
    pub stations: bool,
    /// Output folder for frame_000000.png ... and tour.json.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: PathBuf,
    /// Eye height above the ground where the path gives no z, metres [default: 1.7, or 20
    /// median point spacings when higher (sparse aerial data), as `render` places its eye].
    #[arg(long, value_name = "H", value_parser = parse_height)]
    pub height: Option<f64>,
    /// Walking speed along the path, metres per second.
    #[arg(long, default_value = "1.4", value_parser = parse_positive)]
    pub speed: f64,
    /// Frames per second of the video the frames make.
    #[arg(long, default_value = "30", value_parser = parse_positive)]
    pub fps: f64,
    /// Render this many frames evenly along the path instead (ignores --speed).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub frames: Option<u64>,
    /// Metres of path over which the heading follows the averaged tangent, so turns at
    /// keyframes ease in and out (0: the exact tangent). Ignored when the path gives yaw.
    #[arg(long, default_value = "2", value_parser = parse_non_negative)]
    pub heading_smoothing: f64,
    /// Frame file format.
    #[arg(long, value_enum, ignore_case = true, default_value = "png")]
    pub format: FrameFormat,
    /// JPEG quality (with --format jpg).
    #[arg(long, default_value = "90", value_parser = clap::value_parser!(u8).range(1..=100))]
    pub quality: u8,
    /// Re-render frames whose file already exists (by default they are skipped).
    #[arg(long)]
    pub overwrite: bool,
    /// Render only shard I of N (contiguous frame ranges), or `auto`: from Slurm job arrays,
    /// Kubernetes Indexed Jobs (with --shards) or GNU parallel (with --shards).
    #[arg(long, value_name = "I/N|auto")]
    pub shard: Option<ShardChoice>,
    /// Number of shards for `--shard auto` under Kubernetes or GNU parallel.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub shards: Option<u32>,
    /// Image width, colour, shading, renderer and rasterizer modes.
    #[command(flatten)]
    pub draw: DrawArgs,
    /// Scene and stereo (--camera is refused: the path places the camera; --yaw is added to
    /// every frame's heading).
    #[command(flatten)]
    pub view: ViewArgs,
    /// Eye-dome lighting, supersampling, background (as `render` takes them).
    #[command(flatten)]
    pub look: LookArgs,
    /// Level of detail for COPC files (.copc.laz, from `omnicloud index`): `on` reads, per
    /// frame, the octree nodes whose point spacing seen from the camera is a pixel or more,
    /// a number of pixels sets that threshold, `off` keeps every point resident.
    #[arg(long, default_value = "on", value_name = "on|off|PIXELS")]
    pub lod: LodChoice,
    /// Level of detail: points a view reads at least, where the file holds them; past the
    /// threshold it refines the nodes that look coarsest first (a scan this small is drawn
    /// whole, as with `--lod off`); 0 keeps the threshold alone.
    #[arg(long, default_value_t = crate::prepare::lod::LOD_FLOOR_POINTS, value_name = "POINTS")]
    pub lod_floor: u64,
    /// Memory cap: the ray tracer's scene and BVH, or the level of detail's nodes kept on the
    /// GPU between frames, e.g. 2G [default: 80% of the available memory, at most 2 GiB of
    /// nodes].
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Also encode the frames into this H.264 MP4 with 360 metadata once all are rendered
    /// (as `omnicloud video`; with --shard, run that after the last shard instead).
    #[arg(long, value_name = "OUT.mp4")]
    pub video: Option<PathBuf>,
}

impl TourArgs {
    /// These options with every length (`--height`, `--speed`, `--heading-smoothing` and
    /// [`ViewArgs::in_file_units`]'s) converted by `scale` into file units.
    pub fn in_file_units(&self, scale: &LengthScale) -> TourArgs {
        if self.view.scale.is_some() {
            return self.clone();
        }
        TourArgs {
            height: self.height.map(|h| scale.height(h)),
            speed: scale.length(self.speed),
            heading_smoothing: scale.length(self.heading_smoothing),
            view: self.view.in_file_units(scale),
            ..self.clone()
        }
    }

    /// [`ViewArgs::given_lengths`] with `--height` when given and `--speed` when it spaces
    /// the frames.
    pub fn given_lengths(&self) -> Vec<(&'static str, f64)> {
        let mut given = self.view.given_lengths();
        if let Some(h) = self.height {
            given.push(("--height", h));
        }
        if self.frames.is_none() {
            given.push(("--speed", self.speed));
        }
        given
    }
}

fn parse_positive(s: &str) -> Result<f64, String> {
    let v = crate::value::finite(s, "a positive number")?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("`{s}` must be greater than 0"))
    }
}

fn parse_non_negative(s: &str) -> Result<f64, String> {
    let v = crate::value::finite(s, "metres")?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("`{s}` must not be negative"))
    }
}

fn parse_height(s: &str) -> Result<f64, String> {
    crate::value::finite(s, "metres above the ground")
}

/// Runs `omnicloud render --camera station:all -o DIR`: a tour of the file's stations, one
/// panorama each, with `render`'s options (frames as PNG, resumable, `--shard` as a tour).
pub fn run_stations(render: &RenderArgs, matches: &clap::ArgMatches) -> Result<()> {
    let single = [
        ("--depth", render.depth.is_some()),
        ("--anaglyph", render.anaglyph.is_some()),
        ("--disparity", render.disparity.is_some()),
        ("--origin", render.origin.is_some()),
        ("--separate-eyes", render.separate_eyes),
        ("--comfort", render.comfort),
    ];
    if let Some((name, _)) = single.iter().find(|(_, given)| *given) {
        bail!("{name} is for one panorama: --camera station:all writes a folder of them");
    }
    let tour = TourArgs {
        file: render.file.clone(),
        path: None,
        stations: true,
        output: render.output.clone(),
        height: render.height,
        speed: 1.4,
        fps: 30.0,
        frames: None,
        heading_smoothing: 0.0,
        format: FrameFormat::Png,
        quality: render.quality,
        overwrite: false,
        lod: render.lod,
        lod_floor: render.lod_floor,
        shard: render.shard,
        shards: render.shards,
        draw: render.draw.clone(),
        view: ViewArgs {
            camera: None,
            ..render.view.clone()
        },
        look: render.look.clone(),
        max_memory: render.max_memory,
        quiet: render.quiet,
        video: None,
    };
    run(&tour, matches)
}

/// Runs `omnicloud tour`: lengths converted from `--units` to the scan's unit.
pub fn run(given: &TourArgs, matches: &clap::ArgMatches) -> Result<()> {
    let info = crate::io::read_info(&given.file)?;
    let scale = given.view.length_scale(&info);
    let args = &given.in_file_units(&scale);
    let say = |msg: String| {
        if !args.quiet {
            eprintln!("{msg}");
        }
    };
    if args.view.camera.is_some() {
        bail!("tour places the camera along --path: drop --camera");
    }
    check_video(args)?;
    if args.look.wants_alpha() && args.format == FrameFormat::Jpg {
        bail!(
            "a JPEG has no alpha, so its background cannot be transparent: use --format png \
             or exr, or give a colour (--background black)"
        );
    }
    if args.view.projection.is_map() {
        bail!("a tour looks around from each pose: --projection map has no camera to move");
    }
    let image =
        Image::new(args.view.projection, args.draw.width).map_err(|e| anyhow!("--width: {e}"))?;
    args.look.look().render_image(&image)?;
    let shard = match args.shard {
        None => Shard::ALL,
        Some(ShardChoice::Given(s)) => s,
        Some(ShardChoice::Auto) => {
            let (s, source) = shard::from_environment(|k| std::env::var(k).ok(), args.shards)
                .map_err(anyhow::Error::msg)?;
            say(format!("shard {s} from {source}"));
            s
        }
    };
    super::interrupt::install_interrupt_handler();
    check_memory(args)?;

    let request = TourRequest {
        scan: TourScan::File(args.file.clone()),
        route: match &args.path {
            Some(p) => tour::Route::Path(p.clone()),
            None => tour::Route::Stations,
        },
        prepare: crate::prepare::PrepareOptions {
            fields: args.draw.color.fields(),
            ..args.view.prepare_options()
        },
        height: args.view.eye_height(args.height),
        sampling: match args.frames {
            Some(n) => Sampling::Frames(n as usize),
            None => Sampling::Speed {
                speed: args.speed,
                fps: args.fps,
            },
        },
        heading_window: args.heading_smoothing,
        yaw_offset: args.view.yaw,
        pitch_offset: args.view.pitch,
        roll_offset: args.view.roll,
    };
    let started = Instant::now();
    let pb = progress::bar(args.quiet, 0, "loading");
    let planned = tour::plan(&request, &pb);
    pb.finish_and_clear();
    let mut planned = planned?;
    if let Some(report) = &planned.load_report {
        super::notes::say_load_notes(&args.file, report, &say);
    }
    super::notes::say_units(&info, &scale, &given.given_lengths(), &say);
    let total = planned.poses.len();
    let unit = info.length_symbol();
    let points = match planned.surveyed_from {
        Some(all) => format!(
            "planned on {} of {all} points (its coarse levels),",
            planned.scene.len()
        ),
        None => format!("{} points", planned.scene.len()),
    };
    say(format!(
        "{}: {points} around origin ({}, {}, {}); path {} of {:.1} {unit} through {} keyframes, \
         eye {:.2} {unit} above the ground where it gives no z: {total} frames (prepared in \
         {:.2?})",
        args.file.display(),
        planned.origin.x,
        planned.origin.y,
        planned.origin.z,
        request.route,
        planned.length,
        planned.keyframes.len(),
        planned.eye_height,
        started.elapsed()
    ));

    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("creating the output folder {}", args.output.display()))?;
    let settings = args.draw.settings(
        &args.view,
        image,
        crate::projection::Camera::new(glam::DVec3::ZERO, 0.0),
    )?;
    let options = RunOptions {
        settings,
        dir: args.output.clone(),
        format: args.format,
        jpeg_quality: args.quality,
        fps: args.fps,
        overwrite: args.overwrite,
        render_command: super::render_command::render_command(
            &given.file.display().to_string(),
            matches,
        ),
        look: args.look.look(),
        metres_per_unit: scale.metres_per_unit,
    };
    let manifest = tour::run::manifest(&request, &planned, &options);
    let written = manifest.write(&args.output)?;
    say(format!("wrote {}", written.display()));

    let range = shard.frames(total);
    let (todo, skipped) = tour::run::frames_to_render(&options, range.clone());
    let removed = tour::run::remove_stale_temps(&options, &todo);
    if removed > 0 {
        say(format!(
            "removed {removed} unfinished temporary file(s) left by a killed run"
        ));
    }
    if args.shard.is_some() {
        say(format!(
            "shard {shard}: frames {}",
            if range.is_empty() {
                "none".to_string()
            } else {
                format!("{}..={}", range.start, range.end - 1)
            }
        ));
    }
    if !skipped.is_empty() {
        say(format!(
            "skipping {} frame(s) already rendered ({}); --overwrite re-renders them",
            skipped.len(),
            ranges(&skipped)
        ));
    }
    if todo.is_empty() {
        say("nothing to render".to_string());
        return encode_video(args, &say);
    }

    let nodes = node_stream(args, &info, &planned, &request, &settings, &say)?;
    let mut resident = None;
    let mut nodes = nodes;
    let renderer: &mut dyn DrawsFrames = match nodes.as_mut() {
        Some(stream) => {
            say(stream.describe());
            stream
        }
        None => {
            if planned.surveyed_from.is_some() {
                let pb = progress::bar(args.quiet, 0, "loading every point");
                let whole = planned.load_whole(&request, &pb);
                pb.finish_and_clear();
                whole?;
                if let Some(report) = &planned.load_report {
                    super::notes::say_load_notes(&args.file, report, &say);
                }
            }
            let kept = Resident::new(&planned.scene, args.draw.renderer, &settings).with_context(
                || format!("keeping {} resident for the tour", args.file.display()),
            )?;
            if kept.is_streamed() {
                // A warning, shown even with --quiet: every frame now re-sends the points.
                eprintln!("{}", kept.describe());
            } else {
                say(kept.describe());
            }
            resident.insert(kept)
        }
    };
    let log_path = args.output.join("tour.log");
    let mut log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&log_path)
        .with_context(|| format!("opening {}", log_path.display()))?;
    let pb = progress::bar(args.quiet, todo.len() as u64, "rendering");
    let report = tour::render_frames(&planned, renderer, &options, &todo, &pb, |i, path, took| {
        // One short line per frame: appends of this size do not interleave between shards.
        let _ = writeln!(
            log,
            "shard {shard}: rendered frame {i} ({}) in {:.3} s",
            path.file_name().unwrap_or_default().to_string_lossy(),
            took.as_secs_f64()
        );
    });
    pb.finish_and_clear();
    let report = report?;
    say(format!(
        "rendered {} frame(s) ({}) in {:.2?}: {:.2} frames/s sustained",
        report.rendered.len(),
        ranges(&report.rendered),
        report.busy,
        report.sustained_fps()
    ));
    if let Some(stream) = &nodes {
        let c = stream.cache_counts();
        let (used, budget) = stream.cache_bytes();
        say(format!(
            "node cache: {} read and uploaded, {} reused, {} evicted; {} of {} on the GPU; \
             {} node draws skipped as hidden behind nearer ones",
            c.misses,
            c.hits,
            c.evicted,
            crate::memory::format_size(used),
            crate::memory::format_size(budget),
            stream.hidden_nodes()
        ));
    }
    encode_video(args, &say)
}

/// Default bound of the level of detail's node cache.
const DEFAULT_NODE_CACHE: u64 = 2 << 30;

/// The level-of-detail node stream a tour of a COPC file draws through on the rasterizer;
/// `None` (every point resident) with `--lod off`, another format, the ray tracer, or radii
/// the nodes cannot reproduce alone (adaptive radii measured on the whole scan).
fn node_stream(
    args: &TourArgs,
    info: &crate::io::FileInfo,
    planned: &tour::Tour,
    request: &TourRequest,
    settings: &crate::render::RenderSettings,
    say: &impl Fn(String),
) -> Result<Option<crate::renderer::NodeStream>> {
    let LodChoice::Pixels(pixels) = args.lod else {
        return Ok(None);
    };
    if args.draw.renderer != RendererKind::Raster || !crate::io::is_copc(info) {
        return Ok(None);
    }
    let Some(radii) = node_radii(&args.file, info, args.view.radius, &planned.scene, say) else {
        return Ok(None);
    };
    let color = crate::render::ColorRule::for_scene(&planned.scene, settings.color)?;
    let budget = node_cache_budget(args.max_memory);
    let options = crate::prepare::PrepareOptions {
        origin: Some(planned.origin),
        ..request.prepare
    };
    let rasterizer = crate::raster::Rasterizer::new()?;
    let stream = crate::renderer::NodeStream::new(
        rasterizer,
        &args.file,
        &options,
        crate::renderer::NodeRules {
            radii,
            color,
            pixels,
            floor: args.lod_floor,
            budget,
        },
        settings,
    )
    .with_context(|| format!("reading the octree of {}", args.file.display()))?;
    Ok(Some(stream))
}

/// How the nodes of the COPC file `path` are sized when drawn alone, as `scene` (read
/// whole, with `radius` as given) was: the radii the file stores, or one radius; `None`, after
/// saying why, for adaptive radii, which are measured on the whole scan.
pub(super) fn node_radii(
    path: &std::path::Path,
    info: &crate::io::FileInfo,
    radius: Option<RadiusChoice>,
    scene: &crate::Scene,
    say: &impl Fn(String),
) -> Option<NodeRadii> {
    match (radius, &scene.radii) {
        (None, Radii::PerPoint(_)) if info.attributes.radius => Some(NodeRadii::File),
        (Some(RadiusChoice::Fixed(r)), _) => Some(NodeRadii::Base(r)),
        (Some(RadiusChoice::Auto), Radii::Uniform(r)) => Some(NodeRadii::Base(*r)),
        _ => {
            say(format!(
                "{}: level of detail off: its adaptive radii are measured on the whole scan \
                 (index it with `omnicloud index`, which stores them, or give --radius \
                 LENGTH|auto)",
                path.display()
            ));
            None
        }
    }
}

/// Bytes of level-of-detail nodes kept on the GPU: `max_memory` when given, else 80 % of the
/// available memory, at most [`DEFAULT_NODE_CACHE`].
pub(super) fn node_cache_budget(max_memory: Option<u64>) -> u64 {
    max_memory.unwrap_or_else(|| {
        memory::default_cap().map_or(DEFAULT_NODE_CACHE, |c| c.min(DEFAULT_NODE_CACHE))
    })
}

/// Refuses `--video` before anything is loaded or rendered when the frames could not be
/// encoded (too large for the encoder or H.264 level 5.1, odd sizes) or with `--shard`.
fn check_video(args: &TourArgs) -> Result<()> {
    let Some(out) = &args.video else {
        return Ok(());
    };
    if args.shard.is_some() {
        bail!(
            "--video encodes the whole tour, and a shard renders part of it: once every shard \
             has finished, run `omnicloud video {} -o {}`",
            args.output.display(),
            out.display()
        );
    }
    if !args.view.projection.is_full_equirect() {
        bail!(
            "--video {} tags its frames as 360° equirectangular: it needs --projection equirect",
            out.display()
        );
    }
    let height = args.draw.width / 2 * args.view.eyes();
    crate::video::level::level_for(args.draw.width, height, args.fps, 0)
        .with_context(|| format!("--video {} at --width {}", out.display(), args.draw.width))?;
    Ok(())
}

/// Encodes the tour's frames into `--video`, when asked.
fn encode_video(args: &TourArgs, say: &impl Fn(String)) -> Result<()> {
    let Some(out) = &args.video else {
        return Ok(());
    };
    let options = crate::video::VideoOptions {
        fps: Some(args.fps),
        ..crate::video::VideoOptions::default()
    };
    let pb = progress::bar(args.quiet, 0, "encoding");
    let report = crate::video::encode_folder(&args.output, out, &options, &pb)
        .with_context(|| format!("encoding {} into {}", args.output.display(), out.display()))?;
    say(format!(
        "wrote {}: {} frames {}x{} at {} fps, {}, H.264 level {}, {}",
        report.output.display(),
        report.frames,
        report.width,
        report.height,
        report.fps,
        report.stereo.name(),
        report.level.name,
        bytesize::ByteSize(report.bytes)
    ));
    Ok(())
}

/// Refuses, before loading, a ray-traced tour whose resident scene and BVH exceed the cap.
fn check_memory(args: &TourArgs) -> Result<()> {
    if args.draw.renderer != RendererKind::Raytrace {
        return Ok(());
    }
    let (cap, is_default) = match args.max_memory {
        Some(c) => (c, false),
        None => match memory::default_cap() {
            Some(c) => (c, true),
            None => return Ok(()),
        },
    };
    let info = crate::io::open(&args.file)?.info().clone();
    let width = args.draw.render_width(&args.look);
    let estimate = memory::raytrace_estimate_for(&info, 1, width, args.view.eyes());
    memory::check_budget(&args.file, &estimate, cap, is_default)?;
    Ok(())
}

/// Sorted frame numbers as ranges: `0-3, 7, 9-10`.
fn ranges(frames: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < frames.len() {
        let mut j = i;
        while j + 1 < frames.len() && frames[j + 1] == frames[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            frames[i].to_string()
        } else {
            format!("{}-{}", frames[i], frames[j])
        });
        i = j + 1;
    }
    out.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{Cli, Command};
    use clap::Parser;

    fn parse(extra: &[&str]) -> TourArgs {
        let argv = ["omnicloud", "tour", "s.laz", "--path", "p.csv", "-o", "d"]
            .iter()
            .chain(extra);
        match Cli::try_parse_from(argv).unwrap().command {
            Command::Tour(t) => t,
            _ => panic!("not tour"),
        }
    }

    #[test]
    fn defaults_match_the_documentation() {
        let t = parse(&[]);
        assert_eq!((t.height, t.speed, t.fps), (None, 1.4, 30.0));
        assert_eq!(
            (t.frames, t.format, t.shard),
            (None, FrameFormat::Png, None)
        );
        let t = parse(&["--frames", "12", "--shard", "1/3", "--format", "exr"]);
        assert_eq!(t.frames, Some(12));
        assert_eq!(t.shard, Some(ShardChoice::Given(Shard::new(1, 3).unwrap())));
        for bad in [&["--speed", "0"][..], &["--fps", "-1"], &["--frames", "0"]] {
            let argv = ["omnicloud", "tour", "s.laz", "--path", "p", "-o", "d"]
                .iter()
                .chain(bad);
            assert!(Cli::try_parse_from(argv).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn frame_lists_print_as_ranges() {
        assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0-3, 7, 9-10");
        assert_eq!(ranges(&[]), "");
    }
}

#[cfg(test)]
mod render_command_tests {
    use super::*;
    use crate::cli::options::ViewArgs;
    use crate::cli::render_args::RenderArgs;
    use crate::cli::render_command::{TOUR_ONLY, render_command};
    use clap::{ArgMatches, FromArgMatches};
    use proptest::prelude::*;

    /// Values each shared option may take, as a person types them (and as both commands
    /// parse them).
    const EXAMPLES: &[(&str, &[&str])] = &[
        ("width", &["256", "1024", "3840"]),
        (
            "color",
            &["auto", "rgb", "elevation", "classification", "flat"],
        ),
        ("shading", &["unlit", "phong", "normal"]),
        ("renderer", &["raster", "raytrace"]),
        ("proxy", &["quad", "static:8", "dynamic", "bounds"]),
        ("imposter", &["raycast", "sprite"]),
        (
            "projection",
            &[
                "equirect",
                "equirect:180,90",
                "hammer",
                "cylindrical:100",
                "fisheye:180",
                "cubemap",
            ],
        ),
        ("stereo", &["none", "ods", "parallel", "cubemap:256"]),
        ("ipd", &["0.064", "0.07", "0.05"]),
        (
            "pole_merge",
            &["off", "comfortable", "cycles:60,75", "marrinan:50,5,2"],
        ),
        ("pole_merge_north", &["off", "cycles:55.5,70"]),
        ("pole_merge_south", &["off", "marrinan:45,0,3"]),
        ("ods_offset", &["exact", "paper"]),
        ("depth_map", &["0.5=1.5,4=6.25", "1=2"]),
        ("radius", &["0.25", "auto", "adaptive:6"]),
        ("up", &["z", "y"]),
        ("scan", &["0", "1,Hall"]),
        ("classes", &["2,6", "2"]),
        ("drop_classes", &["7,18"]),
        ("returns", &["all", "first", "last"]),
        ("crop", &["-10,5,20,-5", "0,0,1,1"]),
        ("max_distance", &["150", "0.5"]),
        ("units", &["metres", "file"]),
        ("edl", &["1", "0.5"]),
        ("edl_radius", &["2", "1.4"]),
        ("supersample", &["1", "2", "3"]),
        (
            "background",
            &["black", "transparent", "#102030", "10,20,30"],
        ),
        ("quality", &["75", "90"]),
        ("lod_floor", &["0", "250000"]),
    ];

    /// The options `render_command` carries from a tour: `render`'s long options that
    /// `tour` also has, but for [`TOUR_ONLY`] and `--lod`.
    fn shared_options() -> Vec<String> {
        let tour = TourArgs::augment_args(clap::Command::new("tour"));
        let render = RenderArgs::augment_args(clap::Command::new("render"));
        render
            .get_arguments()
            .filter(|a| a.get_long().is_some())
            .map(|a| a.get_id().to_string())
            .filter(|id| !TOUR_ONLY.contains(&id.as_str()) && id != "lod")
            .filter(|id| tour.get_arguments().any(|t| t.get_id() == id.as_str()))
            .collect()
    }

    fn tour_with(extra: &[String]) -> (TourArgs, ArgMatches) {
        let argv = ["tour", "s.laz", "--path", "p.csv", "-o", "d"]
            .into_iter()
            .map(String::from)
            .chain(extra.iter().cloned());
        let matches = TourArgs::augment_args(clap::Command::new("tour"))
            .try_get_matches_from(argv)
            .unwrap();
        (TourArgs::from_arg_matches(&matches).unwrap(), matches)
    }

    /// `omnicloud render ...` as `render` parses it (from the word `render` on).
    fn render(argv: &[String]) -> RenderArgs {
        let argv = argv[1..]
            .iter()
            .cloned()
            .chain(["-o".into(), "x.png".into()]);
        let matches = RenderArgs::augment_args(clap::Command::new("render"))
            .try_get_matches_from(argv)
            .unwrap();
        RenderArgs::from_arg_matches(&matches).unwrap()
    }

    /// `view` without the options a tour sets per frame.
    fn per_tour(view: &ViewArgs) -> ViewArgs {
        ViewArgs {
            camera: None,
            yaw: 0.0,
            pitch: 0.0,
            roll: 0.0,
            ..view.clone()
        }
    }

    #[test]
    fn every_shared_option_has_examples() {
        let missing: Vec<String> = shared_options()
            .into_iter()
            .filter(|id| !EXAMPLES.iter().any(|(e, _)| e == id))
            .collect();
        assert!(
            missing.is_empty(),
            "render options a tour passes on without examples here: {missing:?}"
        );
        assert!(shared_options().len() >= 25, "{:?}", shared_options());
    }

    #[test]
    fn defaults_are_written_out_with_the_tours_level_of_detail() {
        let (t, m) = tour_with(&[]);
        let argv = render_command("s.laz", &m);
        assert_eq!(&argv[..3], ["omnicloud", "render", "s.laz"]);
        assert!(argv.contains(&"--width=3840".to_string()), "{argv:?}");
        assert!(argv.contains(&"--units=metres".to_string()), "{argv:?}");
        assert_eq!(argv.last().map(String::as_str), Some("--lod=on"));
        for tour_only in ["--camera", "--yaw", "--height", "-o", "--output", "--quiet"] {
            assert!(
                !argv.iter().any(|a| a.starts_with(tour_only)),
                "{tour_only} in {argv:?}"
            );
        }
        let r = render(&argv);
        assert_eq!(per_tour(&r.view), per_tour(&t.view));
        assert_eq!(r.lod, crate::prepare::LodChoice::Pixels(1.0));
        let (_, m) = tour_with(&["--lod=off".into()]);
        let argv = render_command("s.laz", &m);
        assert_eq!(argv.last().map(String::as_str), Some("--lod=off"));
        assert_eq!(render(&argv).lod, crate::prepare::LodChoice::Off);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// parse(serialise(args)) == args: any choice of shared options and values, given to
        /// `tour`, reads back from the generated `render` command as the same settings.
        #[test]
        fn the_render_command_reads_back_as_the_tours_settings(
            options in prop::sample::subsequence(
                (0..EXAMPLES.len()).collect::<Vec<_>>(),
                0..=EXAMPLES.len()
            ),
            values in prop::collection::vec(any::<prop::sample::Index>(), EXAMPLES.len())
        ) {
            let mut extra = Vec::new();
            for (option, value) in options.into_iter().zip(values) {
                let (id, values) = EXAMPLES[option];
                let long = id.replace('_', "-");
                extra.push(format!("--{long}={}", values[value.index(values.len())]));
            }
            let (t, m) = tour_with(&extra);
            let r = render(&render_command("s.laz", &m));
            prop_assert_eq!(per_tour(&r.view), per_tour(&t.view));
            prop_assert_eq!(&r.draw, &t.draw);
            prop_assert_eq!(&r.look, &t.look);
            prop_assert_eq!(r.quality, t.quality);
        }
    }
}
