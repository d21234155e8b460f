//! The command line, as clap parses it.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use glam::DVec3;

use crate::bench::BenchMode;
use crate::projection::{OdsOffset, PoleMerge};
use crate::render::{ColorMode, Imposter, Proxy, RendererKind, Shading};

use super::parse::{self, RadiusChoice};

/// Render LiDAR scans (LAS, LAZ, PLY) to 360° panoramas and omnidirectional-stereo pairs.
#[derive(Debug, Parser)]
#[command(name = "omnicloud", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
// Parsed once per run: the size of the render variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Command {
    /// Print a point cloud's format, point count, bounds, attributes and point spacing.
    Info {
        /// A LAS, LAZ or PLY file.
        file: PathBuf,
    },
    /// Render a point cloud to an equirectangular panorama or ODS pair.
    Render(RenderArgs),
    /// Compare a test render against a reference render (EXR files with a Z channel).
    Compare(CompareArgs),
    /// Time every rasterizer mode against the ray-traced reference: tables and charts.
    Bench(BenchArgs),
}

/// Mono panorama or omnidirectional stereo.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StereoArg {
    /// One panorama.
    None,
    /// Left and right eye, top-bottom (left on top).
    Ods,
}

/// Exact ODS inverse or the paper's approximation (rasterizer only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OdsOffsetArg {
    /// The exact inverse of the ODS ray.
    Exact,
    /// Marrinan & Papka's per-vertex offset (atan instead of asin).
    Paper,
}

impl From<OdsOffsetArg> for OdsOffset {
    fn from(a: OdsOffsetArg) -> Self {
        match a {
            OdsOffsetArg::Exact => OdsOffset::Exact,
            OdsOffsetArg::Paper => OdsOffset::Paper,
        }
    }
}

/// Which axis is up in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum UpArg {
    /// Z up (LAS convention).
    Z,
    /// Y up (common in PLY from photogrammetry); swapped to Z up on load.
    Y,
}

/// Options of `omnicloud render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A LAS, LAZ or PLY file.
    pub file: PathBuf,
    /// Output image: .png (8-bit sRGB) or .exr (linear RGB + coverage + Z).
    #[arg(short = 'o', long = "output", value_name = "OUT.png|OUT.exr")]
    pub output: PathBuf,
    /// Image width per eye; the height is half of it.
    #[arg(long, default_value = "3840", value_parser = parse::width)]
    pub width: u32,
    /// Camera centre in file coordinates (default: XY centre of the bounds, 1.7 m above the
    /// ground near it).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse::vec3, allow_hyphen_values = true)]
    pub camera: Option<DVec3>,
    /// Heading in degrees: 0 looks along +Y, 90 along +X.
    #[arg(long, default_value = "0", value_parser = parse::degrees, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Mono or omnidirectional stereo.
    #[arg(long, value_enum, default_value = "none")]
    pub stereo: StereoArg,
    /// Interocular distance in metres.
    #[arg(long, default_value = "0.064", value_parser = parse::ipd)]
    pub ipd: f64,
    /// Pole merging at both poles: off, comfortable (marrinan:45,0,3), cycles (cycles:60,75),
    /// marrinan:START,END,EXP or cycles:FROM,TO.
    #[arg(long, default_value = "comfortable", value_parser = parse::pole_merge)]
    pub pole_merge: PoleMerge,
    /// Pole merging at the north pole only (overrides --pole-merge there).
    #[arg(long, value_parser = parse::pole_merge)]
    pub pole_merge_north: Option<PoleMerge>,
    /// Pole merging at the south pole only (overrides --pole-merge there).
    #[arg(long, value_parser = parse::pole_merge)]
    pub pole_merge_south: Option<PoleMerge>,
    /// Sphere radius in metres, or `auto` (half the median point spacing). Default: the
    /// file's per-point `radius` when it has one, else auto.
    #[arg(long, value_parser = parse::radius)]
    pub radius: Option<RadiusChoice>,
    /// Point colour: auto (rgb when present, else elevation), rgb, intensity, classification,
    /// elevation, flat.
    #[arg(long, default_value = "auto", value_parser = parse::color)]
    pub color: ColorMode,
    /// Shading: unlit, phong, normal.
    #[arg(long, default_value = "unlit", value_parser = parse::shading)]
    pub shading: Shading,
    /// Also write the distance along each ray to this EXR file (Z channel, +inf background).
    #[arg(long, value_name = "OUT.exr")]
    pub depth: Option<PathBuf>,
    /// Also write a red/cyan anaglyph preview (needs --stereo ods).
    #[arg(long, value_name = "OUT.png")]
    pub anaglyph: Option<PathBuf>,
    /// Write one file per eye (NAME_left.EXT, NAME_right.EXT) instead of top-bottom.
    #[arg(long)]
    pub separate_eyes: bool,
    /// raster (GPU, default) or raytrace (CPU reference).
    #[arg(long, default_value = "raster", value_parser = parse::renderer)]
    pub renderer: RendererKind,
    /// Rasterizer proxy geometry: quad, static:N, dynamic, bounds.
    #[arg(long, default_value = "bounds", value_parser = parse::proxy)]
    pub proxy: Proxy,
    /// Rasterizer fragments: sprite (billboard shading) or raycast (exact).
    #[arg(long, default_value = "raycast", value_parser = parse::imposter)]
    pub imposter: Imposter,
    /// Rasterizer ODS inverse: exact or the paper's approximation.
    #[arg(long, value_enum, default_value = "exact")]
    pub ods_offset: OdsOffsetArg,
    /// Up axis of the file.
    #[arg(long, value_enum, default_value = "z")]
    pub up: UpArg,
    /// No progress bars or summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Memory cap, e.g. 2G or 800M (default: 80% of the available memory). The ray tracer
    /// refuses, before loading, a cloud whose estimated need exceeds it.
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
    /// Thin the cloud: N keeps every N-th point; auto keeps what can matter at this
    /// resolution (sub-pixel spheres behind nearer ones are dropped).
    #[arg(long, value_name = "N|auto", value_parser = crate::subsample::parse)]
    pub subsample: Option<crate::subsample::Subsample>,
}

impl RenderArgs {
    /// The stereo mode these options ask for (per-pole merging overrides applied).
    pub fn stereo_mode(&self) -> crate::projection::Stereo {
        use crate::projection::{PoleMerging, Stereo};
        match self.stereo {
            StereoArg::None => Stereo::Mono,
            StereoArg::Ods => Stereo::Ods {
                ipd: self.ipd,
                merging: PoleMerging {
                    north: self.pole_merge_north.unwrap_or(self.pole_merge),
                    south: self.pole_merge_south.unwrap_or(self.pole_merge),
                },
                offset: self.ods_offset.into(),
            },
        }
    }
}

/// Options of `omnicloud compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Reference render (EXR with Z, e.g. from --renderer raytrace).
    pub reference: PathBuf,
    /// Render under test (EXR with Z).
    pub test: PathBuf,
    /// Write the full report as JSON.
    #[arg(long, value_name = "R.json")]
    pub report: Option<PathBuf>,
    /// Write an error heatmap with a legend.
    #[arg(long, value_name = "H.png")]
    pub heatmap: Option<PathBuf>,
}

/// Options of `omnicloud bench`.
#[derive(Debug, Args)]
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
    /// Mono or ODS [none for a scan; the manifest's for --suite].
    #[arg(long, value_enum)]
    pub stereo: Option<StereoArg>,
    /// Interocular distance in metres (with --stereo ods).
    #[arg(long, default_value = "0.064", value_parser = parse::ipd)]
    pub ipd: f64,
    /// Pole merging at both poles (with --stereo ods).
    #[arg(long, default_value = "comfortable", value_parser = parse::pole_merge)]
    pub pole_merge: PoleMerge,
    /// Camera centre in file coordinates [automatic, as for render].
    #[arg(long, value_name = "X,Y,Z", value_parser = parse::vec3, allow_hyphen_values = true)]
    pub camera: Option<DVec3>,
    /// Heading in degrees.
    #[arg(long, default_value = "0", value_parser = parse::degrees, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Sphere radius in metres or `auto` [per-point radii when present, else auto].
    #[arg(long, value_parser = parse::radius)]
    pub radius: Option<RadiusChoice>,
    /// Up axis of the file.
    #[arg(long, value_enum, default_value = "z")]
    pub up: UpArg,
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
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn render_parses_the_full_option_set() {
        let cli = Cli::try_parse_from([
            "omnicloud",
            "render",
            "in.laz",
            "-o",
            "out.exr",
            "--width",
            "1024",
            "--camera",
            "-637000.5,851000,12",
            "--yaw",
            "-30",
            "--stereo",
            "ods",
            "--ipd",
            "0.065",
            "--pole-merge",
            "cycles:60,75",
            "--pole-merge-south",
            "off",
            "--radius",
            "auto",
            "--color",
            "elevation",
            "--shading",
            "phong",
            "--depth",
            "d.exr",
            "--anaglyph",
            "a.png",
            "--renderer",
            "raytrace",
            "--proxy",
            "static:16",
            "--imposter",
            "sprite",
            "--ods-offset",
            "paper",
            "--quiet",
        ])
        .unwrap();
        let Command::Render(r) = cli.command else {
            panic!("not render")
        };
        assert_eq!(r.camera, Some(DVec3::new(-637000.5, 851000.0, 12.0)));
        assert_eq!(r.yaw, -30.0);
        assert_eq!(r.proxy, Proxy::Static(16));
        assert_eq!(r.pole_merge_south, Some(PoleMerge::Off));
        assert_eq!(r.radius, Some(RadiusChoice::Auto));
        assert!(r.quiet);
    }

    #[test]
    fn bad_values_are_rejected_with_the_reason() {
        let e = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--width",
            "999",
        ])
        .unwrap_err()
        .to_string();
        assert!(e.contains("even"), "{e}");
    }
}
