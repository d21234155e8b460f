//! The in-memory scene every renderer draws: spheres around points, in a local f32 frame.

use glam::{DVec3, Vec3};

/// Per-point sphere radii: one global radius or one per point.
#[derive(Debug, Clone, PartialEq)]
pub enum Radii {
    /// Every sphere has this radius (metres).
    Uniform(f32),
    /// One radius per point (metres), same order as `Scene::positions`.
    PerPoint(Vec<f32>),
}

impl Radii {
    /// Radius of point `i`.
    #[inline]
    pub fn get(&self, i: usize) -> f32 {
        match self {
            Radii::Uniform(r) => *r,
            Radii::PerPoint(v) => v[i],
        }
    }

    /// Radii as read from a file: its per-point radii when it has them, with `default` for
    /// any that is not a positive finite number; else `default` for every point.
    pub fn from_file(radius: Option<Vec<f32>>, default: f32) -> Radii {
        match radius {
            Some(mut r) => {
                for x in &mut r {
                    if !(x.is_finite() && *x > 0.0) {
                        *x = default;
                    }
                }
                Radii::PerPoint(r)
            }
            None => Radii::Uniform(default),
        }
    }

    /// Largest radius (0 for an empty per-point list).
    pub fn max(&self) -> f32 {
        match self {
            Radii::Uniform(r) => *r,
            Radii::PerPoint(v) => v.iter().copied().fold(0.0, f32::max),
        }
    }
}

/// Optional per-point attributes read from the file, in point order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Attributes {
    /// sRGB colour scaled to 8 bits (16-bit LAS colour already reduced per DESIGN §5).
    pub rgb: Option<Vec<[u8; 3]>>,
    /// Raw intensity.
    pub intensity: Option<Vec<u16>>,
    /// ASPRS classification code.
    pub classification: Option<Vec<u8>>,
}

/// Points as spheres in a local frame: world = `origin` + position (DESIGN §1).
#[derive(Debug, Clone)]
pub struct Scene {
    /// f64 world coordinate (file coordinates) of the local frame's zero.
    pub origin: DVec3,
    /// Point centres relative to `origin`, metres, Z up.
    pub positions: Vec<Vec3>,
    /// Sphere radii.
    pub radii: Radii,
    /// Attributes for colouring.
    pub attributes: Attributes,
}

impl Scene {
    /// A scene of points with one radius and no attributes.
    pub fn new(origin: DVec3, positions: Vec<Vec3>, radius: f32) -> Self {
        Scene {
            origin,
            positions,
            radii: Radii::Uniform(radius),
            attributes: Attributes::default(),
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when the scene holds no point.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Moves the local frame's zero to `new_origin` (world coordinates), recomputing every
    /// position through f64 so precision follows the new origin (DESIGN §1).
    pub fn recenter(&mut self, new_origin: DVec3) {
        let shift = self.origin - new_origin;
        for p in &mut self.positions {
            *p = (p.as_dvec3() + shift).as_vec3();
        }
        self.origin = new_origin;
    }

    /// The points in `range` (clamped to the scene) as a scene of their own, same origin.
    pub fn range(&self, range: std::ops::Range<usize>) -> Scene {
        let end = range.end.min(self.len());
        let r = range.start.min(end)..end;
        Scene {
            origin: self.origin,
            positions: self.positions[r.clone()].to_vec(),
            radii: match &self.radii {
                Radii::Uniform(x) => Radii::Uniform(*x),
                Radii::PerPoint(v) => Radii::PerPoint(v[r.clone()].to_vec()),
            },
            attributes: Attributes {
                rgb: self.attributes.rgb.as_ref().map(|v| v[r.clone()].to_vec()),
                intensity: self
                    .attributes
                    .intensity
                    .as_ref()
                    .map(|v| v[r.clone()].to_vec()),
                classification: self
                    .attributes
                    .classification
                    .as_ref()
                    .map(|v| v[r.clone()].to_vec()),
            },
        }
    }

    /// Axis-aligned bounds of the point centres in the local frame, or `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recenter_keeps_millimetres_at_utm_scale() {
        let origin = DVec3::new(637_000.0, 851_000.0, 100.0);
        let world = DVec3::new(637_012.345_6, 851_020.001_2, 101.234_5);
        let mut scene = Scene::new(origin, vec![(world - origin).as_vec3()], 0.1);
        let camera = DVec3::new(637_012.0, 851_020.0, 101.0);
        scene.recenter(camera);
        let back = scene.origin + scene.positions[0].as_dvec3();
        assert!((back - world).abs().max_element() < 1e-5);
    }
}
