//! The stability suite's scenes: spheres placed where projection-based renderers fail.
//!
//! Every generator is deterministic (a fixed SplitMix64 seed) and rounds coordinates and radii
//! to 0.1 mm, so the files written from them are byte-identical from run to run.

use std::f64::consts::PI;

use glam::DVec3;

use crate::projection::{Camera, Stereo, equirect};
use crate::scene::{Attributes, Radii, Scene};

use crate::rng::SplitMix64;

/// One sphere of a suite scene, in file (world) coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SuitePoint {
    /// Centre, metres, file coordinates.
    pub position: DVec3,
    /// 8-bit sRGB colour.
    pub rgb: [u8; 3],
    /// Sphere radius, metres.
    pub radius: f32,
}

/// Mono or ODS, as a manifest entry names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SuiteStereo {
    /// One central panorama.
    Mono,
    /// An omnidirectional-stereo pair.
    Ods,
}

/// One way to view a suite scene (a scene file may be viewed several ways).
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteView {
    /// Unique name of this view (the manifest entry's name).
    pub name: String,
    /// What the view exercises.
    pub description: String,
    /// Mono or ODS.
    pub stereo: SuiteStereo,
    /// Interocular distance, metres (ignored for mono).
    pub ipd: f64,
    /// North pole merge, in the CLI's syntax (`off`, `comfortable`, `cycles:60,75`, ...).
    pub pole_merge_north: String,
    /// South pole merge, in the CLI's syntax.
    pub pole_merge_south: String,
    /// Image width per eye.
    pub width: u32,
    /// What fails here: `pole`, `seam`, `near`, `enclosing`, `culled`, `utm`, `dense`, `huge`.
    pub tags: Vec<String>,
}

/// A generated scene: spheres, a camera, and the views the suite renders it with.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteScene {
    /// File stem of the scene (`NAME.ply`).
    pub name: String,
    /// Spheres in file coordinates.
    pub points: Vec<SuitePoint>,
    /// Camera centre, file coordinates.
    pub camera: DVec3,
    /// Camera heading, degrees.
    pub yaw_deg: f64,
    /// The views rendered from this scene.
    pub views: Vec<SuiteView>,
}

impl SuiteScene {
    /// The scene as renderers take it: local frame centred on the camera (DESIGN §1), per-point
    /// radii and colours. The camera is then at the local origin.
    pub fn to_scene(&self) -> Scene {
        let origin = self.camera;
        Scene {
            origin,
            positions: self
                .points
                .iter()
                .map(|p| (p.position - origin).as_vec3())
                .collect(),
            radii: Radii::PerPoint(self.points.iter().map(|p| p.radius).collect()),
            attributes: Attributes {
                rgb: Some(self.points.iter().map(|p| p.rgb).collect()),
                ..Attributes::default()
            },
        }
    }
}

/// Default width of a suite view: small enough for CI on a software rasterizer.
pub const SUITE_WIDTH: u32 = 512;

/// Every suite scene, in manifest order.
pub fn all_scenes() -> Vec<SuiteScene> {
    vec![
        poles(),
        seam(),
        near_eye(),
        enclosing(),
        inside_circle(),
        utm(),
        dense_cluster(),
        huge_sphere(),
        high_latitude(),
    ]
}

/// Rounds to 0.1 mm so the bytes do not depend on the last bit of `sin`/`cos`.
fn quantize(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

fn quantize_radius(r: f64) -> f32 {
    quantize(r) as f32
}

/// A random 8-bit colour, each channel in [40, 255] so no sphere is near-black.
fn random_color(rng: &mut SplitMix64) -> [u8; 3] {
    let mut c = || 40 + (rng.next_u64() % 216) as u8;
    [c(), c(), c()]
}

/// Places spheres by direction and distance from a camera.
struct Placer {
    camera: Camera,
    rng: SplitMix64,
    points: Vec<SuitePoint>,
}

impl Placer {
    fn new(center: DVec3, yaw_deg: f64, seed: u64) -> Self {
        Placer {
            camera: Camera::new(center, yaw_deg),
            rng: SplitMix64::new(seed),
            points: Vec::new(),
        }
    }

    /// A sphere at longitude/latitude (degrees, camera frame) and distance from the camera.
    fn at_angles(&mut self, lam_deg: f64, phi_deg: f64, dist: f64, radius: f64) {
        let d = equirect::direction(
            &self.camera.basis(),
            lam_deg.to_radians(),
            phi_deg.to_radians(),
        );
        self.at_offset(d * dist, radius);
    }

    /// A sphere at `offset` from the camera centre (world axes).
    fn at_offset(&mut self, offset: DVec3, radius: f64) {
        let p = self.camera.center + offset;
        let rgb = random_color(&mut self.rng);
        self.points.push(SuitePoint {
            position: DVec3::new(quantize(p.x), quantize(p.y), quantize(p.z)),
            rgb,
            radius: quantize_radius(radius),
        });
    }

    /// A ring of context spheres around the horizon, so no image is nearly empty.
    fn horizon_ring(&mut self, count: usize, dist: f64, radius: f64) {
        for k in 0..count {
            let lam = -180.0 + (k as f64 + 0.5) * 360.0 / count as f64;
            self.at_angles(lam, 0.0, dist, radius);
        }
    }

    fn finish(self, name: &str, views: Vec<SuiteView>) -> SuiteScene {
        SuiteScene {
            name: name.to_string(),
            points: self.points,
            camera: self.camera.center,
            yaw_deg: self.camera.yaw_deg,
            views,
        }
    }
}

fn view(
    name: &str,
    description: &str,
    stereo: SuiteStereo,
    merge: (&str, &str),
    tags: &[&str],
) -> SuiteView {
    SuiteView {
        name: name.to_string(),
        description: description.to_string(),
        stereo,
        ipd: Stereo::DEFAULT_IPD,
        pole_merge_north: merge.0.to_string(),
        pole_merge_south: merge.1.to_string(),
        width: SUITE_WIDTH,
        tags: tags.iter().map(|t| t.to_string()).collect(),
    }
}

/// A sphere straight above and one straight below the camera, and two off-axis spheres whose
/// silhouettes still contain a pole: the proxies must become bands reaching the pole.
pub fn poles() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(0.0, 0.0, 1.7), 0.0, 0x5011);
    p.at_offset(DVec3::new(0.0, 0.0, 3.0), 1.0);
    p.at_offset(DVec3::new(0.0, 0.0, -1.6), 0.5);
    // Angular radius asin(1/6) = 9.6° > 6° from the pole: contains the north pole.
    p.at_angles(40.0, 84.0, 6.0, 1.0);
    // asin(0.5/4) = 7.2° > 4°: contains the south pole.
    p.at_angles(-120.0, -86.0, 4.0, 0.5);
    p.horizon_ring(24, 5.0, 0.2);
    p.finish(
        "poles",
        vec![
            view(
                "poles",
                "spheres covering the north and south poles (one on the axis, one off it, per pole)",
                SuiteStereo::Mono,
                ("off", "off"),
                &["pole"],
            ),
            view(
                "poles_ods",
                "the pole spheres in ODS, comfortable merge north, Cycles merge south",
                SuiteStereo::Ods,
                ("comfortable", "cycles"),
                &["pole"],
            ),
        ],
    )
}

/// Spheres centred just either side of the seam (behind the camera) at several latitudes and
/// sizes, with a yawed camera so the seam is not along a world axis.
pub fn seam() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(2.0, -3.0, 1.5), 30.0, 0x5EA4);
    let latitudes = [-60.0, -30.0, 0.0, 30.0, 60.0];
    let radii = [0.05, 0.2, 0.6];
    for (a, &phi) in latitudes.iter().enumerate() {
        for (b, &r) in radii.iter().enumerate() {
            // Alternate sides of the seam, a fraction of a degree to a few degrees off it.
            let side = if (a + b) % 2 == 0 { 1.0 } else { -1.0 };
            let off = 0.3 * (b as f64 + 1.0);
            let lam = side * (180.0 - off);
            let dist = 5.0 + 1.5 * b as f64;
            p.at_angles(lam, phi, dist, r);
        }
    }
    p.horizon_ring(18, 6.0, 0.15);
    p.finish(
        "seam",
        vec![
            view(
                "seam",
                "spheres straddling the seam behind the camera at latitudes -60..60, radii 5-60 cm",
                SuiteStereo::Mono,
                ("off", "off"),
                &["seam"],
            ),
            view(
                "seam_ods",
                "the seam spheres in ODS with comfortable merging",
                SuiteStereo::Ods,
                ("comfortable", "comfortable"),
                &["seam"],
            ),
        ],
    )
}

/// Small spheres 10-40 cm from the eye in every direction: large angular size, strong ODS
/// parallax, but every ray origin stays outside every sphere.
pub fn near_eye() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(0.0, 0.0, 1.6), 0.0, 0x0EE1);
    for _ in 0..40 {
        let lam = p.rng.range(-180.0, 180.0);
        let phi = p.rng.range(-70.0, 70.0);
        let dist = p.rng.range(0.12, 0.4);
        let radius = p.rng.range(0.01, 0.05);
        p.at_angles(lam, phi, dist, radius);
    }
    p.horizon_ring(24, 4.0, 0.15);
    p.finish(
        "near_eye",
        vec![view(
            "near_eye",
            "40 spheres 12-40 cm from the eye (radius 1-5 cm), ODS without merging",
            SuiteStereo::Ods,
            ("off", "off"),
            &["near"],
        )],
    )
}

/// One large sphere that encloses the camera, with small spheres inside it.
pub fn enclosing() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(10.0, 20.0, 1.6), -45.0, 0xE4C1);
    p.at_offset(DVec3::new(1.0, 0.5, 0.3), 8.0);
    p.horizon_ring(12, 3.0, 0.2);
    for _ in 0..12 {
        let lam = p.rng.range(-180.0, 180.0);
        let phi = p.rng.range(-60.0, 60.0);
        p.at_angles(lam, phi, 2.0, 0.15);
    }
    p.finish(
        "enclosing",
        vec![
            view(
                "enclosing",
                "a sphere of radius 8 m enclosing the camera (seen from inside), small spheres within",
                SuiteStereo::Mono,
                ("off", "off"),
                &["enclosing"],
            ),
            view(
                "enclosing_ods",
                "the enclosing sphere in ODS, comfortable merge",
                SuiteStereo::Ods,
                ("comfortable", "comfortable"),
                &["enclosing"],
            ),
        ],
    )
}

/// Spheres wholly inside the ODS viewing cylinder (no ODS ray reaches them without merging),
/// among ordinary spheres: they must be culled, not drawn as garbage.
pub fn inside_circle() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(-5.0, 7.0, 1.6), 10.0, 0x1C1C);
    for _ in 0..40 {
        // rho + radius <= 0.02 + 0.006 < ipd/2 = 0.032.
        let a = p.rng.range(0.0, 2.0 * PI);
        let rho = p.rng.range(0.0, 0.02);
        let z = p.rng.range(0.3, 3.0) * if p.rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
        p.at_offset(DVec3::new(rho * a.cos(), rho * a.sin(), z), 0.006);
    }
    p.horizon_ring(24, 3.0, 0.2);
    p.finish(
        "inside_circle",
        vec![view(
            "inside_circle",
            "40 spheres inside the viewing cylinder (rho + radius < ipd/2) above and below the eye",
            SuiteStereo::Ods,
            ("off", "off"),
            &["culled"],
        )],
    )
}

/// A street-like scene at UTM coordinates (1e6 m offsets), camera in the same coordinates.
pub fn utm() -> SuiteScene {
    let center = DVec3::new(637_012.5, 851_020.25, 112.0);
    let mut p = Placer::new(center, 75.0, 0x07A1);
    // Ground: a 1 m grid 1.6 m below the eye.
    for gx in -10..=10 {
        for gy in -10..=10 {
            let jitter = DVec3::new(p.rng.range(-0.2, 0.2), p.rng.range(-0.2, 0.2), 0.0);
            let radius = p.rng.range(0.05, 0.12);
            p.at_offset(DVec3::new(gx as f64, gy as f64, -1.6) + jitter, radius);
        }
    }
    // Two walls either side, 6 m away.
    for side in [-6.0, 6.0] {
        for k in 0..20 {
            for h in 0..8 {
                p.at_offset(
                    DVec3::new(side, -10.0 + k as f64, -1.6 + 0.5 * h as f64),
                    0.15,
                );
            }
        }
    }
    p.finish(
        "utm",
        vec![
            view(
                "utm",
                "ground grid and walls at UTM coordinates (637 km E, 851 km N), mono",
                SuiteStereo::Mono,
                ("off", "off"),
                &["utm"],
            ),
            view(
                "utm_ods",
                "the UTM scene in ODS, comfortable merge",
                SuiteStereo::Ods,
                ("comfortable", "comfortable"),
                &["utm"],
            ),
        ],
    )
}

/// Thousands of tiny spheres in a 40 cm cube 3 m ahead: sub-pixel proxies, heavy overdraw.
pub fn dense_cluster() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(0.0, 0.0, 0.0), 0.0, 0xDE45);
    for _ in 0..3000 {
        let o = DVec3::new(
            p.rng.range(-0.2, 0.2),
            3.0 + p.rng.range(-0.2, 0.2),
            p.rng.range(-0.2, 0.2),
        );
        p.at_offset(o, 0.004);
    }
    p.horizon_ring(12, 5.0, 0.1);
    p.finish(
        "dense_cluster",
        vec![view(
            "dense_cluster",
            "3000 spheres of radius 4 mm in a 40 cm cube 3 m ahead (about one pixel each)",
            SuiteStereo::Mono,
            ("off", "off"),
            &["dense"],
        )],
    )
}

/// One sphere filling a large part of the view, small spheres in front of it.
pub fn huge_sphere() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(0.0, 0.0, 0.0), 0.0, 0x4B6E);
    // Angular radius asin(40/50) = 53°.
    p.at_angles(20.0, 10.0, 50.0, 40.0);
    for _ in 0..30 {
        let lam = p.rng.range(-30.0, 70.0);
        let phi = p.rng.range(-30.0, 50.0);
        let dist = p.rng.range(3.0, 8.0);
        p.at_angles(lam, phi, dist, 0.1);
    }
    p.finish(
        "huge_sphere",
        vec![
            view(
                "huge_sphere",
                "one sphere of radius 40 m at 50 m (53° angular radius), small spheres in front",
                SuiteStereo::Mono,
                ("off", "off"),
                &["huge"],
            ),
            view(
                "huge_sphere_ods",
                "the huge sphere in ODS, comfortable merge",
                SuiteStereo::Ods,
                ("comfortable", "comfortable"),
                &["huge"],
            ),
        ],
    )
}

/// A field of spheres at latitudes 60-89° (north and south), rendered with and without pole
/// merging: where merging changes the viewing circle fastest.
pub fn high_latitude() -> SuiteScene {
    let mut p = Placer::new(DVec3::new(3.0, 3.0, 1.6), 0.0, 0x4161);
    for _ in 0..1500 {
        let lam = p.rng.range(-180.0, 180.0);
        let sign = if p.rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
        let phi = sign * p.rng.range(60.0, 89.0);
        let dist = p.rng.range(3.0, 15.0);
        let radius = p.rng.range(0.03, 0.12);
        p.at_angles(lam, phi, dist, radius);
    }
    p.horizon_ring(24, 6.0, 0.2);
    p.finish(
        "high_latitude",
        vec![
            view(
                "high_latitude_merge",
                "1500 spheres at latitudes 60-89° north and south, ODS with comfortable merging",
                SuiteStereo::Ods,
                ("comfortable", "comfortable"),
                &["pole"],
            ),
            view(
                "high_latitude_nomerge",
                "the high-latitude field in ODS without pole merging",
                SuiteStereo::Ods,
                ("off", "off"),
                &["pole"],
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{Eye, OdsOffset, PoleMerging, Stereo, View};

    #[test]
    fn generators_are_deterministic() {
        assert_eq!(all_scenes(), all_scenes());
    }

    #[test]
    fn names_are_unique_across_views_and_scenes() {
        let mut names: Vec<String> = all_scenes()
            .iter()
            .flat_map(|s| s.views.iter().map(|v| v.name.clone()))
            .collect();
        let n = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n);
    }

    #[test]
    fn pole_spheres_contain_the_poles() {
        let s = poles();
        let contains = |dir: DVec3| {
            s.points.iter().take(4).filter(move |p| {
                let v = p.position - s.camera;
                // The ray from the camera along `dir` hits the sphere.
                let t = v.dot(dir);
                t > 0.0 && (v - t * dir).length() < p.radius as f64
            })
        };
        assert_eq!(contains(DVec3::Z).count(), 2);
        assert_eq!(contains(-DVec3::Z).count(), 2);
    }

    #[test]
    fn seam_spheres_are_behind_the_camera_and_cross_it() {
        let s = seam();
        let b = Camera::new(s.camera, s.yaw_deg).basis();
        for p in s.points.iter().take(15) {
            let v = p.position - s.camera;
            let (lam, _) = equirect::angles(&b, v);
            let half_width = (p.radius as f64 / v.length()).asin();
            assert!(PI - lam.abs() < half_width + 0.06, "lam {lam}");
        }
    }

    #[test]
    fn inside_circle_spheres_are_unprojectable_for_both_eyes() {
        let s = inside_circle();
        let stereo = Stereo::Ods {
            ipd: Stereo::DEFAULT_IPD,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
        let cam = Camera::new(s.camera, s.yaw_deg);
        for eye in [Eye::Left, Eye::Right] {
            let v = View::eye(cam, &stereo, eye);
            let culled = s.points.iter().filter(|p| v.project(p.position).is_none());
            assert_eq!(culled.count(), 40);
        }
    }

    #[test]
    fn enclosing_sphere_contains_the_camera_and_near_spheres_do_not_contain_ray_origins() {
        let e = enclosing();
        let big = e.points[0];
        assert!((big.position - e.camera).length() < big.radius as f64 - 1.0);
        let n = near_eye();
        for p in n.points.iter().take(40) {
            // Ray origins lie within ipd/2 = 0.032 m of the camera centre.
            assert!((p.position - n.camera).length() - p.radius as f64 > 0.032);
        }
    }

    #[test]
    fn utm_scene_keeps_sub_millimetre_precision_in_the_local_frame() {
        let s = utm();
        assert!(s.camera.x > 6e5 && s.camera.y > 8e5);
        let scene = s.to_scene();
        for (local, p) in scene.positions.iter().zip(&s.points) {
            let back = scene.origin + local.as_dvec3();
            assert!((back - p.position).abs().max_element() < 1e-5);
        }
    }
}
