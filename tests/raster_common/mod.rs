//! Shared helpers of the rasterizer tests: adapter acquisition, a brute-force f64 reference
//! renderer, stress scenes and comparison metrics.
#![allow(dead_code)]

use glam::{DVec3, Vec3};
use omnicloud::projection::View;
use omnicloud::raster::{RasterError, Rasterizer};
use omnicloud::render::RenderSettings;
use omnicloud::{Attributes, Frame, Radii, Scene};
use rayon::prelude::*;

/// The rasterizer, or `None` (with a loud message) when no adapter exists outside CI.
/// In CI (`CI` set) a missing adapter fails the test.
pub fn rasterizer() -> Option<Rasterizer> {
    match Rasterizer::new() {
        Ok(r) => Some(r),
        Err(RasterError::NoAdapter) if std::env::var_os("CI").is_none() => {
            eprintln!(
                "\n!!!!!!!! SKIPPED: no GPU adapter (install mesa-vulkan-drivers); set CI=1 to make this fail !!!!!!!!\n"
            );
            None
        }
        Err(e) => panic!("rasterizer unavailable: {e}"),
    }
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

/// Brute-force reference: every pixel's `View::pixel_ray` against every sphere.
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
                let (o, d) = view.pixel_ray(&img, i, j);
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

/// Coverage, depth and colour agreement of a frame with the reference.
#[derive(Debug)]
pub struct Agreement {
    pub pixels: usize,
    pub coverage_diff: usize,
    pub both: usize,
    pub depth_rel_p99: f64,
    pub depth_rel_max: f64,
    /// Colour mismatches where the reference's nearest hit is unambiguous (second sphere
    /// more than 1e-4 relative behind).
    pub color_diff: usize,
    /// Coverage differences per region: pole caps (|phi| > 60°), seam strip (|lam| > 170°).
    pub pole_coverage_diff: usize,
    pub pole_pixels: usize,
    pub seam_coverage_diff: usize,
    pub seam_pixels: usize,
}

impl Agreement {
    pub fn coverage_fraction(&self) -> f64 {
        self.coverage_diff as f64 / self.pixels as f64
    }
    pub fn pole_fraction(&self) -> f64 {
        self.pole_coverage_diff as f64 / self.pole_pixels.max(1) as f64
    }
    pub fn seam_fraction(&self) -> f64 {
        self.seam_coverage_diff as f64 / self.seam_pixels.max(1) as f64
    }
}

/// Compares a rendered frame with the reference and the scene's colours.
pub fn compare(
    frame: &Frame,
    reference: &[Option<RefPixel>],
    colors: &[[u8; 3]],
    settings: &RenderSettings,
) -> Agreement {
    let img = settings.image;
    let mut a = Agreement {
        pixels: reference.len(),
        coverage_diff: 0,
        both: 0,
        depth_rel_p99: 0.0,
        depth_rel_max: 0.0,
        color_diff: 0,
        pole_coverage_diff: 0,
        pole_pixels: 0,
        seam_coverage_diff: 0,
        seam_pixels: 0,
    };
    let mut rel = Vec::new();
    for j in 0..img.height {
        for i in 0..img.width {
            let k = frame.index(i, j);
            let (lam, phi) = img.pixel_angles(i, j);
            let pole = phi.abs() > 60f64.to_radians();
            let seam = lam.abs() > 170f64.to_radians();
            a.pole_pixels += pole as usize;
            a.seam_pixels += seam as usize;
            let hit = frame.color[k][3] != 0;
            match (reference[k], hit) {
                (Some(r), true) => {
                    a.both += 1;
                    rel.push((frame.depth[k] as f64 - r.t).abs() / r.t);
                    let c = colors[r.sphere];
                    let got = [frame.color[k][0], frame.color[k][1], frame.color[k][2]];
                    if got != c && r.second_t > r.t * (1.0 + 1e-4) {
                        a.color_diff += 1;
                    }
                }
                (None, false) => {}
                _ => {
                    a.coverage_diff += 1;
                    a.pole_coverage_diff += pole as usize;
                    a.seam_coverage_diff += seam as usize;
                }
            }
        }
    }
    rel.sort_by(f64::total_cmp);
    if !rel.is_empty() {
        a.depth_rel_p99 = rel[((rel.len() - 1) as f64 * 0.99) as usize];
        a.depth_rel_max = *rel.last().unwrap();
    }
    a
}

/// Deterministic xorshift generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
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
    let mut rng = Rng::new(12345);
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
            intensity: None,
            classification: None,
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
            intensity: None,
            classification: None,
        },
    }
}
