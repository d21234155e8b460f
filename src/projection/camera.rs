//! The camera: a centre, a heading and the rig's pitch and roll (DESIGN §1, §8).

use glam::DVec3;

/// Camera centre (in the scene's local frame) and orientation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Centre `C`, metres, in the scene's local frame.
    pub center: DVec3,
    /// Heading in degrees: 0 looks along +Y, 90 along +X (clockwise seen from above).
    pub yaw_deg: f64,
    /// Pitch in degrees: positive looks up.
    pub pitch_deg: f64,
    /// Roll in degrees: positive turns the rig clockwise as seen from behind it.
    pub roll_deg: f64,
}

/// The camera's orthonormal frame: forward, right, up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis {
    /// `F`: `(sin yaw, cos yaw, 0)` turned up by the pitch.
    pub forward: DVec3,
    /// `R`: `F x U` before the roll, turned by it.
    pub right: DVec3,
    /// `U`: `(0, 0, 1)` without pitch and roll.
    pub up: DVec3,
}

impl Camera {
    /// A level camera at `center` with heading `yaw_deg`.
    pub fn new(center: DVec3, yaw_deg: f64) -> Self {
        Camera {
            center,
            yaw_deg,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        }
    }

    /// This camera with pitch `pitch_deg` and roll `roll_deg`.
    pub fn with_orientation(self, pitch_deg: f64, roll_deg: f64) -> Self {
        Camera {
            pitch_deg,
            roll_deg,
            ..self
        }
    }

    /// True when pitch and roll are zero (the rig's up is +Z).
    pub fn is_level(&self) -> bool {
        self.pitch_deg == 0.0 && self.roll_deg == 0.0
    }

    /// Forward, right and up vectors (DESIGN §8; §1 when level).
    pub fn basis(&self) -> Basis {
        let yaw = self.yaw_deg.to_radians();
        let f0 = DVec3::new(yaw.sin(), yaw.cos(), 0.0);
        let u0 = DVec3::Z;
        let r0 = f0.cross(u0);
        if self.is_level() {
            return Basis {
                forward: f0,
                right: r0,
                up: u0,
            };
        }
        let (sp, cp) = self.pitch_deg.to_radians().sin_cos();
        let (sq, cq) = self.roll_deg.to_radians().sin_cos();
        let forward = cp * f0 + sp * u0;
        let u1 = -sp * f0 + cp * u0;
        Basis {
            forward,
            right: cq * r0 - sq * u1,
            up: sq * r0 + cq * u1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn yaw_zero_looks_along_y_and_right_is_x() {
        let b = Camera::new(DVec3::ZERO, 0.0).basis();
        assert!((b.forward - DVec3::Y).length() < 1e-12);
        assert!((b.right - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn yaw_ninety_looks_along_x() {
        let b = Camera::new(DVec3::ZERO, 90.0).basis();
        assert!((b.forward - DVec3::X).length() < 1e-12);
        assert!((b.right + DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn pitch_ninety_looks_straight_up_with_up_pointing_back() {
        let b = Camera::new(DVec3::ZERO, 0.0)
            .with_orientation(90.0, 0.0)
            .basis();
        assert!((b.forward - DVec3::Z).length() < 1e-12);
        assert!((b.up + DVec3::Y).length() < 1e-12);
        assert!((b.right - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn positive_roll_lowers_the_right_side() {
        let b = Camera::new(DVec3::ZERO, 0.0)
            .with_orientation(0.0, 30.0)
            .basis();
        assert!(b.right.z < 0.0);
        assert!((b.right.z + 0.5).abs() < 1e-12);
        assert!((b.forward - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn every_orientation_is_orthonormal_and_right_handed() {
        for &(y, p, q) in &[
            (10.0, 20.0, 30.0),
            (-170.0, -80.0, 95.0),
            (45.0, 0.0, -10.0),
        ] {
            let b = Camera::new(DVec3::ZERO, y).with_orientation(p, q).basis();
            for v in [b.forward, b.right, b.up] {
                assert!((v.length() - 1.0).abs() < 1e-12);
            }
            assert!(b.forward.dot(b.right).abs() < 1e-12);
            assert!(b.forward.dot(b.up).abs() < 1e-12);
            assert!((b.forward.cross(b.up) - b.right).length() < 1e-12);
        }
    }
}
