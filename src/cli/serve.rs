//! `omnicloud serve`: loads a scan, draws its map, starts the live server, serves until
//! Ctrl-C.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::io::Up;
use crate::io::e57::ScanSelection;
use crate::prepare::lod::{self, PLAN_SURVEY_POINTS};
use crate::prepare::{
    EyeHeight, LengthScale, LodChoice, PrepareOptions, RadiusChoice, Units, prepare,
};
use crate::projection::Stereo;
use crate::render::{ColorMode, Shading};
use crate::web::serve::live::LiveScale;
use crate::web::serve::{LiveOptions, LiveScan, LiveServer, ServedLod, StreamOptions};

use super::{parse, progress, view};

/// Options of `omnicloud serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// A LAS, LAZ, PLY or E57 file.
    pub file: PathBuf,
    /// E57 scans to read, by index (from 0) or name, e.g. 0,2 or Hall [default: all]. The
    /// same as naming the file FILE#scan:0,2.
    #[arg(long, value_name = "N|NAME[,..]")]
    pub scan: Option<ScanSelection>,
    /// Address to listen on: 127.0.0.1 keeps it on this machine; 0.0.0.0 lets a headset on
    /// the network reach it (and everyone else there).
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value = "8360")]
    pub port: u16,
    /// Panorama width per eye; the ODS pair is WIDTH x WIDTH (top-bottom).
    #[arg(long, default_value = "2048", value_parser = parse::width)]
    pub width: u32,
    /// Camera height above the ground, metres, at the start and where the map is clicked
    /// [default: 1.7, or 20 median point spacings when higher (sparse aerial data), as
    /// `render` places its eye].
    #[arg(long, value_name = "H", value_parser = eye_height, allow_hyphen_values = true)]
    pub height: Option<f64>,
    /// The map's longer side, pixels.
    #[arg(long, default_value = "1024", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub map_size: u32,
    /// Sphere radius in metres, `auto` (half the median point spacing) or `adaptive[:K]`
    /// (per point, from K nearest neighbours). Default: the file's per-point `radius` when
    /// it has one, else adaptive:8.
    #[arg(long)]
    pub radius: Option<RadiusChoice>,
    /// Up axis of the file.
    #[arg(long, value_enum, ignore_case = true, default_value = "z")]
    pub up: Up,
    /// What the lengths given (--height, --radius, the page's IPD) are in: metres, converted
    /// to the unit the file's coordinate system declares, or the file's own unit.
    #[arg(long, value_enum, ignore_case = true, default_value = "metres")]
    pub units: Units,
    /// Point colour (auto: rgb when present, else elevation).
    #[arg(long, value_enum, ignore_case = true, default_value = "auto")]
    pub color: ColorMode,
    /// Shading.
    #[arg(long, value_enum, ignore_case = true, default_value = "unlit")]
    pub shading: Shading,
    /// Live stream (`/api/live`) while moving: `auto` lets the width drop (to a quarter at
    /// most) when frames render slower than 10 a second, `1` keeps every frame at --width.
    #[arg(long, default_value = "auto", value_name = "auto|1")]
    pub live_scale: LiveScale,
    /// Level of detail for COPC files (.copc.laz, from `omnicloud index`): `on` reads, per
    /// render, the octree nodes whose point spacing seen from the camera is a pixel or more
    /// and keeps them on the GPU for the next renders, a number of pixels sets that
    /// threshold, `off` keeps every point resident.
    #[arg(long, default_value = "on", value_name = "on|off|PIXELS")]
    pub lod: LodChoice,
    /// Level of detail: points a view reads at least, where the file holds them; past the
    /// threshold it refines the nodes that look coarsest first (a scan this small is drawn
    /// whole, as with `--lod off`); 0 keeps the threshold alone.
    #[arg(long, default_value_t = crate::prepare::lod::LOD_FLOOR_POINTS, value_name = "POINTS")]
    pub lod_floor: u64,
    /// Level of detail: bytes of nodes kept on the GPU between renders, e.g. 2G [default: 80%
    /// of the available memory, at most 2 GiB].
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
    /// Also open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
}

/// How a COPC file is served through its level of detail; `None` with `--lod off`, another
/// format, or adaptive radii (said why).
fn served_lod(
    args: &ServeArgs,
    prepared: &crate::prepare::Prepared,
    radius: Option<RadiusChoice>,
    say: &impl Fn(String),
) -> Option<ServedLod> {
    let LodChoice::Pixels(pixels) = args.lod else {
        return None;
    };
    let info = &prepared.report.info;
    if !crate::io::is_copc(info) {
        return None;
    }
    let radii = super::tour::node_radii(&args.file, info, radius, &prepared.scene, say)?;
    Some(ServedLod {
        path: args.file.clone(),
        up: args.up,
        radii,
        pixels,
        floor: args.lod_floor,
        budget: super::tour::node_cache_budget(args.max_memory),
    })
}

/// The coarse levels of the COPC file `args.file` (described by `info`) of more than
/// `budget` points, prepared ([`lod::survey`]), when every view of it is drawn through the
/// level of detail (`--lod` on, radii stored or given): the map, the ground and the bounds
/// need no more, and the rest need not be resident.
fn survey(
    args: &ServeArgs,
    info: &crate::io::FileInfo,
    options: &PrepareOptions,
    budget: u64,
    pb: &indicatif::ProgressBar,
) -> Result<Option<lod::Survey>> {
    let radii_known = match options.radius {
        None => info.attributes.radius,
        Some(RadiusChoice::Fixed(_) | RadiusChoice::Auto) => true,
        Some(RadiusChoice::Adaptive { .. }) => false,
    };
    if !matches!(args.lod, LodChoice::Pixels(_)) || !radii_known {
        return Ok(None);
    }
    Ok(lod::survey(&args.file, options, budget, pb)?)
}

/// A camera height: finite, from 0 to 1000 m.
fn eye_height(s: &str) -> Result<f64, String> {
    let v = crate::value::finite(s, "metres")?;
    if (0.0..=1000.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "expected a height from 0 to 1000 metres, got `{s}`"
        ))
    }
}

/// Serves `args.file` until Ctrl-C.
pub fn run(args: &ServeArgs) -> Result<()> {
    let started = Instant::now();
    let info = crate::io::read_info(&args.file)?;
    let scale = LengthScale::for_info(&info, args.units, args.up);
    let height = EyeHeight::new(args.height.map(|h| scale.height(h)), scale.height(1.0));
    let options = PrepareOptions {
        // The page starts where `render`'s automatic camera stands.
        camera: crate::prepare::CameraChoice::Auto,
        height,
        up: args.up,
        radius: args.radius.map(|r| r.scaled(scale.length(1.0))),
        ..PrepareOptions::default()
    };
    let pb = progress::bar(args.quiet, 0, "loading");
    let surveyed = survey(args, &info, &options, PLAN_SURVEY_POINTS, &pb)?;
    let (prepared, spacing, points_total) = match surveyed {
        Some(s) => (s.prepared, s.detail_spacing, Some(s.points_total)),
        None => {
            let prepared = prepare(&args.file, &options, &pb)?;
            let spacing = crate::prepare::radius::median_spacing(&prepared.scene);
            (prepared, spacing, None)
        }
    };
    pb.finish_and_clear();
    let say = |m: String| eprintln!("{m}");
    super::notes::say_load_notes(&args.file, &prepared.report, &say);
    if let Some(total) = points_total {
        say(format!(
            "{}: the map, the ground and the bounds come from its coarse levels ({} of {total} \
             points); every view is drawn through the level of detail",
            args.file.display(),
            prepared.scene.len()
        ));
    }
    let mut given = vec![("IPD", Stereo::DEFAULT_IPD)];
    if let Some(h) = args.height {
        given.push(("--height", h));
    }
    super::notes::say_units(&prepared.report.info, &scale, &given, &say);
    let unit = prepared.report.info.length_symbol();
    let radius = prepared.radii.describe(&unit);
    let live = LiveOptions {
        width: args.width,
        height: height.over(spacing),
        per_metre: scale.length(1.0),
        metres_per_unit: scale.metres_per_unit,
        color: args.color,
        shading: args.shading,
        map_size: args.map_size,
    };
    let lod = served_lod(args, &prepared, options.radius, &say);
    let mut scan = LiveScan::new(&args.file, prepared.scene, live)?;
    if let Some(total) = points_total {
        scan = scan.surveyed_from(total);
    }
    if let Some(lod) = lod {
        say(format!(
            "{}: level of detail ({} px, floor {} points): each render reads the octree nodes \
             it needs into a cache of {} on the GPU",
            args.file.display(),
            lod.pixels,
            lod.floor,
            crate::memory::format_size(lod.budget)
        ));
        scan = scan.with_lod(lod);
    }
    let server = LiveServer::bind(&args.host, args.port, scan)?.with_stream(StreamOptions {
        scale: args.live_scale,
        ..StreamOptions::default()
    });
    let max = server.renderer().max_width();
    if args.width > max {
        bail!(
            "--width {} is wider than the GPU adapter allows ({max}); choose a smaller --width",
            args.width
        );
    }
    let scan = server.scan();
    println!(
        "omnicloud serve: {} ({} points, radius {radius}, map {}x{}, ODS {}x{} on {}; ready in {:.1?})",
        args.file.display(),
        scan.info.points,
        scan.grid.width,
        scan.grid.height,
        args.width,
        args.width,
        server.renderer().adapter(),
        started.elapsed()
    );
    let addr = server.addr();
    let url = view::local_url(addr);
    println!("open {url}   (Ctrl-C stops the server)");
    if !addr.ip().is_loopback() {
        view::warn_exposed(addr);
    }
    let stopper = server.stopper();
    ctrlc::set_handler(move || stopper.stop()).context("installing the Ctrl-C handler")?;
    if args.open {
        view::open_browser(&url);
    }
    server.serve();
    println!("omnicloud serve: stopped");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        serve: ServeArgs,
    }

    fn info() -> crate::io::FileInfo {
        crate::io::read_info(&args(&[]).file).unwrap()
    }

    fn args(extra: &[&str]) -> ServeArgs {
        let file = concat!(env!("CARGO_MANIFEST_DIR"), "/data/courtyard.copc.laz");
        let mut argv = vec!["serve", file];
        argv.extend_from_slice(extra);
        Cli::try_parse_from(argv).unwrap().serve
    }

    fn options(radius: Option<RadiusChoice>) -> PrepareOptions {
        PrepareOptions {
            camera: crate::prepare::CameraChoice::Auto,
            radius,
            ..PrepareOptions::default()
        }
    }

    #[test]
    fn a_copc_file_over_the_budget_is_served_from_its_coarse_levels() {
        let pb = indicatif::ProgressBar::hidden();
        let budget = 100_000;
        let auto = Some(RadiusChoice::Auto);
        let s = survey(&args(&[]), &info(), &options(auto), budget, &pb)
            .unwrap()
            .expect("431,121 points are over the budget");
        assert_eq!(s.points_total, 431_121);
        let held = s.prepared.scene.len() as u64;
        assert!(held <= budget && held > budget / 8, "{held} points held");
        // Within the budget, with `--lod off`, or with radii measured on every point: whole.
        assert!(
            survey(&args(&[]), &info(), &options(auto), 431_121, &pb)
                .unwrap()
                .is_none()
        );
        assert!(
            survey(
                &args(&["--lod", "off"]),
                &info(),
                &options(auto),
                budget,
                &pb
            )
            .unwrap()
            .is_none()
        );
        assert!(
            survey(&args(&[]), &info(), &options(None), budget, &pb)
                .unwrap()
                .is_none()
        );
    }
}
