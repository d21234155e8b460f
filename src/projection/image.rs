//! The output image: a projection (DESIGN §2, §8) and its pixel grid.

use std::f64::consts::{PI, TAU};
use std::fmt;
use std::str::FromStr;

use glam::DVec3;

use super::equirect::Equirect;
use super::map::MapFrame;
use super::{cubemap, cylindrical, fisheye, hammer};

/// How image positions map to directions (`--projection`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Equirectangular over `hfov x vfov` degrees, centred on the heading.
    Equirect {
        /// Horizontal field of view, degrees, in (0, 360].
        hfov_deg: f64,
        /// Vertical field of view, degrees, in (0, 180].
        vfov_deg: f64,
    },
    /// Hammer–Aitoff, the whole sphere in an ellipse.
    Hammer,
    /// Full longitude; latitude through `tan`.
    Cylindrical {
        /// Vertical field of view, degrees, in (0, 180).
        vfov_deg: f64,
    },
    /// Equidistant fisheye centred on the heading.
    Fisheye {
        /// Field of view, degrees, in (0, 360].
        fov_deg: f64,
    },
    /// Six 90° faces in one strip.
    Cubemap,
    /// Orthographic from above over the scan, north up (mono only); the frame is set from
    /// the scene's bounds before rendering.
    Map(Option<MapFrame>),
}

impl Default for Projection {
    fn default() -> Self {
        Projection::EQUIRECT
    }
}

impl Projection {
    /// The full equirectangular panorama.
    pub const EQUIRECT: Projection = Projection::Equirect {
        hfov_deg: 360.0,
        vfov_deg: 180.0,
    };

    /// True for the full 360 x 180 equirectangular panorama.
    pub fn is_full_equirect(&self) -> bool {
        *self == Projection::EQUIRECT
    }

    /// True for the map (mono only, camera orientation ignored).
    pub fn is_map(&self) -> bool {
        matches!(self, Projection::Map(_))
    }

    /// Short name as accepted by `--projection`.
    pub fn name(&self) -> &'static str {
        match self {
            Projection::Equirect { .. } => "equirect",
            Projection::Hammer => "hammer",
            Projection::Cylindrical { .. } => "cylindrical",
            Projection::Fisheye { .. } => "fisheye",
            Projection::Cubemap => "cubemap",
            Projection::Map(_) => "map",
        }
    }

    /// Image height for `width`, or why `width` does not suit this projection. The map
    /// needs its frame (see [`Image::map`]).
    ///
    /// # Errors
    /// A message naming the rule.
    pub fn height(&self, width: u32) -> Result<u32, String> {
        let height = match *self {
            Projection::Equirect { hfov_deg, vfov_deg } => {
                if self.is_full_equirect() {
                    Equirect::check_width(width)?;
                    width / 2
                } else {
                    (f64::from(width) * vfov_deg / hfov_deg).round() as u32
                }
            }
            Projection::Hammer => {
                if !width.is_multiple_of(2) {
                    return Err(format!("hammer needs an even width, got {width}"));
                }
                width / 2
            }
            Projection::Cylindrical { vfov_deg } => {
                cylindrical::height(width, vfov_deg.to_radians())
            }
            Projection::Fisheye { .. } => width,
            Projection::Cubemap => {
                if !width.is_multiple_of(6) {
                    return Err(format!(
                        "cubemap needs a width that is a multiple of 6 (six square faces), got {width}"
                    ));
                }
                width / 6
            }
            Projection::Map(frame) => {
                let Some(f) = frame else {
                    return Err("the map's extent comes from the scene's bounds".into());
                };
                (f64::from(width) * (f.y1 - f.y0) / (f.x1 - f.x0)).round() as u32
            }
        };
        if !(Equirect::MIN_WIDTH..=Equirect::MAX_WIDTH).contains(&width) {
            return Err(format!(
                "the width must lie within {}..={}, got {width}",
                Equirect::MIN_WIDTH,
                Equirect::MAX_WIDTH
            ));
        }
        if height == 0 || height > Equirect::MAX_WIDTH {
            return Err(format!(
                "{} at width {width} gives a height of {height} pixels: it must lie within 1..={}",
                self.name(),
                Equirect::MAX_WIDTH
            ));
        }
        Ok(height)
    }

    /// Longitude and latitude in the rig frame seen at continuous image position `(u, v)` in
    /// `[0, 1]^2`, or `None` where the projection shows nothing (and for the map, whose rays
    /// are vertical and parallel).
    #[inline]
    pub fn angles(&self, u: f64, v: f64) -> Option<(f64, f64)> {
        match *self {
            Projection::Equirect { hfov_deg, vfov_deg } => {
                if self.is_full_equirect() {
                    Some(((u - 0.5) * TAU, (0.5 - v) * PI))
                } else {
                    let (h, w) = (hfov_deg.to_radians(), vfov_deg.to_radians());
                    Some(((u - 0.5) * h, (0.5 - v) * w))
                }
            }
            Projection::Hammer => hammer::angles(u, v),
            Projection::Cylindrical { vfov_deg } => {
                Some(cylindrical::angles(u, v, vfov_deg.to_radians()))
            }
            Projection::Fisheye { fov_deg } => {
                fisheye::direction(u, v, fov_deg.to_radians()).map(rig_angles)
            }
            Projection::Cubemap => Some(rig_angles(cubemap::direction(u, v))),
            Projection::Map(_) => None,
        }
    }

    /// Continuous image position `(u, v)` in `[0, 1]^2` at which the rig-frame direction `d`
    /// (components `(d.R, d.F, d.U)`) appears, or `None` where it is outside the image. Not
    /// for the map.
    pub fn position_of_direction(&self, d: DVec3) -> Option<(f64, f64)> {
        let lam = d.x.atan2(d.y);
        let phi = d.z.atan2(d.x.hypot(d.y));
        let inside = |(u, v): (f64, f64)| {
            ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some((u, v))
        };
        match *self {
            Projection::Equirect { hfov_deg, vfov_deg } => inside((
                lam / hfov_deg.to_radians() + 0.5,
                0.5 - phi / vfov_deg.to_radians(),
            )),
            Projection::Hammer => Some(hammer::position(lam, phi)),
            Projection::Cylindrical { vfov_deg } => {
                inside(cylindrical::position(lam, phi, vfov_deg.to_radians()))
            }
            Projection::Fisheye { fov_deg } => fisheye::position(d, fov_deg.to_radians()),
            Projection::Cubemap => Some(cubemap::position(d)),
            Projection::Map(_) => None,
        }
    }
}

/// Longitude and latitude of a rig-frame direction `(d.R, d.F, d.U)` (DESIGN §8:
/// `lam = atan2(d.R, d.F)`, `phi = asin(d.U)`, the latter through `atan2` so a direction a
/// rounding away from unit length keeps its latitude).
#[inline]
pub fn rig_angles(d: DVec3) -> (f64, f64) {
    (d.x.atan2(d.y), d.z.atan2(d.x.hypot(d.y)))
}

/// Parses `equirect[:HFOV,VFOV]`, `hammer`, `cylindrical[:VFOV]`, `fisheye[:FOV]`, `cubemap`
/// or `map` (degrees).
impl FromStr for Projection {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim().to_ascii_lowercase();
        let (name, args) = match s.split_once(':') {
            Some((n, a)) => (n, Some(a)),
            None => (s.as_str(), None),
        };
        let angle = |text: &str, what: &str, max: f64, max_ok: bool| -> Result<f64, String> {
            let v: f64 = text
                .trim()
                .parse()
                .map_err(|_| format!("{name}: {what} must be a number of degrees, got `{text}`"))?;
            let ok = v.is_finite() && v > 0.0 && (v < max || (max_ok && v == max));
            if ok {
                Ok(v)
            } else {
                let end = if max_ok { "]" } else { ")" };
                Err(format!(
                    "{name}: {what} must lie in (0, {max}{end} degrees, got {v}"
                ))
            }
        };
        let no_args = |p: Projection| match args {
            None => Ok(p),
            Some(a) => Err(format!("{name} takes no parameters, got `{name}:{a}`")),
        };
        match name {
            "equirect" | "equirectangular" => match args {
                None => Ok(Projection::EQUIRECT),
                Some(a) => {
                    let (h, v) = a.split_once(',').ok_or_else(|| {
                        format!("expected equirect:HFOV,VFOV (degrees), got `{s}`")
                    })?;
                    Ok(Projection::Equirect {
                        hfov_deg: angle(h, "the horizontal field of view", 360.0, true)?,
                        vfov_deg: angle(v, "the vertical field of view", 180.0, true)?,
                    })
                }
            },
            "cylindrical" => Ok(Projection::Cylindrical {
                vfov_deg: match args {
                    None => 90.0,
                    Some(a) => angle(a, "the vertical field of view", 180.0, false)?,
                },
            }),
            "fisheye" => Ok(Projection::Fisheye {
                fov_deg: match args {
                    None => 180.0,
                    Some(a) => angle(a, "the field of view", 360.0, true)?,
                },
            }),
            "hammer" => no_args(Projection::Hammer),
            "cubemap" => no_args(Projection::Cubemap),
            "map" => no_args(Projection::Map(None)),
            _ => Err(format!(
                "unknown projection `{s}`: use equirect[:HFOV,VFOV], hammer, cylindrical[:VFOV], \
                 fisheye[:FOV], cubemap or map"
            )),
        }
    }
}

/// Prints as `--projection` parses.
impl fmt::Display for Projection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Projection::Equirect { .. } if self.is_full_equirect() => write!(f, "equirect"),
            Projection::Equirect { hfov_deg, vfov_deg } => {
                write!(f, "equirect:{hfov_deg},{vfov_deg}")
            }
            Projection::Cylindrical { vfov_deg } => write!(f, "cylindrical:{vfov_deg}"),
            Projection::Fisheye { fov_deg } => write!(f, "fisheye:{fov_deg}"),
            _ => write!(f, "{}", self.name()),
        }
    }
}

/// An image: its projection and pixel grid. Pixel `(i, j)` is sampled at its centre,
/// `u = (i + 0.5)/W`, `v = (j + 0.5)/H`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The projection.
    pub projection: Projection,
}

impl Image {
    /// The full equirectangular panorama `width` wide (`width / 2` high).
    pub fn equirect(width: u32) -> Self {
        Image {
            width,
            height: width / 2,
            projection: Projection::EQUIRECT,
        }
    }

    /// `projection` at `width`, its height from the projection.
    ///
    /// # Errors
    /// Why the width does not suit the projection (and for an unresolved map).
    pub fn new(projection: Projection, width: u32) -> Result<Self, String> {
        let height = projection.height(width)?;
        Ok(Image {
            width,
            height,
            projection,
        })
    }

    /// The map over XY box `[lo, hi]` (local frame, sphere extents included), `width` wide.
    ///
    /// # Errors
    /// When the scan's aspect gives a height beyond the largest image.
    pub fn map(lo: DVec3, hi: DVec3, width: u32) -> Result<Self, String> {
        let (frame, _) = MapFrame::over(lo, hi, width);
        Image::new(Projection::Map(Some(frame)), width)
    }

    /// The equirectangular grid of this image when it is the full panorama.
    pub fn as_equirect(&self) -> Option<Equirect> {
        self.projection.is_full_equirect().then_some(Equirect {
            width: self.width,
            height: self.height,
        })
    }

    /// `(u, v)` of the centre of pixel `(i, j)`.
    #[inline]
    pub fn pixel_uv(&self, i: u32, j: u32) -> (f64, f64) {
        (
            (f64::from(i) + 0.5) / f64::from(self.width),
            (f64::from(j) + 0.5) / f64::from(self.height),
        )
    }

    /// Longitude and latitude (rig frame) seen by the centre of pixel `(i, j)`, or `None`.
    #[inline]
    pub fn pixel_angles(&self, i: u32, j: u32) -> Option<(f64, f64)> {
        match self.as_equirect() {
            // The full panorama keeps the equirect module's arithmetic, bit for bit.
            Some(e) => Some(e.pixel_angles(i, j)),
            None => {
                let (u, v) = self.pixel_uv(i, j);
                self.projection.angles(u, v)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for s in [
            "equirect",
            "equirect:180,90",
            "hammer",
            "cylindrical:100",
            "fisheye:220",
            "cubemap",
            "map",
        ] {
            let p: Projection = s.parse().unwrap();
            assert_eq!(p.to_string(), s);
            assert_eq!(p.to_string().parse::<Projection>().unwrap(), p);
        }
        assert_eq!(
            "equirect:360,180".parse::<Projection>().unwrap(),
            Projection::EQUIRECT
        );
        assert_eq!(
            "fisheye".parse::<Projection>().unwrap(),
            Projection::Fisheye { fov_deg: 180.0 }
        );
    }

    #[test]
    fn bad_values_name_the_field() {
        for (s, needle) in [
            ("equirect:400,90", "horizontal field of view"),
            ("equirect:90", "HFOV,VFOV"),
            ("cylindrical:180", "(0, 180)"),
            ("fisheye:NaN", "field of view"),
            ("hammer:3", "no parameters"),
            ("mercator", "unknown projection"),
        ] {
            let e = s.parse::<Projection>().unwrap_err();
            assert!(e.contains(needle), "{s}: {e}");
        }
    }

    #[test]
    fn heights_follow_the_projection() {
        let h = |s: &str, w| s.parse::<Projection>().unwrap().height(w);
        assert_eq!(h("equirect", 512), Ok(256));
        assert_eq!(h("equirect:180,90", 512), Ok(256));
        assert_eq!(h("equirect:120,90", 480), Ok(360));
        assert_eq!(h("hammer", 512), Ok(256));
        assert_eq!(h("fisheye", 300), Ok(300));
        assert_eq!(h("cubemap", 600), Ok(100));
        assert!(h("cubemap", 512).unwrap_err().contains("multiple of 6"));
        assert!(h("map", 512).is_err());
    }

    #[test]
    fn partial_equirect_at_full_view_is_the_panorama() {
        let full = Image::equirect(64);
        let e = full.as_equirect().unwrap();
        for (i, j) in [(0, 0), (13, 7), (63, 31)] {
            assert_eq!(full.pixel_angles(i, j), Some(e.pixel_angles(i, j)));
        }
    }

    #[test]
    fn every_projection_sees_its_own_positions() {
        for s in [
            "equirect:200,100",
            "hammer",
            "cylindrical:120",
            "fisheye:270",
            "cubemap",
        ] {
            let p: Projection = s.parse().unwrap();
            for &(u, v) in &[(0.5, 0.5), (0.31, 0.42), (0.77, 0.6), (0.45, 0.2)] {
                let Some((lam, phi)) = p.angles(u, v) else {
                    continue;
                };
                let d = DVec3::new(phi.cos() * lam.sin(), phi.cos() * lam.cos(), phi.sin());
                let (u2, v2) = p.position_of_direction(d).unwrap();
                assert!(
                    (u2 - u).abs() < 1e-9 && (v2 - v).abs() < 1e-9,
                    "{s} {u},{v}"
                );
            }
        }
    }
}
