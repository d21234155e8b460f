//! The options `render` and `tour` share (image, stereo rig, renderer, colour, radii, filters,
//! units, look), parsed by the library's parsers into its settings, and written back as the
//! `omnicloud render` options that draw the same image.

use glam::DVec3;
use omnicloud::io::Up;
use omnicloud::prepare::{LengthScale, PointFilter, RadiusChoice, Units};
use omnicloud::projection::{Camera, Image as ImageSize, OdsOffset, PoleMerge, PoleMerging};
use omnicloud::projection::{Projection, Stereo, StereoKind};
use omnicloud::render::{Background, ColorMode, Edl, Look, RenderSettings, RendererKind, Shading};
use pyo3::prelude::*;

use crate::cloud::PointCloud;
use crate::errors::value_error;
use crate::options::{FilterArgs, as_text, finite, parse, parse_any, value_enum};

// The signatures' `ipd=0.064` is the library's default, written out so `help()` shows it.
const _: () = assert!(Stereo::DEFAULT_IPD == 0.064);

/// The shared options as Python passes them (lengths in `units`).
pub struct ViewArgs<'a, 'py> {
    pub width: u32,
    pub stereo: &'a str,
    pub projection: &'a str,
    pub ipd: f64,
    pub pole_merge: &'a str,
    pub pole_merge_north: Option<&'a str>,
    pub pole_merge_south: Option<&'a str>,
    pub ods_offset: &'a str,
    pub renderer: &'a str,
    pub color: &'a str,
    pub shading: &'a str,
    pub radius: Option<&'a Bound<'py, PyAny>>,
    pub classes: Option<&'a Bound<'py, PyAny>>,
    pub drop_classes: Option<&'a Bound<'py, PyAny>>,
    pub returns: &'a str,
    pub crop: Option<&'a Bound<'py, PyAny>>,
    pub max_distance: Option<f64>,
    pub units: &'a str,
    pub edl: Option<f32>,
    pub edl_radius: f32,
    pub supersample: u32,
    pub background: Option<&'a Bound<'py, PyAny>>,
}

/// The shared options parsed, lengths in the cloud's unit.
pub struct View {
    /// From the lengths given to the cloud's unit.
    pub scale: LengthScale,
    /// The output projection.
    pub projection: Projection,
    /// Which renderer draws.
    pub renderer: RendererKind,
    /// Passes on each render (eye-dome lighting, supersampling, background).
    pub look: Look,
    /// Sphere radius rule, in the cloud's unit; `None`: the cloud's radii, else adaptive.
    pub radius: Option<RadiusChoice>,
    /// Which points are kept.
    pub filter: PointFilter,
    /// The output image (`None` for the top-down map, sized by the points).
    pub image: Option<ImageSize>,
    /// Settings of a render at the output size (for the map: a `width` wide panorama,
    /// replaced once the points size it), the camera level at the local zero.
    pub settings: RenderSettings,
}

impl ViewArgs<'_, '_> {
    /// The options parsed for `cloud`, each error a ValueError naming its argument.
    pub fn parse(&self, cloud: &PointCloud) -> PyResult<View> {
        // Lengths given in metres become lengths in the cloud's unit, as the command line
        // converts them (`--units`).
        let units: Units = value_enum("units", self.units)?;
        let scale = LengthScale::for_file(&cloud.units, units, cloud.up);
        let stereo: StereoKind = parse("stereo", self.stereo)?;
        let projection: Projection = parse("projection", self.projection)?;
        let ipd = Stereo::check_ipd(finite("ipd", self.ipd)?)
            .map_err(|e| value_error(format!("ipd: {e}")))?;
        let pole: PoleMerge = parse("pole_merge", self.pole_merge)?;
        let merging = PoleMerging {
            north: self
                .pole_merge_north
                .map_or(Ok(pole), |p| parse("pole_merge_north", p))?,
            south: self
                .pole_merge_south
                .map_or(Ok(pole), |p| parse("pole_merge_south", p))?,
        };
        let offset: OdsOffset = value_enum("ods_offset", self.ods_offset)?;
        let renderer: RendererKind = parse("renderer", self.renderer)?;
        let color: ColorMode = parse("color", self.color)?;
        let shading: Shading = parse("shading", self.shading)?;
        let radius =
            parse_any::<RadiusChoice>("radius", self.radius)?.map(|r| r.scaled(scale.length(1.0)));
        let filter = FilterArgs {
            classes: self.classes,
            drop_classes: self.drop_classes,
            returns: self.returns,
            crop: self.crop,
            max_distance: self.max_distance,
        }
        .filter(scale.length(1.0))?;
        let edl = self
            .edl
            .map(|strength| -> PyResult<Edl> {
                use omnicloud::render::edl::{parse_radius, parse_strength};
                Ok(Edl {
                    strength: parse_strength(&strength.to_string())
                        .map_err(|e| value_error(format!("edl: {e}")))?,
                    radius: parse_radius(&self.edl_radius.to_string())
                        .map_err(|e| value_error(format!("edl_radius: {e}")))?,
                })
            })
            .transpose()?;
        let look = Look {
            edl,
            supersample: self.supersample,
            background: parse_any::<Background>("background", self.background)?,
        };
        let map = projection.is_map();
        if map && stereo.eyes() == 2 {
            return Err(value_error(
                "projection \"map\" is a top-down view: it has one eye (use stereo=\"none\")",
            ));
        }
        let image = if map {
            None
        } else {
            Some(
                ImageSize::new(projection, self.width)
                    .map_err(|e| value_error(format!("width: {e}")))?,
            )
        };
        let settings = RenderSettings {
            image: image.unwrap_or_else(|| ImageSize::equirect(self.width)),
            camera: Camera::new(DVec3::ZERO, 0.0),
            stereo: stereo.rig(scale.length(ipd), merging, offset),
            color,
            shading,
            proxy: Default::default(),
            imposter: Default::default(),
            depth_map: None,
        };
        Ok(View {
            scale,
            projection,
            renderer,
            look,
            radius,
            filter,
            image,
            settings,
        })
    }

    /// `omnicloud render` options that draw what these options draw for `cloud`, lengths in
    /// the units given (with `--units`), every one written out in `render`'s order: what a
    /// tour records per frame.
    pub fn render_options(&self, cloud: &PointCloud) -> PyResult<Vec<String>> {
        let given = |name: &str, value: Option<&Bound<'_, PyAny>>| -> PyResult<Option<String>> {
            value
                .map(|v| as_text(name, v).map(|t| format!("--{}={t}", name.replace('_', "-"))))
                .transpose()
        };
        let up = match cloud.up {
            Up::Z => "z",
            Up::Y => "y",
        };
        let mut argv = vec![
            format!("--width={}", self.width),
            format!("--color={}", self.color),
            format!("--shading={}", self.shading),
            format!("--renderer={}", self.renderer),
            format!("--projection={}", self.projection),
            format!("--stereo={}", self.stereo),
            format!("--ipd={}", self.ipd),
            format!("--pole-merge={}", self.pole_merge),
        ];
        argv.extend(
            self.pole_merge_north
                .map(|p| format!("--pole-merge-north={p}")),
        );
        argv.extend(
            self.pole_merge_south
                .map(|p| format!("--pole-merge-south={p}")),
        );
        argv.push(format!("--ods-offset={}", self.ods_offset));
        argv.push(format!("--up={up}"));
        argv.extend(given("radius", self.radius)?);
        argv.extend(given("classes", self.classes)?);
        argv.extend(given("drop_classes", self.drop_classes)?);
        argv.push(format!("--returns={}", self.returns));
        argv.extend(given("crop", self.crop)?);
        argv.extend(self.max_distance.map(|m| format!("--max-distance={m}")));
        argv.push(format!("--units={}", self.units));
        argv.extend(self.edl.map(|edl| format!("--edl={edl}")));
        argv.push(format!("--edl-radius={}", self.edl_radius));
        argv.push(format!("--supersample={}", self.supersample));
        argv.extend(given("background", self.background)?);
        Ok(argv)
    }
}
