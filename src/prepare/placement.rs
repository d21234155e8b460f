//! Automatic camera placement: eye height above the ground at the middle of the scan.

use crate::scene::Scene;
use glam::{DVec3, Vec2};
use std::collections::HashMap;

/// Eye height above the estimated ground (metres).
pub const EYE_HEIGHT: f64 = 1.7;
/// Non-empty cells the neighbourhood must reach before the ground is estimated.
const MIN_CELLS: usize = 24;
/// Cells per neighbourhood radius.
const CELLS_PER_RADIUS: f32 = 4.0;
/// Percentile of heights taken as a cell's ground: low enough to ignore objects standing on
/// the ground, high enough to ignore a few noise points below it.
const CELL_PERCENTILE: f32 = 0.1;

/// A camera position (local frame) [`EYE_HEIGHT`] above open ground near the local zero: the
/// nearest point of a 10 m grid (out to 80 m) whose ground, a low height percentile within
/// 5 m, has no point more than 0.5 m above it; the local zero at eye height when none is.
///
/// For benchmarks and tests that want an unobstructed view (no canopy or wall next to the
/// eye), unlike [`auto_camera_position`], which stands exactly at the scan's centre.
pub fn open_ground_camera_position(scene: &Scene) -> DVec3 {
    let mut candidates: Vec<(f32, f32)> = (-8..=8)
        .flat_map(|i| (-8..=8).map(move |j| (i as f32 * 10.0, j as f32 * 10.0)))
        .collect();
    candidates.sort_by(|a, b| a.0.hypot(a.1).total_cmp(&b.0.hypot(b.1)));
    let (x, y, ground) = candidates
        .iter()
        .find_map(|&(x, y)| {
            let mut near: Vec<f32> = scene
                .positions
                .iter()
                .filter(|p| (p.x - x).hypot(p.y - y) < 5.0)
                .map(|p| p.z)
                .collect();
            if near.len() < 10 {
                return None;
            }
            near.sort_by(f32::total_cmp);
            let ground = near[near.len() / 20];
            (near[near.len() - 1] < ground + 0.5).then_some((x, y, ground))
        })
        .unwrap_or((0.0, 0.0, 0.0));
    DVec3::new(x as f64, y as f64, ground as f64 + EYE_HEIGHT)
}

/// Moves the scene's frame onto the camera (DESIGN §1: the origin is the camera position)
/// and returns the camera's world position: `camera` when given (file coordinates), else
/// [`auto_camera_position`]. `None` for an empty scene without a given camera.
pub fn center_on_camera(scene: &mut Scene, camera: Option<DVec3>) -> Option<DVec3> {
    let world = match camera {
        Some(c) => c,
        None => scene.origin + auto_camera_position(scene)?,
    };
    scene.recenter(world);
    Some(world)
}

/// A camera position (local frame) at the XY centre of the scene's bounds, [`EYE_HEIGHT`]
/// above the ground there; `None` for an empty scene.
///
/// The ground is estimated in a disk around the centre whose radius doubles (from 1/64 of the
/// scene's XY extent) until it covers at least 24 non-empty cells of a grid of radius/4: each
/// cell's ground is the 10th percentile of its heights (sparse noise below the ground and
/// objects on it do not move it), and the scene's ground is the median over cells (a pole or a
/// tree trunk at the centre fills one cell; a centre over a hole grows the disk until it
/// reaches the ground around the hole; on a slope the median is the height at the centre).
pub fn auto_camera_position(scene: &Scene) -> Option<DVec3> {
    let (lo, hi) = scene.bounds()?;
    let centre = (lo.truncate() + hi.truncate()) * 0.5;
    let extent = (hi.truncate() - lo.truncate()).max_element();
    ground_camera_position(scene, centre, extent)
}

/// [`auto_camera_position`] at a given XY `centre` (local frame) of a cloud `extent` metres
/// wide: for a scene that is a sample of a larger cloud, whose own bounds may miss the
/// cloud's edges (the centre and extent then come from the file's header). `None` when no
/// point of the scene lies within `extent` of the centre.
pub fn ground_camera_position(scene: &Scene, centre: Vec2, extent: f32) -> Option<DVec3> {
    let ground = ground_height(scene, centre, extent)?;
    Some(DVec3::new(
        f64::from(centre.x),
        f64::from(centre.y),
        ground + EYE_HEIGHT,
    ))
}

/// The ground's height (local frame) under the XY point `centre` of a cloud `extent` metres
/// wide, estimated as [`auto_camera_position`] describes; `None` when no point lies within
/// `extent` of it.
pub fn ground_height(scene: &Scene, centre: Vec2, extent: f32) -> Option<f64> {
    let mut radius = if extent > 0.0 { extent / 64.0 } else { 1.0 };
    let mut cells: HashMap<(i32, i32), Vec<f32>> = HashMap::new();
    loop {
        cells.clear();
        let cell = radius / CELLS_PER_RADIUS;
        for p in &scene.positions {
            let d = p.truncate() - centre;
            if d.length_squared() <= radius * radius {
                let key = ((d.x / cell).floor() as i32, (d.y / cell).floor() as i32);
                cells.entry(key).or_default().push(p.z);
            }
        }
        if cells.len() >= MIN_CELLS || radius >= extent {
            break;
        }
        radius *= 2.0;
    }
    let mut grounds: Vec<f32> = cells
        .into_values()
        .map(|mut z| {
            let rank = ((z.len() - 1) as f32 * CELL_PERCENTILE) as usize;
            *z.select_nth_unstable_by(rank, f32::total_cmp).1
        })
        .collect();
    if grounds.is_empty() {
        return None;
    }
    let mid = (grounds.len() - 1) / 2;
    let ground = *grounds.select_nth_unstable_by(mid, f32::total_cmp).1;
    Some(f64::from(ground))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A deterministic pseudo-random sequence in [0, 1).
    fn lcg(seed: &mut u64) -> f32 {
        let mut rng = crate::rng::SplitMix64::new(*seed);
        let x = rng.next_f64() as f32;
        *seed = rng.state();
        x
    }

    /// A 20 m x 20 m ground grid at `z`, centred on (10, 10), with `hole` metres of radius left
    /// empty around the centre.
    fn ground(z: f32, hole: f32) -> Vec<Vec3> {
        let mut pts = Vec::new();
        for i in 0..=100 {
            for j in 0..=100 {
                let p = Vec3::new(i as f32 * 0.2, j as f32 * 0.2, z);
                if p.truncate().distance(Vec2::splat(10.0)) >= hole {
                    pts.push(p);
                }
            }
        }
        pts
    }

    #[test]
    fn empty_scene_has_no_position() {
        let scene = Scene::new(DVec3::ZERO, vec![], 0.1);
        assert_eq!(auto_camera_position(&scene), None);
    }

    #[test]
    fn flat_ground_gives_eye_height() {
        let scene = Scene::new(DVec3::ZERO, ground(3.0, 0.0), 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p - DVec3::new(10.0, 10.0, 4.7)).length() < 1e-5, "{p}");
    }

    #[test]
    fn noise_below_ground_is_ignored() {
        let mut seed = 7;
        let mut pts = ground(0.0, 0.0);
        // 3 % of the points scattered up to 5 m below the ground.
        for _ in 0..pts.len() * 3 / 100 {
            let x = lcg(&mut seed) * 20.0;
            let y = lcg(&mut seed) * 20.0;
            pts.push(Vec3::new(x, y, -5.0 * lcg(&mut seed)));
        }
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 1.7).abs() < 0.05, "{p}");
    }

    #[test]
    fn objects_on_the_ground_do_not_lift_the_camera() {
        let mut pts = ground(1.0, 0.0);
        // A 10 m pole of points standing right at the centre.
        for i in 0..2000 {
            pts.push(Vec3::new(10.0, 10.0, 1.0 + i as f32 * 0.005));
        }
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 2.7).abs() < 1e-5, "{p}");
    }

    #[test]
    fn centre_over_a_hole_finds_surrounding_ground() {
        let scene = Scene::new(DVec3::ZERO, ground(-2.0, 4.0), 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p - DVec3::new(10.0, 10.0, -0.3)).length() < 1e-5, "{p}");
    }

    #[test]
    fn sloped_ground_uses_local_height_not_global_minimum() {
        // Ground rising 0.5 m per metre along x: global minimum 0, height at the centre 5.
        let pts: Vec<Vec3> = ground(0.0, 0.0)
            .into_iter()
            .map(|p| Vec3::new(p.x, p.y, 0.5 * p.x))
            .collect();
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 6.7).abs() < 0.5, "{p}");
    }
}
