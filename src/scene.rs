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
    /// Return number and number of returns (LAS; PLY when it has both properties).
    pub returns: Option<Vec<Returns>>,
}

/// A LiDAR pulse's return number and its number of returns, as the LAS record stores them
/// (0–15 each; 0 means the file does not say).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Returns {
    /// Which return of its pulse the point is (1 = first).
    pub number: u8,
    /// How many returns its pulse had.
    pub of: u8,
}

impl Returns {
    /// The first return of its pulse; a point whose file gives no return number (0) counts
    /// as its pulse's only return.
    pub fn is_first(self) -> bool {
        self.number <= 1
    }

    /// The last return of its pulse (also a pulse's only return, and a point whose file
    /// gives no number of returns).
    pub fn is_last(self) -> bool {
        self.number >= self.of
    }
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

    /// `n` points given in world coordinates by `point(i)` (finite), placed as the readers
    /// place a file without header bounds: the local zero at `origin`, else at the centre of
    /// the points' bounds, each position its f32 offset from there; one `radius` for all.
    pub fn from_world(
        n: usize,
        point: impl Fn(usize) -> DVec3,
        origin: Option<DVec3>,
        radius: f32,
    ) -> Scene {
        let origin = origin.unwrap_or_else(|| {
            let (lo, hi) = (0..n)
                .map(&point)
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p), hi.max(p))
                });
            if n == 0 { DVec3::ZERO } else { (lo + hi) * 0.5 }
        });
        let positions = (0..n).map(|i| (point(i) - origin).as_vec3()).collect();
        Scene::new(origin, positions, radius)
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
                returns: self
                    .attributes
                    .returns
                    .as_ref()
                    .map(|v| v[r.clone()].to_vec()),
            },
        }
    }

    /// The points whose `mask` flag is set, with their radii and attributes, as a scene of
    /// their own (same origin). Points beyond the mask's end are dropped.
    pub fn select(&self, mask: &[bool]) -> Scene {
        fn pick<T: Copy>(v: &[T], mask: &[bool]) -> Vec<T> {
            masked(v, mask).collect()
        }
        let a = &self.attributes;
        Scene {
            origin: self.origin,
            positions: pick(&self.positions, mask),
            radii: match &self.radii {
                Radii::Uniform(r) => Radii::Uniform(*r),
                Radii::PerPoint(v) => Radii::PerPoint(pick(v, mask)),
            },
            attributes: Attributes {
                rgb: a.rgb.as_deref().map(|v| pick(v, mask)),
                intensity: a.intensity.as_deref().map(|v| pick(v, mask)),
                classification: a.classification.as_deref().map(|v| pick(v, mask)),
                returns: a.returns.as_deref().map(|v| pick(v, mask)),
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

/// The `values` whose `mask` flag is set, in order: the one selection behind
/// [`Scene::select`] and the loaders' per-chunk attribute gathering ([`extend_masked`]).
pub(crate) fn masked<'a, T: Copy>(
    values: &'a [T],
    mask: &'a [bool],
) -> impl Iterator<Item = T> + 'a {
    values
        .iter()
        .zip(mask)
        .filter(|(_, keep)| **keep)
        .map(|(v, _)| *v)
}

/// Appends to `out` the `values` whose `mask` flag is set (nothing when `values` is `None`):
/// a loader gathering one attribute chunk by chunk.
pub(crate) fn extend_masked<T: Copy>(
    out: &mut Option<Vec<T>>,
    values: Option<&[T]>,
    mask: &[bool],
) {
    if let Some(values) = values {
        out.get_or_insert_with(Vec::new)
            .extend(masked(values, mask));
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

    #[test]
    fn select_keeps_flagged_points_with_their_radii_and_attributes() {
        let mut s = Scene::new(
            DVec3::ONE,
            (0..5).map(|i| Vec3::splat(i as f32)).collect(),
            0.1,
        );
        s.attributes.intensity = Some(vec![0, 1, 2, 3, 4]);
        s.radii = Radii::PerPoint(vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        let t = s.select(&[true, false, true, false, true]);
        assert_eq!(t.origin, DVec3::ONE);
        assert_eq!(
            t.positions,
            [Vec3::ZERO, Vec3::splat(2.0), Vec3::splat(4.0)]
        );
        assert_eq!(t.attributes.intensity, Some(vec![0, 2, 4]));
        assert_eq!(t.attributes.rgb, None);
        assert_eq!(t.radii, Radii::PerPoint(vec![1.0, 3.0, 5.0]));
        let mut acc = None;
        extend_masked(&mut acc, Some(&[7u8, 8, 9][..]), &[false, true, true]);
        extend_masked(&mut acc, None, &[true]);
        assert_eq!(acc, Some(vec![8, 9]));
    }
}
