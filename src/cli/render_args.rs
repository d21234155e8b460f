//! Options of `omnicloud render`, and what they make: the preparation, the inputs, the
//! lengths in file units.

use std::path::PathBuf;

use clap::Args;
use glam::DVec3;

use crate::prepare::{FilterCounts, LengthScale, LodChoice, PrepareOptions, Subsample};
use crate::render::Look;

use super::options::{DrawArgs, LookArgs, ViewArgs};
use super::parse;

/// Options of `omnicloud render`.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    /// A LAS, LAZ, PLY or E57 file.
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
    /// Level of detail: points a view reads at least, where the file holds them; past the
    /// threshold it refines the nodes that look coarsest first (a scan this small is drawn
    /// whole, as with `--lod off`); 0 keeps the threshold alone.
    #[arg(long, default_value_t = crate::prepare::lod::LOD_FLOOR_POINTS, value_name = "POINTS")]
    pub lod_floor: u64,
    /// Eye height above the local ground with --camera auto or center, metres [default: 1.7,
    /// or 20 median point spacings when higher (sparse aerial data)].
    #[arg(long, value_name = "H", value_parser = parse::distance)]
    pub height: Option<f64>,
    /// With --camera station:all: render only shard I of N of the stations, or `auto` (as
    /// `tour --shard`).
    #[arg(long, value_name = "I/N|auto")]
    pub shard: Option<crate::tour::ShardChoice>,
    /// With --camera station:all and --shard auto: the number of shards (as `tour --shards`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub shards: Option<u32>,
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
            lod: self
                .lod
                .at_width(self.render_width())
                .with_floor(self.lod_floor()),
            height: self.view.eye_height(self.height),
            fields: self.draw.color.fields(),
            ..self.view.prepare_options()
        }
    }

    /// Says what each filter removed, when any filter was asked for.
    pub fn say_filtered(&self, filtered: &FilterCounts, kept: u64, say: &impl Fn(String)) {
        if !self.prepare_options().filter.keeps_all() {
            say(format!(
                "filters: {filtered}; {kept} of {} points kept",
                kept + filtered.total()
            ));
        }
    }

    /// [`ViewArgs::given_lengths`] with `--height` and, for the comfort summary,
    /// `--comfort-near`.
    pub fn given_lengths(&self) -> Vec<(&'static str, f64)> {
        let mut given = self.view.given_lengths();
        if let Some(h) = self.height {
            given.push(("--height", h));
        }
        if self.comfort || self.disparity.is_some() {
            given.push(("--comfort-near", self.comfort_near));
        }
        given
    }

    /// These options with every length (`--height`, `--comfort-near` and
    /// [`ViewArgs::in_file_units`]'s) converted by `scale` into file units.
    pub fn in_file_units(&self, scale: &LengthScale) -> RenderArgs {
        if self.view.scale.is_some() {
            return self.clone();
        }
        RenderArgs {
            height: self.height.map(|h| scale.height(h)),
            comfort_near: scale.length(self.comfort_near),
            view: self.view.in_file_units(scale),
            ..self.clone()
        }
    }

    /// The memory cap in force and whether it is the default; `None` where none is given
    /// and the available memory is unknown.
    pub fn memory_cap(&self) -> Option<(u64, bool)> {
        match self.max_memory {
            Some(c) => Some((c, false)),
            None => crate::memory::default_cap().map(|c| (c, true)),
        }
    }

    /// `--lod-floor`, for the ray tracer at most the points its memory cap holds: the floor
    /// adds detail where it is cheap and never makes a render refused.
    fn lod_floor(&self) -> u64 {
        match (self.draw.renderer, self.memory_cap()) {
            (crate::render::RendererKind::Raytrace, Some((cap, _))) => {
                let held = crate::memory::raytrace_points_within(
                    cap,
                    self.render_width(),
                    self.view.eyes(),
                );
                self.lod_floor.min(held)
            }
            _ => self.lod_floor,
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
