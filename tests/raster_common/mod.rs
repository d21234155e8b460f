//! Shared helpers of the rasterizer tests: adapter acquisition, a brute-force f64 reference
//! renderer, stress scenes, and `compare`'s metrics against the reference.
#![allow(dead_code)]

pub mod gpu;

use glam::{DVec3, Vec3};
use omnicloud::compare::{RegionStats, Regions, compare_eyes};
use omnicloud::io::{LoadOptions, load_scene};
use omnicloud::prepare::{placement, radius};
use omnicloud::projection::{Image, View};
use omnicloud::render::RenderSettings;
use omnicloud::rng::SplitMix64;
use omnicloud::{Attributes, Frame, Radii, Scene};
use rayon::prelude::*;

pub use gpu::rasterizer;

/// The bundled Autzen sample, centred on a camera at the centre of its bounds (above the
/// ground there), every sphere of the automatic radius.
pub fn autzen_at_centre() -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");
    let (mut scene, _) = load_scene(path.as_ref(), &LoadOptions::default()).expect("sample loads");
    placement::center_on_camera(
        &mut scene,
        placement::CameraChoice::Center,
        Default::default(),
    )
    .expect("camera placed");
    scene.radii = Radii::Uniform(radius::auto_radius(&scene));
    scene
}

/// Pixels whose colour or depth bits differ between two frames of one size.
pub fn differing_pixels(a: &Frame, b: &Frame) -> usize {
    (0..a.color.len())
        .filter(|&k| a.color[k] != b.color[k] || a.depth[k].to_bits() != b.depth[k].to_bits())
        .count()
}

/// Reference pixel: nearest hit, its sphere, and the second-nearest distinct sphere's t.
#[derive(Clone, Copy)]
pub struct RefPixel {
    pub t: f64,
    pub sphere: usize,
    pub second_t: f64,
}

/// Nearest t > 0 of the ray (o, d) with sphere (c, r), stable quadratic, f64.
pub fn intersect(o: DVec3, d: DVec3, c: DVec3, r: f64) -> Option<f64> {
    let oc = o - c;
    let b = oc.dot(d);
    let perp = oc - b * d;
    let disc = r * r - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let h = disc.sqrt();
    let cc = oc.length_squared() - r * r;
    let q = if b > 0.0 { -b - h } else { -b + h };
    let (t0, t1) = if q == 0.0 { (-h, h) } else { (cc / q, q) };
    let (near, far) = (t0.min(t1), t0.max(t1));
    if near > 0.0 {
        Some(near)
    } else if far > 0.0 {
        Some(far)
    } else {
        None
    }
}

/// Brute-force reference: every pixel's `View::image_ray` against every sphere.
pub fn reference(scene: &Scene, settings: &RenderSettings, view: &View) -> Vec<Option<RefPixel>> {
    let img = settings.image;
    let spheres: Vec<(DVec3, f64)> = (0..scene.len())
        .map(|i| (scene.positions[i].as_dvec3(), scene.radii.get(i) as f64))
        .collect();
    (0..img.height)
        .into_par_iter()
        .flat_map_iter(|j| {
            let spheres = &spheres;
            (0..img.width).map(move |i| {
                let (o, d) = view.image_ray(&img, i, j)?;
                let mut best: Option<RefPixel> = None;
                for (k, &(c, r)) in spheres.iter().enumerate() {
                    if let Some(t) = intersect(o, d, c, r) {
                        best = Some(match best {
                            None => RefPixel {
                                t,
                                sphere: k,
                                second_t: f64::INFINITY,
                            },
                            Some(b) if t < b.t => RefPixel {
                                t,
                                sphere: k,
                                second_t: b.t,
                            },
                            Some(b) => RefPixel {
                                second_t: b.second_t.min(t),
                                ..b
                            },
                        });
                    }
                }
                best
            })
        })
        .collect()
}

/// The reference as a frame: each pixel's nearest sphere, its colour and distance.
pub fn reference_frame(reference: &[Option<RefPixel>], colors: &[[u8; 3]], img: Image) -> Frame {
    let mut f = Frame::new(img.width, img.height);
    for (k, r) in reference.iter().enumerate() {
        if let Some(r) = r {
            let [red, green, blue] = colors[r.sphere];
            f.color[k] = [red, green, blue, 255];
            f.depth[k] = r.t as f32;
        }
    }
    f
}

/// A frame against the reference: `compare`'s statistics, plus the one figure they lack.
#[derive(Debug)]
pub struct Agreement {
    /// `compare`'s statistics of the frame against [`reference_frame`].
    pub regions: Regions,
    /// Colour mismatches where the reference's nearest hit is unambiguous (the second sphere
    /// more than 1e-4 relative behind); `compare` also counts near-ties, where either colour
    /// is right.
    pub color_diff: u64,
}

/// Bands of [`Regions::latitude_bands`] at each pole counted as its cap (|latitude| > 60°).
const POLE_BANDS: usize = 3;

impl Agreement {
    /// The whole image.
    pub fn all(&self) -> &RegionStats {
        &self.regions.all
    }
    /// Coverage-mismatched fraction of all pixels.
    pub fn coverage_fraction(&self) -> f64 {
        self.all().mismatch as f64 / self.all().pixels as f64
    }
    /// Depth relative error p99 (nearest rank) where both hit.
    pub fn depth_rel_p99(&self) -> f64 {
        self.all().depth_relative.as_ref().map_or(0.0, |d| d.p99)
    }
    /// Coverage mismatches in the polar caps (|latitude| > 60°) and the caps' pixels.
    pub fn pole(&self) -> (u64, u64) {
        let bands = &self.regions.latitude_bands;
        let caps = bands[..POLE_BANDS]
            .iter()
            .chain(&bands[bands.len() - POLE_BANDS..]);
        caps.fold((0, 0), |(m, p), b| (m + b.mismatch, p + b.pixels))
    }
    /// Coverage-mismatched fraction of the polar caps.
    pub fn pole_fraction(&self) -> f64 {
        let (m, p) = self.pole();
        m as f64 / p.max(1) as f64
    }
    /// The seam columns (of a full equirect panorama).
    pub fn seam(&self) -> &RegionStats {
        self.regions
            .seam
            .as_ref()
            .expect("a full equirect panorama has a seam")
    }
    /// Coverage-mismatched fraction of the seam columns.
    pub fn seam_fraction(&self) -> f64 {
        let s = self.seam();
        s.mismatch as f64 / s.pixels.max(1) as f64
    }
}

/// Compares a rendered frame with the reference and the scene's colours.
pub fn compare(
    frame: &Frame,
    reference: &[Option<RefPixel>],
    colors: &[[u8; 3]],
    settings: &RenderSettings,
) -> Agreement {
    let expected = reference_frame(reference, colors, settings.image);
    let panorama = settings.image.projection.is_full_equirect();
    let regions =
        compare_eyes(&[(&expected, frame)], panorama).expect("frame and reference agree in size");
    let color_diff = reference
        .iter()
        .enumerate()
        .filter(|&(k, r)| {
            r.is_some_and(|r| {
                frame.color[k][3] != 0
                    && frame.color[k] != expected.color[k]
                    && r.second_t > r.t * (1.0 + 1e-4)
            })
        })
        .count() as u64;
    Agreement {
        regions,
        color_diff,
    }
}

fn dir(lam_deg: f64, phi_deg: f64) -> DVec3 {
    let (l, p) = (lam_deg.to_radians(), phi_deg.to_radians());
    // Camera yaw 0: forward +Y, right +X.
    DVec3::new(p.cos() * l.sin(), p.cos() * l.cos(), p.sin())
}

/// The stress scene around a camera at the origin looking along +Y: spheres covering each
/// pole, near the poles, straddling the seam, next to the eye, and a random field; each
/// sphere has its own colour. `random` is the size of the random field.
pub fn stress_scene(random: usize) -> Scene {
    let mut pts: Vec<(DVec3, f64)> = vec![
        // Covering the poles (the vertical axis passes through them).
        (DVec3::new(0.1, -0.05, 3.0), 0.5),
        (DVec3::new(-0.05, 0.1, -2.0), 0.4),
        // Near the poles without covering them.
        (3.0 * dir(20.0, 84.0), 0.2),
        (2.5 * dir(-130.0, -80.0), 0.25),
        (4.0 * dir(100.0, 75.0), 0.3),
        // Straddling the seam (behind the camera).
        (3.0 * dir(180.0, 5.0), 0.3),
        (6.0 * dir(178.5, -20.0), 0.25),
        (2.0 * dir(-179.0, 40.0), 0.15),
        // Next to the eye: within and just outside the viewing circle.
        (DVec3::new(0.02, 0.01, 0.3), 0.02),
        (DVec3::new(0.08, 0.05, -0.02), 0.05),
        (DVec3::new(-0.15, 0.1, 0.05), 0.1),
    ];
    let mut rng = SplitMix64::new(12345);
    for _ in 0..random {
        let lam = rng.range(-180.0, 180.0);
        let phi = (rng.range(-1.0, 1.0)).asin().to_degrees();
        let d = rng.range(1.0, 30.0);
        pts.push((d * dir(lam, phi), rng.range(0.02, 0.3)));
    }
    let mut colors = Vec::new();
    for k in 0..pts.len() {
        // Distinct colours: the index in base 200 over two channels plus a fixed blue.
        colors.push([(k % 200 + 20) as u8, (k / 200 * 20 + 10) as u8, 77]);
    }
    Scene {
        origin: DVec3::ZERO,
        positions: pts.iter().map(|p| p.0.as_vec3()).collect::<Vec<Vec3>>(),
        radii: Radii::PerPoint(pts.iter().map(|p| p.1 as f32).collect()),
        attributes: Attributes {
            rgb: Some(colors),
            ..Attributes::default()
        },
    }
}

/// A sphere enclosing the eye with a few spheres inside it.
pub fn enclosing_scene() -> Scene {
    let pts = [
        (DVec3::new(0.3, -0.2, 0.4), 8.0),
        (DVec3::new(0.0, 3.0, 0.0), 0.5),
        (DVec3::new(-2.0, -1.0, 1.0), 0.7),
        (DVec3::new(1.0, 1.0, 4.0), 0.6),
    ];
    Scene {
        origin: DVec3::ZERO,
        positions: pts.iter().map(|p| p.0.as_vec3()).collect(),
        radii: Radii::PerPoint(pts.iter().map(|p| p.1 as f32).collect()),
        attributes: Attributes {
            rgb: Some(vec![[10, 20, 30], [200, 0, 0], [0, 200, 0], [0, 0, 200]]),
            ..Attributes::default()
        },
    }
}
