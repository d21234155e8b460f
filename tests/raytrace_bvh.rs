//! The BVH tracer returns exactly the brute-force closest hit (index and distance) on
//! random scenes, including duplicated points, mixed radii and far-off coordinates.

use glam::{DVec3, Vec3};
use omnicloud::raytrace::{Tracer, trace_brute_force};
use omnicloud::rng::SplitMix64;
use omnicloud::{Radii, Scene};

/// A random unit vector (rejection sampling in the unit ball).
fn unit(rng: &mut SplitMix64) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

fn random_scene(
    rng: &mut SplitMix64,
    n: usize,
    offset: Vec3,
    extent: f64,
    per_point: bool,
) -> Scene {
    let mut pts: Vec<Vec3> = (0..n)
        .map(|_| {
            offset
                + Vec3::new(
                    rng.range(-extent, extent) as f32,
                    rng.range(-extent, extent) as f32,
                    rng.range(-0.3 * extent, 0.3 * extent) as f32,
                )
        })
        .collect();
    // Duplicates: exact ties that must go to the lowest index.
    for k in 0..n / 20 {
        let p = pts[k * 7 % n];
        pts.push(p);
    }
    let mut scene = Scene::new(DVec3::ZERO, pts, (0.02 * extent) as f32);
    if per_point {
        let radii = (0..scene.len())
            .map(|_| rng.range(0.005, 0.05) as f32 * extent as f32)
            .collect();
        scene.radii = Radii::PerPoint(radii);
    }
    scene
}

fn assert_same_hits(scene: &Scene, rng: &mut SplitMix64, origins: &[DVec3], rays: usize) -> usize {
    let tracer = Tracer::new(scene).unwrap();
    let mut hits = 0;
    for k in 0..rays {
        let origin = origins[k % origins.len()];
        let dir = unit(rng);
        let fast = tracer.trace(origin, dir);
        let slow = trace_brute_force(scene, origin, dir);
        assert_eq!(fast, slow, "ray {k}: origin {origin} dir {dir}");
        hits += fast.is_some() as usize;
    }
    hits
}

#[test]
fn bvh_equals_brute_force_on_random_scenes() {
    let mut rng = SplitMix64::new(0x9e37_79b9_7f4a_7c15);
    for (n, per_point, min_hits) in [(3000, false, 400), (3000, true, 400), (17, true, 20)] {
        let scene = random_scene(&mut rng, n, Vec3::ZERO, 10.0, per_point);
        let mut origins: Vec<DVec3> = (0..64)
            .map(|_| {
                DVec3::new(
                    rng.range(-12.0, 12.0),
                    rng.range(-12.0, 12.0),
                    rng.range(-4.0, 4.0),
                )
            })
            .collect();
        // Origins at sphere centres (inside) and on sphere surfaces.
        origins.push(scene.positions[5].as_dvec3());
        origins.push(scene.positions[9].as_dvec3() + DVec3::X * scene.radii.get(9) as f64);
        let hits = assert_same_hits(&scene, &mut rng, &origins, 4000);
        assert!(hits > min_hits, "only {hits} hits: the scene tests nothing");
    }
}

#[test]
fn bvh_equals_brute_force_far_from_the_local_zero() {
    // A cloud 800 m away with centimetre spheres, seen from the local zero and from inside.
    let mut rng = SplitMix64::new(42);
    let offset = Vec3::new(600.0, -500.0, 30.0);
    let scene = random_scene(&mut rng, 4000, offset, 2.0, true);
    let origins = [
        DVec3::ZERO,
        offset.as_dvec3(),
        offset.as_dvec3() + DVec3::new(1.0, 1.0, 0.5),
    ];
    // Aim at random points of the cloud so that most rays hit something.
    let tracer = Tracer::new(&scene).unwrap();
    let mut hits = 0;
    for k in 0..3000 {
        let origin = origins[k % origins.len()];
        let target = scene.positions[k % scene.len()].as_dvec3() + 0.01 * unit(&mut rng);
        let dir = target - origin;
        let fast = tracer.trace(origin, dir);
        assert_eq!(fast, trace_brute_force(&scene, origin, dir), "ray {k}");
        hits += fast.is_some() as usize;
    }
    assert!(hits > 1500, "only {hits} hits");
}
