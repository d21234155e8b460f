//! The real sample (Autzen stadium, 110,000 points) rendered from 1.7 m above the ground
//! near its centre: coverage and depth must be those of standing on a scanned field.

use indicatif::ProgressBar;
use omnicloud::prepare::radius::{auto_radius, median_spacing};
use omnicloud::projection::Camera;
use omnicloud::raytrace::render;
use omnicloud::render::{ColorMode, RenderSettings};
use omnicloud::stats::percentile;
use omnicloud::{Rendered, Scene};

const AUTZEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");

fn load_autzen() -> Scene {
    let (scene, _) = omnicloud::io::load_scene(AUTZEN.as_ref(), &Default::default())
        .expect("the bundled sample loads");
    scene
}

#[test]
fn autzen_from_standing_height_near_the_centre() {
    let mut scene = load_autzen();
    assert_eq!(scene.len(), 110_000);
    let spacing = median_spacing(&scene).unwrap();
    let radius = auto_radius(&scene);
    scene.radii = omnicloud::Radii::Uniform(radius);
    // Open flat ground near the centre: at the exact centre the eye stands in a tree canopy.
    let eye = omnicloud::prepare::placement::open_ground_camera_position(&scene);
    let camera = Camera::new(eye, 0.0);
    let mut settings = RenderSettings::new(1024, camera);
    settings.color = ColorMode::Rgb;
    let Rendered::Mono(f) = render(&scene, &settings, &ProgressBar::hidden()).unwrap() else {
        panic!("mono expected")
    };
    let n = f.color.len() as f64;
    let coverage = f.coverage_count() as f64 / n;
    let h = f.height as usize;
    let w = f.width as usize;
    let lower = f.color[w * h / 2..].iter().filter(|c| c[3] != 0).count() as f64 / (n / 2.0);
    let upper = f.color[..w * h / 2].iter().filter(|c| c[3] != 0).count() as f64 / (n / 2.0);
    let mut depths: Vec<f64> = f
        .depth
        .iter()
        .filter(|d| d.is_finite())
        .map(|&d| d as f64)
        .collect();
    depths.sort_by(f64::total_cmp);
    let at = |p| percentile(&depths, p).expect("something is hit");
    let (dmin, dmed, dmax) = (at(0.0), at(0.5), at(1.0));
    println!(
        "autzen: spacing {spacing:.3} m, radius {radius:.3} m, camera at ({:.1}, {:.1}, {:.2}), \
         coverage {coverage:.3} (lower half {lower:.3}, upper half {upper:.3}), \
         depth min {dmin:.2} median {dmed:.2} max {dmax:.1} m",
        eye.x, eye.y, eye.z
    );
    // Measured: spacing 1.336 m, coverage 0.410 (lower half 0.718, upper 0.103), depth
    // 1.04 to 626.9 m; the bounds sit a few per cent around these.
    assert!((1.30..1.37).contains(&spacing), "spacing {spacing}");
    assert!(f.depth.iter().all(|d| !d.is_nan()));
    // Standing on the ground: most of the lower hemisphere is scanned ground, little sky.
    assert!(lower > 0.70, "lower-half coverage {lower}");
    assert!(upper < 0.11, "upper-half coverage {upper}");
    assert!((0.40..0.42).contains(&coverage), "coverage {coverage}");
    // Nearest ground is the eye height less a radius away; the farthest within the tile.
    assert!((1.0..1.1).contains(&dmin), "min depth {dmin}");
    assert!((600.0..650.0).contains(&dmax), "max depth {dmax}");
    // Colours come from the file (not the flat grey).
    assert!(
        f.color
            .iter()
            .any(|c| c[3] != 0 && c[..3] != [200, 200, 200])
    );
}
