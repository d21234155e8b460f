//! The command line, as clap parses it.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use glam::DVec3;

use crate::bench::BenchMode;
use crate::io::Up;
use crate::prepare::filter::{ClassSet, Crop, ReturnFilter};
use crate::prepare::{
    CameraChoice, LodChoice, PointFilter, PrepareOptions, RadiusChoice, Subsample,
};
use crate::projection::depth_map::DepthMap;
use crate::projection::{OdsOffset, PoleMerge, PoleMerging, Projection, Stereo, StereoKind};
use crate::render::{Background, ColorMode, Edl, Imposter, Look, Proxy, RendererKind, Shading};

use super::parse;

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
    /// Print a point cloud's header: format, point count, bounds, scale and offset,
    /// coordinate system, attributes (--stats: a pass over the points for histograms).
    Info(super::info::InfoArgs),
    /// Render a point cloud to an equirectangular panorama or ODS pair.
    Render(RenderArgs),
    /// Compare a test render against a reference render (EXR files with a Z channel).
    Compare(CompareArgs),
    /// Time every rasterizer mode against the ray-traced reference: tables and charts.
    Bench(BenchArgs),
    /// Look around a panorama or a tour folder in the browser (and in VR, through WebXR).
    View(super::view::ViewerArgs),
    /// Render a camera path through a scan, one frame per pose (resumable, shardable).
    Tour(super::tour::TourArgs),
    /// Render a scan live in the browser: pick camera positions on its map, tune IPD and
    /// pole merging, look around (and in VR, through WebXR).
    Serve(super::serve::ServeArgs),
    /// Encode a folder of panorama frames (a tour) into an H.264 MP4 that 360 players show
    /// as a sphere, in stereo for ODS frames.
    Video(super::video::VideoArgs),
}

/// Scene, camera and stereo options shared by `render` and `bench`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Camera: auto (open space near the scan's centre, no point within 0.6 × the eye height
    /// of the eye, ground below), center (the XY centre of the bounds, above the ground
    /// there) or X,Y,Z in file coordinates [default: auto].
    #[arg(long, value_name = "auto|center|X,Y,Z", allow_hyphen_values = true)]
    pub camera: Option<CameraChoice>,
    /// Heading in degrees: 0 looks along +Y, 90 along +X.
    #[arg(long, default_value = "0", value_parser = parse::degrees, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Camera pitch in degrees: positive looks up (the whole rig turns, viewing circle
    /// included).
    #[arg(long, default_value = "0", value_parser = parse::degrees, allow_hyphen_values = true)]
    pub pitch: f64,
    /// Camera roll in degrees: positive turns the rig clockwise as seen from behind it.
    #[arg(long, default_value = "0", value_parser = parse::degrees, allow_hyphen_values = true)]
    pub roll: f64,
    /// Projection: equirect[:HFOV,VFOV], hammer, cylindrical[:VFOV], fisheye[:FOV], cubemap or
    /// map (top-down over the scan, mono). --width is the image width; the height follows.
    #[arg(long, default_value = "equirect", value_name = "PROJECTION")]
    pub projection: Projection,
    /// Mono or stereo: none, ods (omnidirectional stereo), parallel (two parallel cameras) or
    /// cubemap[:N] (two cube maps of N x N faces from the parallel cameras, resampled)
    /// [default: none; bench --suite: each manifest entry's].
    #[arg(long, value_name = "none|ods|parallel|cubemap[:N]")]
    pub stereo: Option<StereoKind>,
    /// Interocular distance in metres (with --stereo ods).
    #[arg(long, default_value_t = Stereo::DEFAULT_IPD, value_parser = parse::ipd)]
    pub ipd: f64,
    /// Pole merging at both poles (with --stereo ods): off, comfortable (marrinan:45,0,3),
    /// cycles (cycles:60,75), marrinan:START,END,EXP or cycles:FROM,TO.
    #[arg(long, default_value = "comfortable")]
    pub pole_merge: PoleMerge,
    /// Pole merging at the north pole only (overrides --pole-merge there).
    #[arg(long)]
    pub pole_merge_north: Option<PoleMerge>,
    /// Pole merging at the south pole only (overrides --pole-merge there).
    #[arg(long)]
    pub pole_merge_south: Option<PoleMerge>,
    /// Rasterizer ODS inverse (with --stereo ods).
    #[arg(long, value_enum, ignore_case = true, default_value = "exact")]
    pub ods_offset: OdsOffset,
    /// Depth budget (with --stereo ods): B0=D0,...,Bn=Dn in metres, both increasing. A
    /// sphere whose centre lies Bi away horizontally is shown with the disparity of a point
    /// Di away (interpolated in 1/distance between pairs, scaled down beyond Bn); e.g. 0.5=1.5
    /// shows nothing nearer than 1.5 m. Identity pairs (B=D) are plain ODS.
    #[arg(long, value_name = "B0=D0,...")]
    pub depth_map: Option<DepthMap>,
    /// Sphere radius in metres, `auto` (half the median point spacing) or `adaptive[:K]`
    /// (per point, from K nearest neighbours, default K 8). Default: the file's per-point
    /// `radius` when it has one, else adaptive:8.
    #[arg(long)]
    pub radius: Option<RadiusChoice>,
    /// Up axis of the file.
    #[arg(long, value_enum, ignore_case = true, default_value = "z")]
    pub up: Up,
    /// Keep only these classification codes, e.g. 2,6 (ground, buildings).
    #[arg(long, value_name = "CODES")]
    pub classes: Option<ClassSet>,
    /// Drop these classification codes, e.g. 7,18 (low and high noise).
    #[arg(long, value_name = "CODES")]
    pub drop_classes: Option<ClassSet>,
    /// Keep the first or last return of each pulse only.
    #[arg(long, value_enum, ignore_case = true, default_value = "all")]
    pub returns: ReturnFilter,
    /// Keep the points inside this rectangle, in file coordinates (X and Y; X and Z with
    /// --up y).
    #[arg(long, value_name = "X0,Y0,X1,Y1", allow_hyphen_values = true)]
    pub crop: Option<Crop>,
    /// Keep the points within M metres of the camera, measured horizontally.
    #[arg(long, value_name = "M", value_parser = parse::distance)]
    pub max_distance: Option<f64>,
}

impl ViewArgs {
    /// The stereo mode `--stereo` asks for, per-pole merging and the ODS offset applied;
    /// `None` when it is not given.
    pub fn stereo_mode(&self) -> Option<Stereo> {
        self.stereo.map(|kind| match kind {
            StereoKind::Mono => Stereo::Mono,
            StereoKind::Parallel => Stereo::Parallel { ipd: self.ipd },
            StereoKind::Cubemap(face) => Stereo::Cubemap {
                ipd: self.ipd,
                face,
            },
            StereoKind::Ods => Stereo::Ods {
                ipd: self.ipd,
                merging: self.merging(),
                offset: self.ods_offset,
            },
        })
    }

    /// `--depth-map`, checked against `--stereo`.
    ///
    /// # Errors
    /// A depth map without `--stereo ods`.
    pub fn depth_map(&self) -> anyhow::Result<Option<DepthMap>> {
        match (self.depth_map, self.stereo) {
            (Some(map), kind) if kind != Some(StereoKind::Ods) => anyhow::bail!(
                "--depth-map {map} sets per-sphere ODS radii: it needs --stereo ods, not {}",
                kind.unwrap_or_default()
            ),
            (map, _) => Ok(map),
        }
    }

    /// Pole merging per pole: `--pole-merge`, overridden by `--pole-merge-north/-south`.
    pub fn merging(&self) -> PoleMerging {
        PoleMerging {
            north: self.pole_merge_north.unwrap_or(self.pole_merge),
            south: self.pole_merge_south.unwrap_or(self.pole_merge),
        }
    }

    /// The camera at `center` (local frame) with `--yaw`, `--pitch` and `--roll`.
    pub fn camera_at(&self, center: glam::DVec3) -> crate::projection::Camera {
        crate::projection::Camera::new(center, self.yaw).with_orientation(self.pitch, self.roll)
    }

    /// Images per frame: 2 with `--stereo ods`, else 1.
    pub fn eyes(&self) -> u32 {
        self.stereo.unwrap_or_default().eyes()
    }

    /// Where the scene's camera goes and how its file is read.
    pub fn prepare_options(&self) -> PrepareOptions {
        PrepareOptions {
            camera: self.camera.unwrap_or_default(),
            height: None,
            up: self.up,
            radius: self.radius,
            filter: PointFilter {
                classes: self.classes,
                drop_classes: self.drop_classes,
                returns: self.returns,
                crop: self.crop,
                max_distance: self.max_distance,
            },
            origin: None,
            lod: crate::prepare::Lod::Off,
        }
    }
}

/// Options of `omnicloud render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A LAS, LAZ or PLY file.
    pub file: PathBuf,
    /// More files rendered with the first as one scene (tiles of one survey, same
    /// coordinate system).
    #[arg(value_name = "MORE")]
    pub more_files: Vec<PathBuf>,
    /// Output image: .png (8-bit sRGB), .jpg, .vr.jpg (VR photo, needs --stereo ods) or
    /// .exr (linear RGB + coverage + Z).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "OUT.png|OUT.jpg|OUT.vr.jpg|OUT.exr"
    )]
    pub output: PathBuf,
    /// JPEG quality (for .jpg and .vr.jpg outputs).
    #[arg(long, default_value = "90", value_parser = clap::value_parser!(u8).range(1..=100))]
    pub quality: u8,
    /// Image width, colour, shading, renderer and rasterizer modes.
    #[command(flatten)]
    pub draw: DrawArgs,
    /// Scene, camera and stereo.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Also write the distance along each ray to this EXR file (Z channel, +inf background).
    #[arg(long, value_name = "OUT.exr")]
    pub depth: Option<PathBuf>,
    /// Also write a red/cyan anaglyph preview (needs --stereo ods).
    #[arg(long, value_name = "OUT.png")]
    pub anaglyph: Option<PathBuf>,
    /// Also write the left eye's angular disparity (arcminutes; channels disparity.h and
    /// disparity.v, NaN where none) and print the comfort summary (needs a stereo mode).
    #[arg(long, value_name = "OUT.exr")]
    pub disparity: Option<PathBuf>,
    /// Print the comfort summary: share of pixels perceived nearer than --comfort-near, the
    /// largest disparity, and neighbours whose disparity gradient exceeds 1 (needs a stereo
    /// mode).
    #[arg(long)]
    pub comfort: bool,
    /// Perceived distance, metres, the comfort summary counts pixels nearer than.
    #[arg(long, default_value = "0.5", value_name = "M", value_parser = parse::distance)]
    pub comfort_near: f64,
    /// Write one file per eye (NAME_left.EXT, NAME_right.EXT) instead of top-bottom.
    #[arg(long)]
    pub separate_eyes: bool,
    /// No progress bars or summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Zero of the local frame the renderers work in (file coordinates; default: the camera).
    /// With it the scan is loaded whole and the camera moves within that frame, as in a tour:
    /// a tour's frame and `render --origin` at its pose give the same file.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse::vec3, allow_hyphen_values = true)]
    pub origin: Option<DVec3>,
    /// Memory cap, e.g. 2G or 800M (default: 80% of the available memory). The ray tracer
    /// refuses, before loading, a cloud whose estimated need exceeds it.
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
    /// Thin the cloud: N keeps every N-th point; auto keeps what can matter at this
    /// resolution (sub-pixel spheres behind nearer ones are dropped).
    #[arg(long, value_name = "N|auto")]
    pub subsample: Option<Subsample>,
    /// Eye-dome lighting, supersampling, background.
    #[command(flatten)]
    pub look: LookArgs,
    /// Level of detail for COPC files (.copc.laz): `on` reads only the octree nodes whose
    /// point spacing seen from the camera is a pixel or more, a number of pixels sets that
    /// threshold, `off` reads every point.
    #[arg(long, default_value = "on", value_name = "on|off|PIXELS")]
    pub lod: LodChoice,
    /// Eye height above the local ground with --camera auto or center, metres [default: 1.7,
    /// or 20 median point spacings when higher (sparse aerial data)].
    #[arg(long, value_name = "H", value_parser = parse::distance)]
    pub height: Option<f64>,
}

impl RenderArgs {
    /// The passes on the rendered frames: eye-dome lighting, supersampling, background.
    pub fn look(&self) -> Look {
        self.look.look()
    }

    /// [`ViewArgs::prepare_options`] with the eye height and the level of detail for the
    /// width drawn (the supersampled one: its pixels are the ones the spacing is compared
    /// with).
    pub fn prepare_options(&self) -> PrepareOptions {
        PrepareOptions {
            lod: self.lod.at_width(self.render_width()),
            height: self.height,
            ..self.view.prepare_options()
        }
    }

    /// Width the renderer draws per eye: `--width` times `--supersample`.
    pub fn render_width(&self) -> u32 {
        self.draw.render_width(&self.look)
    }

    /// Every input file, the first first.
    pub fn inputs(&self) -> Vec<PathBuf> {
        std::iter::once(self.file.clone())
            .chain(self.more_files.iter().cloned())
            .collect()
    }

    /// How the summary names the inputs: the file, or the first and how many more.
    pub fn inputs_name(&self) -> String {
        match self.more_files.len() {
            0 => self.file.display().to_string(),
            n => format!(
                "{} (+{n} more file{})",
                self.file.display(),
                if n == 1 { "" } else { "s" }
            ),
        }
    }
}

/// The image and how it is drawn, shared by `render` and `tour`: width, colour, shading,
/// renderer and the rasterizer's modes.
#[derive(Debug, Args)]
pub struct DrawArgs {
    /// Image width per eye; the height is half of it.
    #[arg(long, default_value = "3840", value_parser = parse::width)]
    pub width: u32,
    /// Point colour (auto: rgb when present, else elevation).
    #[arg(long, value_enum, ignore_case = true, default_value = "auto")]
    pub color: ColorMode,
    /// Shading.
    #[arg(long, value_enum, ignore_case = true, default_value = "unlit")]
    pub shading: Shading,
    /// Renderer.
    #[arg(long, value_enum, ignore_case = true, default_value = "raster")]
    pub renderer: RendererKind,
    /// Rasterizer proxy geometry: quad, static:N, dynamic, bounds.
    #[arg(long, default_value = "bounds")]
    pub proxy: Proxy,
    /// Rasterizer fragments.
    #[arg(long, value_enum, ignore_case = true, default_value = "raycast")]
    pub imposter: Imposter,
}

impl DrawArgs {
    /// Width the renderer draws per eye under `look`: `--width` times `--supersample`.
    pub fn render_width(&self, look: &LookArgs) -> u32 {
        self.width.saturating_mul(look.supersample.max(1))
    }

    /// The render settings of `image` seen by `camera` under `view`'s stereo and depth map.
    pub fn settings(
        &self,
        view: &ViewArgs,
        image: crate::projection::Image,
        camera: crate::projection::Camera,
    ) -> anyhow::Result<crate::render::RenderSettings> {
        Ok(crate::render::RenderSettings {
            image,
            camera,
            stereo: view.stereo_mode().unwrap_or(Stereo::Mono),
            color: self.color,
            shading: self.shading,
            proxy: self.proxy,
            imposter: self.imposter,
            depth_map: view.depth_map()?,
        })
    }
}

/// The passes on rendered frames, shared by `render` and `tour`.
#[derive(Debug, Args)]
pub struct LookArgs {
    /// Eye-dome lighting: darkens the far side of depth edges so that shapes read without
    /// colour or lights (Potree's formula, neighbours in angle); STRENGTH defaults to 1.
    #[arg(
        long,
        value_name = "STRENGTH",
        num_args = 0..=1,
        default_missing_value = "1",
        value_parser = crate::render::edl::parse_strength
    )]
    pub edl: Option<f32>,
    /// Eye-dome lighting's neighbour distance, in output pixels.
    #[arg(long, value_name = "PIXELS", default_value = "1.4", value_parser = crate::render::edl::parse_radius)]
    pub edl_radius: f32,
    /// Render N x N samples per pixel and average them in linear light (smooth edges; alpha
    /// becomes the covered fraction, depth the nearest sample).
    #[arg(long, value_name = "N", default_value = "1", value_parser = clap::value_parser!(u32).range(1..=8))]
    pub supersample: u32,
    /// Background: #rrggbb, r,g,b (0-255), black, white, grey, or transparent [default:
    /// transparent in PNG and EXR, black in JPEG].
    #[arg(long, value_name = "COLOR|transparent")]
    pub background: Option<Background>,
}

impl LookArgs {
    /// The passes on the rendered frames: eye-dome lighting, supersampling, background.
    pub fn look(&self) -> Look {
        Look {
            edl: self.edl.map(|strength| Edl {
                strength,
                radius: self.edl_radius,
            }),
            supersample: self.supersample,
            background: self.background,
        }
    }

    /// The options as `omnicloud render` reads them back; none when they are the defaults.
    pub fn render_options(&self) -> Vec<String> {
        let mut a = Vec::new();
        if let Some(s) = self.edl {
            a.push(format!("--edl={s}"));
            a.push(format!("--edl-radius={}", self.edl_radius));
        }
        if self.supersample > 1 {
            a.push(format!("--supersample={}", self.supersample));
        }
        match self.background {
            Some(Background::Color([r, g, b])) => a.push(format!("--background={r},{g},{b}")),
            Some(Background::Transparent) => a.push("--background=transparent".into()),
            None => {}
        }
        a
    }

    /// True when a JPEG cannot hold the result (a transparent background was asked for).
    pub fn wants_alpha(&self) -> bool {
        self.background == Some(Background::Transparent)
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
            "--quality",
            "75",
            "--quiet",
        ])
        .unwrap();
        let Command::Render(r) = cli.command else {
            panic!("not render")
        };
        assert_eq!(
            r.view.camera,
            Some(CameraChoice::At(DVec3::new(-637000.5, 851000.0, 12.0)))
        );
        assert_eq!(r.view.yaw, -30.0);
        assert_eq!(r.draw.proxy, Proxy::Static(16));
        assert_eq!(r.view.pole_merge_south, Some(PoleMerge::Off));
        assert_eq!(r.view.radius, Some(RadiusChoice::Auto));
        assert_eq!(
            r.view.stereo_mode(),
            Some(Stereo::Ods {
                ipd: 0.065,
                merging: PoleMerging {
                    north: PoleMerge::CYCLES_DEFAULT,
                    south: PoleMerge::Off
                },
                offset: OdsOffset::Paper
            })
        );
        assert_eq!(r.draw.renderer, RendererKind::Raytrace);
        assert_eq!(
            (r.draw.color, r.draw.shading),
            (ColorMode::Elevation, Shading::Phong)
        );
        assert_eq!(r.quality, 75);
        assert!(r.quiet);
        for bad in ["0", "101"] {
            let argv = [
                "omnicloud",
                "render",
                "a.laz",
                "-o",
                "a.jpg",
                "--quality",
                bad,
            ];
            assert!(Cli::try_parse_from(argv).is_err(), "--quality {bad}");
        }
    }

    #[test]
    fn bench_takes_the_shared_view_options() {
        let bench = |extra: &[&str]| {
            let argv = ["omnicloud", "bench"].iter().chain(extra);
            let Command::Bench(b) = Cli::try_parse_from(argv).unwrap().command else {
                panic!("not bench")
            };
            b
        };
        let b = bench(&[
            "s.laz",
            "--stereo",
            "ods",
            "--pole-merge-north",
            "off",
            "--ods-offset",
            "paper",
        ]);
        assert_eq!(
            b.view.stereo_mode(),
            Some(Stereo::Ods {
                ipd: 0.064,
                merging: PoleMerging {
                    north: PoleMerge::Off,
                    south: PoleMerge::COMFORTABLE
                },
                offset: OdsOffset::Paper
            })
        );
        assert_eq!(b.width, None);
        // Without --stereo the manifest (or, for a scan, mono) decides.
        assert_eq!(bench(&["--suite", "dir"]).view.stereo_mode(), None);
    }

    #[test]
    fn the_depth_map_needs_ods_stereo() {
        let view = |extra: &[&str]| {
            let argv = ["omnicloud", "render", "s.laz", "-o", "x.png"]
                .iter()
                .chain(extra);
            let Command::Render(r) = Cli::try_parse_from(argv).unwrap().command else {
                panic!("not render")
            };
            r.view
        };
        let map = view(&["--stereo", "ods", "--depth-map", "0.5=1.5,2=3"])
            .depth_map()
            .unwrap()
            .unwrap();
        assert_eq!(map.to_string(), "0.5=1.5,2=3");
        assert_eq!(view(&["--stereo", "ods"]).depth_map().unwrap(), None);
        for (extra, named) in [
            (&["--depth-map", "0.5=1.5"][..], "not none"),
            (
                &["--stereo", "parallel", "--depth-map", "0.5=1.5"],
                "not parallel",
            ),
        ] {
            let e = view(extra).depth_map().unwrap_err().to_string();
            assert!(e.contains("needs --stereo ods") && e.contains(named), "{e}");
        }
        let argv = [
            "omnicloud",
            "render",
            "s.laz",
            "-o",
            "x.png",
            "--depth-map",
            "2=1,1=3",
        ];
        let e = Cli::try_parse_from(argv).unwrap_err().to_string();
        assert!(e.contains("pair 2 `1=3`: B must be greater"), "{e}");
    }

    #[test]
    fn plain_values_are_listed_and_read_in_any_case() {
        let Command::Render(r) = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--renderer",
            "RAYTRACE",
            "--up",
            "Y",
        ])
        .unwrap()
        .command
        else {
            panic!("not render")
        };
        assert_eq!(
            (r.draw.renderer, r.view.up),
            (RendererKind::Raytrace, Up::Y)
        );
        assert_eq!(r.view.stereo_mode(), None);
        let e = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--shading",
            "toon",
        ])
        .unwrap_err()
        .to_string();
        assert!(e.contains("unlit, phong, normal"), "{e}");
    }

    #[test]
    fn render_takes_several_files_and_the_point_filters() {
        let Command::Render(r) = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.laz",
            "b.laz",
            "c.las",
            "-o",
            "x.png",
            "--classes",
            "2,6",
            "--drop-classes",
            "7,18",
            "--returns",
            "LAST",
            "--crop",
            "-10,5,20,-5",
            "--max-distance",
            "150",
        ])
        .unwrap()
        .command
        else {
            panic!("not render")
        };
        assert_eq!(
            r.inputs(),
            ["a.laz", "b.laz", "c.las"].map(PathBuf::from).to_vec()
        );
        assert_eq!(r.inputs_name(), "a.laz (+2 more files)");
        let f = r.view.prepare_options().filter;
        assert_eq!(f.classes.map(|c| c.codes()), Some(vec![2, 6]));
        assert_eq!(f.drop_classes.map(|c| c.codes()), Some(vec![7, 18]));
        assert_eq!(f.returns, ReturnFilter::Last);
        let crop = f.crop.unwrap();
        assert_eq!(
            (crop.min.x, crop.min.y, crop.max.x, crop.max.y),
            (-10.0, -5.0, 20.0, 5.0)
        );
        assert_eq!(f.max_distance, Some(150.0));
        for (option, bad, why) in [
            (
                "--classes",
                "2,ground",
                "'ground' is not a classification code",
            ),
            ("--crop", "1,2,3", "four numbers"),
            ("--max-distance", "0", "above 0 m"),
        ] {
            let e =
                Cli::try_parse_from(["omnicloud", "render", "a.las", "-o", "x.png", option, bad])
                    .unwrap_err()
                    .to_string();
            assert!(e.contains(why), "{option} {bad}: {e}");
        }
        let Command::Info(i) =
            Cli::try_parse_from(["omnicloud", "info", "--stats", "--json", "a.laz", "b.ply"])
                .unwrap()
                .command
        else {
            panic!("not info")
        };
        assert!(i.stats && i.json && i.files.len() == 2);
    }

    #[test]
    fn picture_options_parse_with_their_defaults() {
        let parse = |extra: &[&str]| {
            let argv = ["omnicloud", "render", "a.las", "-o", "x.png"]
                .iter()
                .chain(extra);
            match Cli::try_parse_from(argv).map(|c| c.command) {
                Ok(Command::Render(r)) => Ok(r.look()),
                Ok(_) => panic!("not render"),
                Err(e) => Err(e.to_string()),
            }
        };
        assert_eq!(
            parse(&[]).unwrap(),
            Look {
                supersample: 1,
                ..Look::default()
            }
        );
        let edl = |l: Look| l.edl.map(|e| (e.strength, e.radius));
        assert_eq!(edl(parse(&["--edl"]).unwrap()), Some((1.0, 1.4)));
        assert_eq!(
            edl(parse(&["--edl", "0.5", "--edl-radius", "2"]).unwrap()),
            Some((0.5, 2.0))
        );
        let l = parse(&["--supersample", "3", "--background", "#000000"]).unwrap();
        assert_eq!(l.supersample, 3);
        assert_eq!(l.background, Some(Background::Color([0, 0, 0])));
        for (bad, why) in [
            (&["--supersample", "9"][..], "1..=8"),
            (&["--edl=-1"], ">= 0"),
            (&["--edl-radius", "0"], "above 0"),
        ] {
            let e = parse(bad).unwrap_err();
            assert!(e.contains(why), "{bad:?}: {e}");
        }
        let e = Cli::try_parse_from(["omnicloud", "render", "--edl", "a.las", "-o", "x.png"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--edl=1"), "{e}");
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
