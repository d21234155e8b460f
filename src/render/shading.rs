//! Shading of a sphere hit (DESIGN §5). `shaders/shading.wgsl` mirrors this file.
//!
//! `phong` lights the scene with two point lights fixed relative to the camera, like the
//! paper's LiDAR scene: a key light 10 m ahead-right and 10 m up, a fill light 10 m
//! behind-left and 5 m up. Shading happens in linear light; base colours are sRGB.

use glam::Vec3;

use crate::projection::Camera;

/// Shading model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Shading {
    /// Base colour only: the mode for accuracy comparisons.
    #[default]
    Unlit,
    /// Ambient + diffuse + specular from two point lights.
    Phong,
    /// The world-space surface normal as colour, `(n + 1) / 2`.
    Normal,
}

/// `unlit`, `phong` or `normal`.
impl std::str::FromStr for Shading {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        crate::value::choice(s, "shading")
    }
}

/// A point light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Position in the scene's local frame.
    pub position: Vec3,
    /// Intensity multiplier for diffuse and specular.
    pub intensity: f32,
}

/// Ambient term of `phong`.
pub const AMBIENT: f32 = 0.25;
/// Specular strength of `phong`.
pub const SPECULAR: f32 = 0.25;
/// Specular exponent of `phong`.
pub const SHININESS: f32 = 24.0;

/// The two lights of `phong` for `camera`.
pub fn lights(camera: &Camera) -> [Light; 2] {
    let b = camera.basis();
    let c = camera.center.as_vec3();
    let (f, r, u) = (b.forward.as_vec3(), b.right.as_vec3(), b.up.as_vec3());
    [
        Light {
            position: c + 10.0 * (f + r) + 10.0 * u,
            intensity: 0.8,
        },
        Light {
            position: c - 10.0 * (f + r) + 5.0 * u,
            intensity: 0.35,
        },
    ]
}

/// sRGB byte to linear light.
#[inline]
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to an sRGB byte (clamped).
#[inline]
pub fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0 + 0.5) as u8
}

/// Colour of a hit: `normal` is the surface normal facing the viewer, `hit` the hit point and
/// `eye` the ray's origin, all in the scene's local frame. The normal is normalised here: the
/// rasterizer's f32 normal is unit only to rounding, and both renderers must light the same
/// vector.
pub fn shade(
    mode: Shading,
    base: [u8; 3],
    normal: Vec3,
    hit: Vec3,
    eye: Vec3,
    lights: &[Light; 2],
) -> [u8; 3] {
    let normal = normal.normalize_or_zero();
    match mode {
        Shading::Unlit => base,
        Shading::Normal => normal
            .to_array()
            .map(|n| ((n * 0.5 + 0.5) * 255.0 + 0.5) as u8),
        Shading::Phong => {
            let albedo = Vec3::from_array(base.map(srgb_to_linear));
            let view = (eye - hit).normalize_or_zero();
            let mut diffuse = AMBIENT;
            let mut specular = 0.0;
            for light in lights {
                let l = (light.position - hit).normalize_or_zero();
                let n_dot_l = normal.dot(l);
                if n_dot_l > 0.0 {
                    diffuse += light.intensity * n_dot_l;
                    let reflected = 2.0 * n_dot_l * normal - l;
                    specular += light.intensity * reflected.dot(view).max(0.0).powf(SHININESS);
                }
            }
            let c = albedo * diffuse + Vec3::splat(SPECULAR * specular);
            c.to_array().map(linear_to_srgb)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_byte() {
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(b)), b);
        }
    }

    #[test]
    fn unlit_is_the_base_colour_and_phong_darkens_the_far_side() {
        let cam = Camera::new(glam::DVec3::ZERO, 0.0);
        let ls = lights(&cam);
        let base = [180, 120, 60];
        let eye = Vec3::ZERO;
        let hit = Vec3::new(0.0, 5.0, 0.0);
        assert_eq!(shade(Shading::Unlit, base, -Vec3::Y, hit, eye, &ls), base);
        let lit = shade(Shading::Phong, base, Vec3::Z, hit, eye, &ls);
        let dark = shade(Shading::Phong, base, -Vec3::Z, hit, eye, &ls);
        assert!(lit[0] > dark[0]);
        assert_eq!(
            shade(Shading::Normal, base, Vec3::Z, hit, eye, &ls),
            [128, 128, 255]
        );
    }
}
