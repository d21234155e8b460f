//! The default camera (`--camera auto`) on the bundled sample stands in open space: no point
//! within the clearance of the eye, ground below, at the sparse-data eye height.

use indicatif::ProgressBar;
use omnicloud::prepare::placement::{EYE_HEIGHT, clearance, default_eye_height};
use omnicloud::prepare::radius::median_spacing;
use omnicloud::prepare::{CameraChoice, PrepareOptions, prepare};

const AUTZEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");

#[test]
fn default_camera_on_the_sample_has_open_space_around_the_eye() {
    let prepared = prepare(
        AUTZEN.as_ref(),
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap();
    let scene = &prepared.scene;
    let spacing = median_spacing(scene).unwrap();
    let height = default_eye_height(Some(spacing), EYE_HEIGHT);
    // The scene is centred on the camera: distances to the eye are the points' lengths.
    let nearest = scene
        .positions
        .iter()
        .map(|p| p.length())
        .fold(f32::INFINITY, f32::min);
    // Ground below: points right under the eye, `height` down.
    let below: Vec<f32> = scene
        .positions
        .iter()
        .filter(|p| p.truncate().length() < 2.0 * spacing)
        .map(|p| -p.z)
        .collect();
    let (lo, hi) = scene.bounds().unwrap();
    let centre = (lo.truncate() + hi.truncate()) * 0.5;
    println!(
        "autzen auto camera: spacing {spacing:.3} m, eye {height:.2} m up, nearest point \
         {nearest:.2} m, {} m from the centre, ground {:?} m below",
        centre.length(),
        below
    );
    // Measured: spacing 1.336 m, eye 26.7 m above the ground.
    assert!((26.4..27.0).contains(&height), "{height}");
    assert!(
        f64::from(nearest) > clearance(height),
        "nearest point {nearest} m"
    );
    assert!(!below.is_empty(), "no ground below the eye");
    assert!(
        below.iter().any(|d| (f64::from(*d) - height).abs() < 1.0),
        "no point {height} m below: {below:?}"
    );
    // `center` keeps the old rule: the XY centre of the bounds, 1.7 m above the ground.
    let center = prepare(
        AUTZEN.as_ref(),
        &PrepareOptions {
            camera: CameraChoice::Center,
            ..PrepareOptions::default()
        },
        &ProgressBar::hidden(),
    )
    .unwrap();
    let (lo, hi) = center.scene.bounds().unwrap();
    let middle = ((lo + hi) * 0.5).truncate();
    assert!(middle.length() < 1e-3, "{middle}");
}

#[test]
fn a_given_height_stands_that_far_above_the_ground() {
    let low = prepare(
        AUTZEN.as_ref(),
        &PrepareOptions {
            height: omnicloud::prepare::EyeHeight::new(Some(1.7), 1.0),
            ..PrepareOptions::default()
        },
        &ProgressBar::hidden(),
    )
    .unwrap();
    let nearest = low
        .scene
        .positions
        .iter()
        .map(|p| p.length())
        .fold(f32::INFINITY, f32::min);
    assert!(f64::from(nearest) > clearance(1.7), "{nearest}");
    let under: Vec<f32> = low
        .scene
        .positions
        .iter()
        .filter(|p| p.truncate().length() < 2.7)
        .map(|p| -p.z)
        .collect();
    assert!(under.iter().any(|d| (d - 1.7).abs() < 0.5), "{under:?}");
}
