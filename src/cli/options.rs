//! Options shared by several commands, flattened into each: the scene, camera and stereo
//! ([`ViewArgs`]), the image and how it is drawn ([`DrawArgs`]), the passes on rendered
//! frames ([`LookArgs`]).

use clap::Args;

use crate::io::Up;
use crate::io::e57::ScanSelection;
use crate::prepare::filter::{ClassSet, Crop, ReturnFilter};
use crate::prepare::{
    CameraChoice, EyeHeight, LengthScale, PointFilter, PrepareOptions, RadiusChoice, StationPick,
    Units,
};
use crate::projection::depth_map::DepthMap;
use crate::projection::{OdsOffset, PoleMerge, PoleMerging, Projection, Stereo, StereoKind};
use crate::render::{Background, ColorMode, Edl, Imposter, Look, Proxy, RendererKind, Shading};

use super::parse;

/// Scene, camera and stereo options shared by `render`, `tour` and `bench`.
#[derive(Debug, Clone, PartialEq, Args)]
pub struct ViewArgs {
    /// Camera: auto (open space near the scan's centre, no point within 0.6 × the eye height
    /// of the eye, ground below), center (the XY centre of the bounds, above the ground
    /// there), X,Y,Z in file coordinates, or station:N (an E57 scan's scanner position and
    /// heading; render's station:all writes one panorama per station into -o DIR)
    /// [default: auto].
    #[arg(
        long,
        value_name = "auto|center|X,Y,Z|station:N|all",
        allow_hyphen_values = true
    )]
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
    /// E57 scans to read, by index (from 0) or name, e.g. 0,2 or Hall [default: all]. The
    /// same as naming the file FILE#scan:0,2.
    #[arg(long, value_name = "N|NAME[,..]")]
    pub scan: Option<ScanSelection>,
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
    /// What the lengths given (--ipd, --height, --radius, --max-distance, --depth-map, a
    /// tour's --speed) are in: metres, converted to the unit the file's coordinate system
    /// declares (feet, US survey feet), or the file's own unit. Positions (--camera, --crop,
    /// --origin, a tour's path) are always file coordinates.
    #[arg(long, value_enum, ignore_case = true, default_value = "metres")]
    pub units: Units,
    /// The scale the lengths above were converted by ([`ViewArgs::in_file_units`]); `None`
    /// while they are as given.
    #[arg(skip)]
    pub scale: Option<LengthScale>,
}

/// `file` with the scans `scan` picks (`FILE#scan:..`); as it is without a pick.
pub fn scan_path(scan: Option<&ScanSelection>, file: &std::path::Path) -> std::path::PathBuf {
    match scan {
        Some(selection) => crate::io::e57::select::with_scans(file, selection),
        None => file.to_path_buf(),
    }
}

impl ViewArgs {
    /// `--camera station:N` as the station's position, its heading added to `--yaw`; other
    /// choices (and `station:all`, a folder of panoramas) are left as they are.
    ///
    /// # Errors
    /// A station `file` does not have, or a file without stations.
    pub fn resolve_station(
        &mut self,
        file: &std::path::Path,
    ) -> Result<(), crate::tour::stations::StationError> {
        if let Some(CameraChoice::Station(StationPick::Index(n))) = self.camera {
            let station = crate::tour::stations::read_station(file, n)?;
            self.camera = Some(CameraChoice::At(station.position));
            self.yaw = crate::tour::poses::wrap_degrees(self.yaw + station.yaw);
        }
        Ok(())
    }

    /// `file` with the scans `--scan` picks (`FILE#scan:..`); as it is without `--scan`.
    pub fn scan_path(&self, file: &std::path::Path) -> std::path::PathBuf {
        scan_path(self.scan.as_ref(), file)
    }

    /// The scale from `--units` to the coordinates of `info`'s file.
    pub fn length_scale(&self, info: &crate::io::FileInfo) -> LengthScale {
        LengthScale::for_info(info, self.units, self.up)
    }

    /// These options with every length (`--ipd`, `--radius`, `--max-distance`, the depth
    /// map's distances) converted by `scale` into file units. Options converted already are
    /// returned as they are.
    pub fn in_file_units(&self, scale: &LengthScale) -> ViewArgs {
        if self.scale.is_some() {
            return self.clone();
        }
        ViewArgs {
            ipd: scale.length(self.ipd),
            depth_map: self.depth_map.map(|m| m.scaled(scale.length(1.0))),
            radius: self.radius.map(|r| r.scaled(scale.length(1.0))),
            max_distance: self.max_distance.map(|m| scale.length(m)),
            scale: Some(scale.clone()),
            ..self.clone()
        }
    }

    /// The lengths given, as typed, that the units note lists: `--ipd` for stereo, a fixed
    /// `--radius`, `--max-distance`.
    pub fn given_lengths(&self) -> Vec<(&'static str, f64)> {
        let mut given = Vec::new();
        if self.eyes() == 2 || matches!(self.stereo, Some(StereoKind::Cubemap(_))) {
            given.push(("--ipd", self.ipd));
        }
        if let Some(RadiusChoice::Fixed(r)) = self.radius {
            // As typed: the f32's shortest decimal, not its binary expansion.
            given.push(("--radius", r.to_string().parse().unwrap_or(f64::from(r))));
        }
        if let Some(m) = self.max_distance {
            given.push(("--max-distance", m));
        }
        given
    }

    /// The eye height for the automatic camera, in file units: `given` (file units), or the
    /// default rule for a person's eye in the unit of [`ViewArgs::scale`].
    pub fn eye_height(&self, given: Option<f64>) -> EyeHeight {
        let per_metre = self.scale.as_ref().map_or(1.0, |s| s.height(1.0));
        EyeHeight::new(given, per_metre)
    }

    /// The stereo mode `--stereo` asks for, per-pole merging and the ODS offset applied;
    /// `None` when it is not given.
    pub fn stereo_mode(&self) -> Option<Stereo> {
        self.stereo
            .map(|kind| kind.rig(self.ipd, self.merging(), self.ods_offset))
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
            height: self.eye_height(None),
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
            fields: crate::io::PointFields::ALL,
        }
    }
}

/// The image and how it is drawn, shared by `render` and `tour`: width, colour, shading,
/// renderer and the rasterizer's modes.
#[derive(Debug, Clone, PartialEq, Args)]
pub struct DrawArgs {
    /// Image width per eye; the height is half of it.
    #[arg(long, default_value = "3840", value_parser = parse::width)]
    pub width: u32,
    /// Point colour (auto: rgb when present, else elevation; an E57 scan without colour but
    /// with photos takes them; image: from the E57 scanner's photos).
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
    /// `file` read with its points coloured from its images (`FILE#color:image`) under
    /// `--color image`; as it is otherwise.
    pub fn colour_path(&self, file: &std::path::Path) -> std::path::PathBuf {
        match self.color {
            ColorMode::Image => crate::io::e57::select::with_image_colour(file),
            _ => file.to_path_buf(),
        }
    }

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
#[derive(Debug, Clone, PartialEq, Args)]
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
