//! The map projection's extent: the scan's XY bounds, sphere extents included.

use glam::DVec3;

use crate::projection::Image;
use crate::scene::Scene;

/// The top-down map of `scene` (local frame) `width` pixels wide, north up, over the bounds
/// of its spheres (DESIGN §8).
///
/// # Errors
/// An empty scene, or a scan whose aspect gives a height beyond the largest image.
pub fn map_image(scene: &Scene, width: u32) -> Result<Image, String> {
    let (lo, hi) = scene
        .bounds()
        .ok_or_else(|| "the map needs at least one point".to_string())?;
    let r = f64::from(scene.radii.max());
    let pad = DVec3::splat(r);
    Image::map(lo.as_dvec3() - pad, hi.as_dvec3() + pad, width)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::Projection;
    use glam::Vec3;

    #[test]
    fn the_map_covers_every_sphere() {
        let scene = Scene::new(
            DVec3::ZERO,
            vec![Vec3::new(-10.0, 0.0, 1.0), Vec3::new(30.0, 10.0, 5.0)],
            0.5,
        );
        let image = map_image(&scene, 410).unwrap();
        let Projection::Map(Some(f)) = image.projection else {
            panic!("{image:?}")
        };
        assert!((f.x0 + 10.5).abs() < 1e-6 && (f.x1 - 30.5).abs() < 1e-6);
        assert_eq!(image.height, 110);
        assert!((f.z_top - 6.5).abs() < 1e-6);
        assert!(map_image(&Scene::new(DVec3::ZERO, vec![], 1.0), 64).is_err());
    }
}
