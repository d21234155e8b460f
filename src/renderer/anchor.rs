//! Where the rasterizer's points are measured from on the GPU.

use glam::DVec3;

/// The position (scene's local frame) the rasterizer's f32 point positions are relative to.
/// The ray tracer keeps the scene as it is and ignores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anchor {
    /// The scene's local zero: one upload serves every camera (a tour's local zero is the
    /// middle of its path).
    SceneZero,
    /// A camera position: f32 keeps millimetres near the eye; a camera that moves is placed
    /// again ([`Resident::place`](super::Resident::place)).
    Camera(DVec3),
}

impl Anchor {
    /// The anchor's position in the scene's local frame.
    pub fn position(self) -> DVec3 {
        match self {
            Anchor::SceneZero => DVec3::ZERO,
            Anchor::Camera(at) => at,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scene_zero_is_the_origin_and_a_camera_is_where_it_stands() {
        assert_eq!(Anchor::SceneZero.position(), DVec3::ZERO);
        let at = DVec3::new(3.5, -2.0, 1.7);
        assert_eq!(Anchor::Camera(at).position(), at);
    }
}
