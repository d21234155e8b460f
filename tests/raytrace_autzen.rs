//! The real sample (Autzen stadium, 110,000 points) rendered from 1.7 m above the ground
//! near its centre: coverage and depth must be those of standing on a scanned field.

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::projection::Camera;
use omnicloud::radius::{auto_radius, median_spacing};
use omnicloud::raytrace::render;
use omnicloud::render::{ColorMode, RenderSettings};
use omnicloud::{Rendered, Scene};

const AUTZEN: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/data/las/autzen_trim.laz"
);

/// Minimal local reader (the crate's loader is written elsewhere): f64 points minus the
/// bounds centre, stored f32; 8-bit colour held in the 16-bit fields.
fn load_autzen() -> Scene {
    let mut reader = las::Reader::from_path(AUTZEN).expect("autzen_trim.laz");
    let b = reader.header().bounds();
    let origin = DVec3::new(
        0.5 * (b.min.x + b.max.x),
        0.5 * (b.min.y + b.max.y),
        0.5 * (b.min.z + b.max.z),
    );
    let data = reader.read_all().expect("read points");
    let mut positions = Vec::new();
    let mut rgb = Vec::new();
    for p in data.points() {
        let p = p.expect("decode point");
        positions.push((DVec3::new(p.x, p.y, p.z) - origin).as_vec3());
        let c = p.color.expect("autzen has colour");
        rgb.push([c.red as u8, c.green as u8, c.blue as u8]);
    }
    let mut scene = Scene::new(origin, positions, 0.0);
    scene.attributes.rgb = Some(rgb);
    scene
}

#[test]
fn autzen_from_standing_height_near_the_centre() {
    let mut scene = load_autzen();
    assert_eq!(scene.len(), 110_000);
    let spacing = median_spacing(&scene).unwrap();
    let radius = auto_radius(&scene);
    scene.radii = omnicloud::Radii::Uniform(radius);
    // Open flat ground near the centre: the nearest candidate (10 m grid) with points around
    // it and none higher than 0.5 m above its ground (a low percentile of z within 5 m).
    let mut candidates: Vec<(f32, f32)> = (-8..=8)
        .flat_map(|i| (-8..=8).map(move |j| (i as f32 * 10.0, j as f32 * 10.0)))
        .collect();
    candidates.sort_by(|a, b| (a.0.hypot(a.1)).total_cmp(&b.0.hypot(b.1)));
    let (cx, cy, ground) = candidates
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
        .expect("open ground near the centre");
    let camera = Camera::new(DVec3::new(cx as f64, cy as f64, ground as f64 + 1.7), 0.0);
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
    let mut depths: Vec<f32> = f.depth.iter().copied().filter(|d| d.is_finite()).collect();
    depths.sort_by(f32::total_cmp);
    let (dmin, dmed, dmax) = (
        depths[0],
        depths[depths.len() / 2],
        depths[depths.len() - 1],
    );
    println!(
        "autzen: spacing {spacing:.3} m, radius {radius:.3} m, camera at ({cx}, {cy}), ground {ground:.2} m, \
         coverage {coverage:.3} (lower half {lower:.3}, upper half {upper:.3}), \
         depth min {dmin:.2} median {dmed:.2} max {dmax:.1} m"
    );
    assert!((0.3..2.0).contains(&spacing), "spacing {spacing}");
    assert!(f.depth.iter().all(|d| !d.is_nan()));
    // Standing on the ground: most of the lower hemisphere is scanned ground, little sky.
    assert!(lower > 0.6, "lower-half coverage {lower}");
    assert!(upper < 0.5, "upper-half coverage {upper}");
    assert!((0.3..0.8).contains(&coverage), "coverage {coverage}");
    // Nearest ground is about the eye height away; the farthest within the tile (~1 km).
    assert!(dmin > 0.5 && dmin < 1.75, "min depth {dmin}");
    assert!(dmax > 100.0 && dmax < 2000.0, "max depth {dmax}");
    // Colours come from the file (not the flat grey).
    assert!(
        f.color
            .iter()
            .any(|c| c[3] != 0 && c[..3] != [200, 200, 200])
    );
}
