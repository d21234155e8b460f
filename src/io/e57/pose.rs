//! A scan's or an image's pose: the rigid motion from its own frame to the file's frame,
//! `world = R(q) · local + t` (DESIGN §12).

use glam::{DQuat, DVec3};

/// Rotation and translation of a scan or image, as the E57 file states them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Unit rotation quaternion (normalised on reading: files round their components).
    pub rotation: DQuat,
    /// Translation: where the frame's zero lies in the file's frame.
    pub translation: DVec3,
}

impl Default for Pose {
    fn default() -> Self {
        Pose {
            rotation: DQuat::IDENTITY,
            translation: DVec3::ZERO,
        }
    }
}

impl Pose {
    /// The pose an E57 `pose` element states; the identity when there is none. A rotation
    /// of zero length (a broken file) reads as the identity.
    pub fn from_e57(transform: Option<&e57::Transform>) -> Pose {
        let Some(t) = transform else {
            return Pose::default();
        };
        let q = DQuat::from_xyzw(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w);
        let rotation = if q.length_squared() > 0.0 && q.is_finite() {
            q.normalize()
        } else {
            DQuat::IDENTITY
        };
        Pose {
            rotation,
            translation: DVec3::new(t.translation.x, t.translation.y, t.translation.z),
        }
    }

    /// A point of the frame in file coordinates: `R · local + t`.
    #[inline]
    pub fn apply(&self, local: DVec3) -> DVec3 {
        self.rotation * local + self.translation
    }

    /// A file-frame point in this frame's coordinates: `Rᵀ · (world − t)`.
    #[inline]
    pub fn inverse_apply(&self, world: DVec3) -> DVec3 {
        self.rotation.inverse() * (world - self.translation)
    }

    /// Heading in degrees (0 along +Y, 90 along +X): the yaw of `R · (0, 1, 0)` on the
    /// horizontal plane, so an unrotated frame looks along +Y. 0 when that axis is vertical.
    pub fn yaw_degrees(&self) -> f64 {
        let d = self.rotation * DVec3::Y;
        if d.x.hypot(d.y) < 1e-12 {
            return 0.0;
        }
        d.x.atan2(d.y).to_degrees()
    }
}

/// A spherical coordinate (range, azimuth, elevation; radians) as a Cartesian point of the
/// scan's frame: `r (cos e cos a, cos e sin a, sin e)`.
#[inline]
pub fn spherical_to_local(range: f64, azimuth: f64, elevation: f64) -> DVec3 {
    let (se, ce) = elevation.sin_cos();
    let (sa, ca) = azimuth.sin_cos();
    DVec3::new(range * ce * ca, range * ce * sa, range * se)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn transform(q: [f64; 4], t: [f64; 3]) -> e57::Transform {
        e57::Transform {
            rotation: e57::Quaternion {
                w: q[0],
                x: q[1],
                y: q[2],
                z: q[3],
            },
            translation: e57::Translation {
                x: t[0],
                y: t[1],
                z: t[2],
            },
        }
    }

    #[test]
    fn a_quarter_turn_about_z_maps_x_to_y_then_translates() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let pose = Pose::from_e57(Some(&transform([h, 0.0, 0.0, h], [10.0, 20.0, 3.0])));
        let p = pose.apply(DVec3::new(1.0, 0.0, 0.0));
        assert!((p - DVec3::new(10.0, 21.0, 3.0)).length() < 1e-12, "{p}");
        let back = pose.inverse_apply(p);
        assert!((back - DVec3::X).length() < 1e-12);
        // +Y turned a quarter anticlockwise looks along -X: heading -90.
        assert!((pose.yaw_degrees() + 90.0).abs() < 1e-9);
        assert_eq!(Pose::from_e57(None).yaw_degrees(), 0.0);
    }

    #[test]
    fn unnormalised_and_zero_quaternions_read_sanely() {
        let pose = Pose::from_e57(Some(&transform([2.0, 0.0, 0.0, 0.0], [0.0; 3])));
        assert_eq!(pose.apply(DVec3::ONE), DVec3::ONE);
        let zero = Pose::from_e57(Some(&transform([0.0; 4], [1.0, 0.0, 0.0])));
        assert_eq!(zero.apply(DVec3::ZERO), DVec3::X);
    }

    #[test]
    fn spherical_axes() {
        let p = spherical_to_local(2.0, std::f64::consts::FRAC_PI_2, 0.0);
        assert!((p - DVec3::new(0.0, 2.0, 0.0)).length() < 1e-12);
        let up = spherical_to_local(3.0, 1.0, std::f64::consts::FRAC_PI_2);
        assert!((up - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-12);
    }
}
