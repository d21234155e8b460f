//! The camera: a centre and a heading (DESIGN §1).

use glam::DVec3;

/// Camera centre (in the scene's local frame) and heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Centre `C`, metres, in the scene's local frame.
    pub center: DVec3,
    /// Heading in degrees: 0 looks along +Y, 90 along +X (clockwise seen from above).
    pub yaw_deg: f64,
}

/// The camera's orthonormal frame: forward, right, up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis {
    /// `F = (sin yaw, cos yaw, 0)`.
    pub forward: DVec3,
    /// `R = F x U`.
    pub right: DVec3,
    /// `U = (0, 0, 1)`.
    pub up: DVec3,
}

impl Camera {
    /// A camera at `center` with heading `yaw_deg`.
    pub fn new(center: DVec3, yaw_deg: f64) -> Self {
        Camera { center, yaw_deg }
    }

    /// Forward, right and up vectors (DESIGN §1).
    pub fn basis(&self) -> Basis {
        let yaw = self.yaw_deg.to_radians();
        let forward = DVec3::new(yaw.sin(), yaw.cos(), 0.0);
        let up = DVec3::Z;
        Basis {
            forward,
            right: forward.cross(up),
            up,
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
}
