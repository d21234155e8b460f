//! Shared by the criterion benches: a suite scene to measure on.

#![allow(dead_code)]

use omnicloud::Scene;
use omnicloud::render::RenderSettings;
use omnicloud::suite::{manifest_of, scenes};

/// The UTM street scene (861 spheres) and its mono settings at `width`.
pub fn street(width: u32) -> (Scene, RenderSettings) {
    let s = scenes::utm();
    let entry = manifest_of(std::slice::from_ref(&s)).scenes[0].clone();
    let scene = s.to_scene();
    let mut settings = entry.settings(scene.origin).expect("suite entry parses");
    settings.image = omnicloud::projection::Image::equirect(width);
    (scene, settings)
}

/// The dense cluster (3012 spheres) and the high-latitude field (1524) in one scene: a BVH
/// with both tight and spread-out leaves.
pub fn mixed() -> Scene {
    let mut a = scenes::dense_cluster().to_scene();
    let b = scenes::high_latitude().to_scene();
    let radii = |s: &Scene| (0..s.len()).map(|i| s.radii.get(i)).collect::<Vec<f32>>();
    let mut r = radii(&a);
    r.extend(radii(&b));
    a.positions.extend_from_slice(&b.positions);
    a.radii = omnicloud::Radii::PerPoint(r);
    a.attributes = Default::default();
    a
}
