//! A scene already in memory is prepared as a file is: the same camera, filters and radii
//! (the path the Python package takes), and points given in world coordinates are placed as
//! a reader places a file without header bounds.

use std::path::Path;

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::io::{LoadOptions, load_scene};
use omnicloud::prepare::filter::ClassSet;
use omnicloud::prepare::{
    FilterError, PointFilter, PrepareError, PrepareOptions, prepare, prepare_scene,
};

const SAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");

#[test]
fn a_loaded_scene_prepares_exactly_as_its_file() {
    let options = PrepareOptions {
        filter: PointFilter {
            classes: Some(ClassSet::of(&[2])),
            ..PointFilter::default()
        },
        ..PrepareOptions::default()
    };
    let path = Path::new(SAMPLE);
    let file = prepare(path, &options, &ProgressBar::hidden()).unwrap();
    let (scene, _) = load_scene(path, &LoadOptions::default()).unwrap();
    let memory = prepare_scene(scene, &options, path).unwrap();
    assert_eq!(memory.camera_world, file.camera_world);
    assert_eq!(memory.scene.origin, file.scene.origin);
    assert_eq!(memory.scene.positions, file.scene.positions);
    assert_eq!(memory.scene.radii, file.scene.radii);
    assert_eq!(memory.scene.attributes, file.scene.attributes);
    assert_eq!(memory.filtered, file.filtered);
    // The sample's ground (class 2) is 26,107 of its 110,000 points.
    assert_eq!(memory.scene.len(), 26_107);
}

#[test]
fn a_filter_the_scene_has_no_attribute_for_is_refused_by_name() {
    let scene = Scene::new(DVec3::ZERO, vec![Vec3::ZERO; 10], 0.1);
    let options = PrepareOptions {
        filter: PointFilter {
            classes: Some(ClassSet::of(&[2])),
            ..PointFilter::default()
        },
        ..PrepareOptions::default()
    };
    let err = prepare_scene(scene, &options, Path::new("<arrays>")).unwrap_err();
    assert!(
        matches!(
            err,
            PrepareError::Filter(FilterError::MissingAttribute { .. })
        ),
        "{err}"
    );
    assert!(err.to_string().contains("<arrays>"), "{err}");
}

#[test]
fn world_points_are_placed_around_the_centre_of_their_bounds() {
    let world = [
        DVec3::new(637_000.25, 851_000.5, 100.0),
        DVec3::new(637_010.25, 851_020.5, 104.0),
        DVec3::new(637_004.0, 851_001.0, 101.0),
    ];
    let scene = Scene::from_world(world.len(), |i| world[i], None, 0.02);
    assert_eq!(scene.origin, DVec3::new(637_005.25, 851_010.5, 102.0));
    assert_eq!(scene.positions[0], Vec3::new(-5.0, -10.0, -2.0));
    for (p, w) in scene.positions.iter().zip(world) {
        assert!((scene.origin + p.as_dvec3() - w).abs().max_element() < 1e-9);
    }
    let given = Scene::from_world(world.len(), |i| world[i], Some(world[0]), 0.02);
    assert_eq!(given.origin, world[0]);
    assert_eq!(given.positions[1], Vec3::new(10.0, 20.0, 4.0));
}
