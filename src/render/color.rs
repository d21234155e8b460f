//! Per-point base colour (DESIGN §5): the colour a sphere has before shading, as sRGB bytes.

use crate::scene::Scene;

/// How points are coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ColorMode {
    /// RGB from the file when present, else elevation.
    #[default]
    Auto,
    /// The file's RGB colour.
    Rgb,
    /// Intensity as grey, stretched between its 1st and 99th percentiles.
    Intensity,
    /// ASPRS classification palette.
    Classification,
    /// Height as a perceptual (viridis) ramp between the 1st and 99th percentiles.
    Elevation,
    /// One light grey.
    Flat,
    /// E57: each point's colour from the photos its own station took (the file is read as
    /// `FILE#color:image`, whose colour is then the scene's RGB), intensity where none sees it.
    Image,
}

impl ColorMode {
    /// The point attributes the mode colours from (elevation and flat need none).
    pub fn fields(self) -> crate::io::PointFields {
        use crate::io::PointFields;
        match self {
            ColorMode::Auto | ColorMode::Rgb => PointFields {
                rgb: true,
                ..PointFields::POSITIONS
            },
            ColorMode::Image => PointFields {
                rgb: true,
                intensity: true,
                ..PointFields::POSITIONS
            },
            ColorMode::Intensity => PointFields {
                intensity: true,
                ..PointFields::POSITIONS
            },
            ColorMode::Classification => PointFields {
                classification: true,
                ..PointFields::POSITIONS
            },
            ColorMode::Elevation | ColorMode::Flat => PointFields::POSITIONS,
        }
    }
}

/// `auto`, `rgb`, `intensity`, `classification`, `elevation` or `flat`.
impl std::str::FromStr for ColorMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        crate::value::choice(s, "colour mode")
    }
}

/// The flat colour.
pub const FLAT_COLOR: [u8; 3] = [200, 200, 200];

/// Why a colour mode cannot apply to a scene.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("the point cloud has no {attribute}; choose another --color (elevation, flat{others})")]
pub struct MissingAttribute {
    /// The attribute the mode needs.
    pub attribute: &'static str,
    /// Other modes that would work, as ", name" fragments.
    pub others: String,
}

/// A colour mode with its value ranges fixed, so that chunks of one cloud streamed separately
/// are coloured alike: intensity and elevation stretch between percentiles, which must come
/// from the whole cloud (or a sample of it), not from each chunk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorRule {
    /// The mode, resolved (`Auto` became `Rgb` or `Elevation`).
    pub mode: ColorMode,
    /// 1st and 99th percentiles of intensity or height (`z` relative to the scene origin) for
    /// `Intensity` and `Elevation`; unused otherwise.
    pub range: (f32, f32),
}

impl ColorRule {
    /// Resolves `mode` on `scene` (or a representative sample of the cloud): checks that the
    /// attribute exists and measures the percentile range.
    pub fn for_scene(scene: &Scene, mode: ColorMode) -> Result<Self, MissingAttribute> {
        let a = &scene.attributes;
        let missing = |attribute| MissingAttribute::in_scene(scene, attribute);
        let mode = match mode {
            ColorMode::Auto if a.rgb.is_some() => ColorMode::Rgb,
            ColorMode::Auto => ColorMode::Elevation,
            ColorMode::Image => ColorMode::Rgb,
            m => m,
        };
        let range = match mode {
            ColorMode::Rgb if a.rgb.is_none() => return Err(missing("RGB colour")),
            ColorMode::Classification if a.classification.is_none() => {
                return Err(missing("classification"));
            }
            ColorMode::Intensity => {
                let values = a.intensity.as_ref().ok_or_else(|| missing("intensity"))?;
                percentile_range(values.iter().map(|&v| v as f32))
            }
            ColorMode::Elevation => percentile_range(scene.positions.iter().map(|p| p.z)),
            _ => (0.0, 0.0),
        };
        Ok(ColorRule { mode, range })
    }

    /// Base colour of every point of `scene` (which must share the origin of the scene the
    /// rule was measured on, for elevation), in point order.
    pub fn colors(&self, scene: &Scene) -> Result<Vec<[u8; 3]>, MissingAttribute> {
        let (lo, hi) = self.range;
        let a = &scene.attributes;
        let missing = |attribute| MissingAttribute::in_scene(scene, attribute);
        Ok(match self.mode {
            ColorMode::Rgb | ColorMode::Image => match &a.rgb {
                Some(rgb) => rgb.clone(),
                None => return Err(missing("RGB colour")),
            },
            ColorMode::Flat => vec![FLAT_COLOR; scene.len()],
            ColorMode::Intensity => match &a.intensity {
                Some(values) => values
                    .iter()
                    .map(|&v| {
                        let g = (stretch(v as f32, lo, hi) * 255.0).round() as u8;
                        [g, g, g]
                    })
                    .collect(),
                None => return Err(missing("intensity")),
            },
            ColorMode::Classification => match &a.classification {
                Some(c) => c.iter().map(|&c| asprs_color(c)).collect(),
                None => return Err(missing("classification")),
            },
            ColorMode::Elevation | ColorMode::Auto => scene
                .positions
                .iter()
                .map(|p| viridis(stretch(p.z, lo, hi)))
                .collect(),
        })
    }
}

impl MissingAttribute {
    /// `attribute` is missing from `scene`; the message lists the modes that would work.
    fn in_scene(scene: &Scene, attribute: &'static str) -> Self {
        let a = &scene.attributes;
        let mut others = String::new();
        for (name, present) in [
            ("rgb", a.rgb.is_some()),
            ("intensity", a.intensity.is_some()),
            ("classification", a.classification.is_some()),
        ] {
            if present {
                others.push_str(", ");
                others.push_str(name);
            }
        }
        MissingAttribute { attribute, others }
    }
}

/// Base colour of every point under `mode`, in point order, with ranges from `scene` itself.
pub fn base_colors(scene: &Scene, mode: ColorMode) -> Result<Vec<[u8; 3]>, MissingAttribute> {
    ColorRule::for_scene(scene, mode)?.colors(scene)
}

fn stretch(v: f32, lo: f32, hi: f32) -> f32 {
    if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    }
}

/// 1st and 99th percentiles of the values, from an evenly strided sample of at most 100 k.
fn percentile_range(values: impl ExactSizeIterator<Item = f32>) -> (f32, f32) {
    let n = values.len();
    let stride = n.div_ceil(100_000).max(1);
    let mut sample: Vec<f32> = values.step_by(stride).filter(|v| v.is_finite()).collect();
    sample.sort_by(f32::total_cmp);
    let at = |q: f64| crate::stats::percentile(&sample, q).unwrap_or(0.0);
    (at(0.01), at(0.99))
}

/// ASPRS standard classification colours (LAS 1.4 R15 codes 0–18), grey otherwise.
pub fn asprs_color(class: u8) -> [u8; 3] {
    match class {
        0 | 1 => [170, 170, 170], // created / unclassified
        2 => [166, 118, 60],      // ground
        3 => [170, 220, 120],     // low vegetation
        4 => [90, 180, 60],       // medium vegetation
        5 => [30, 120, 40],       // high vegetation
        6 => [220, 70, 60],       // building
        7 => [255, 0, 255],       // low point (noise)
        8 => [255, 200, 0],       // model key point (LAS 1.0–1.3)
        9 => [60, 130, 230],      // water
        10 => [150, 100, 160],    // rail
        11 => [80, 80, 80],       // road surface
        12 => [255, 255, 150],    // overlap (LAS 1.0–1.3)
        13 => [240, 240, 60],     // wire guard
        14 => [240, 180, 60],     // wire conductor
        15 => [200, 120, 255],    // transmission tower
        16 => [255, 150, 200],    // wire connector
        17 => [120, 120, 200],    // bridge deck
        18 => [255, 0, 120],      // high noise
        _ => [128, 128, 128],
    }
}

/// Viridis colour map at `t` in [0, 1] (piecewise linear through 9 of its stops).
pub fn viridis(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 9] = [
        [68.0, 1.0, 84.0],
        [71.0, 44.0, 122.0],
        [59.0, 81.0, 139.0],
        [44.0, 113.0, 142.0],
        [33.0, 144.0, 141.0],
        [39.0, 173.0, 129.0],
        [92.0, 200.0, 99.0],
        [170.0, 220.0, 50.0],
        [253.0, 231.0, 37.0],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f32;
    let c = |ch: usize| (STOPS[k][ch] + (STOPS[k + 1][ch] - STOPS[k][ch]) * f).round() as u8;
    [c(0), c(1), c(2)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    #[test]
    fn elevation_ramp_runs_low_to_high() {
        let pts = (0..100).map(|k| Vec3::new(0.0, 0.0, k as f32)).collect();
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let c = base_colors(&scene, ColorMode::Elevation).unwrap();
        assert_eq!(c[0], viridis(0.0));
        assert_eq!(c[99], viridis(1.0));
        assert_eq!(base_colors(&scene, ColorMode::Auto).unwrap(), c);
    }

    #[test]
    fn a_rule_from_one_chunk_colours_another_alike() {
        let all: Vec<Vec3> = (0..100).map(|k| Vec3::new(0.0, 0.0, k as f32)).collect();
        let whole = Scene::new(DVec3::ZERO, all.clone(), 0.1);
        let rule = ColorRule::for_scene(&whole, ColorMode::Auto).unwrap();
        assert_eq!(rule.mode, ColorMode::Elevation);
        let upper = Scene::new(DVec3::ZERO, all[50..].to_vec(), 0.1);
        let full = base_colors(&whole, ColorMode::Elevation).unwrap();
        assert_eq!(rule.colors(&upper).unwrap(), full[50..].to_vec());
        // Ranged per chunk, the upper half alone would start at the bottom of the ramp.
        assert_ne!(
            base_colors(&upper, ColorMode::Elevation).unwrap(),
            full[50..].to_vec()
        );
    }

    #[test]
    fn missing_rgb_is_a_clear_error() {
        let scene = Scene::new(DVec3::ZERO, vec![Vec3::ZERO], 0.1);
        let e = base_colors(&scene, ColorMode::Rgb).unwrap_err();
        assert!(e.to_string().contains("no RGB colour"));
    }
}
