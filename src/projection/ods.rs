//! The omnidirectional-stereo ray of a pixel and its exact inverse (DESIGN §3).

use glam::DVec3;

use super::camera::{Basis, Camera};
use super::depth_map::DepthMap;
use super::equirect::{self, Equirect};
use super::image::{Image, Projection};
use super::pole_merge::{PoleMerge, PoleMerging};

/// Which eye of an ODS pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Eye {
    /// Left eye, sign -1 (top image of a top-bottom pair).
    Left,
    /// Right eye, sign +1.
    Right,
}

impl Eye {
    /// The eye's sign `e` in the ODS formulas.
    pub fn sign(self) -> f64 {
        match self {
            Eye::Left => -1.0,
            Eye::Right => 1.0,
        }
    }
}

/// How the rasterizer maps a world point to an eye's image (`--ods-offset`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum OdsOffset {
    /// The exact inverse of the ODS ray: `asin(r / rho)`, with the pole-merging fixed point.
    #[default]
    Exact,
    /// Marrinan & Papka's per-vertex offset perpendicular to `P - C`: `atan(r / rho)`.
    Paper,
}

/// The stereo method, without its parameters (`--stereo`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StereoKind {
    /// One panorama.
    #[default]
    Mono,
    /// Omnidirectional stereo: left and right eye, top-bottom (left on top).
    Ods,
    /// Two parallel cameras `ipd` apart (DESIGN §9).
    Parallel,
    /// Trapp et al.: two cube maps of `N x N` faces from the parallel cameras, resampled.
    Cubemap(u32),
}

impl StereoKind {
    /// Default cube-map face size of `cubemap` without `:N`.
    pub const DEFAULT_FACE: u32 = 1024;

    /// Cube-map face sizes accepted, pixels.
    pub const FACE_SIZES: std::ops::RangeInclusive<u32> = 16..=8192;

    /// Images rendered per frame: 1 or 2.
    pub fn eyes(self) -> u32 {
        match self {
            StereoKind::Mono => 1,
            _ => 2,
        }
    }

    /// This method's rig: eyes `ipd` apart; `merging` and `offset` apply to ODS only.
    pub fn rig(self, ipd: f64, merging: PoleMerging, offset: OdsOffset) -> Stereo {
        match self {
            StereoKind::Mono => Stereo::Mono,
            StereoKind::Parallel => Stereo::Parallel { ipd },
            StereoKind::Cubemap(face) => Stereo::Cubemap { ipd, face },
            StereoKind::Ods => Stereo::Ods {
                ipd,
                merging,
                offset,
            },
        }
    }
}

/// `none`, `ods`, `parallel` or `cubemap[:N]` (N in 16..=8192, default 1024).
impl std::str::FromStr for StereoKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim().to_ascii_lowercase();
        match s.split_once(':') {
            Some(("cubemap", n)) => {
                let n: u32 = n
                    .parse()
                    .map_err(|_| format!("expected cubemap:N with N the face size, got `{s}`"))?;
                if Self::FACE_SIZES.contains(&n) {
                    Ok(StereoKind::Cubemap(n))
                } else {
                    Err(format!("cubemap:N needs 16 <= N <= 8192 pixels, got {n}"))
                }
            }
            None if s == "none" || s == "mono" => Ok(StereoKind::Mono),
            None if s == "ods" => Ok(StereoKind::Ods),
            None if s == "parallel" => Ok(StereoKind::Parallel),
            None if s == "cubemap" => Ok(StereoKind::Cubemap(Self::DEFAULT_FACE)),
            _ => Err(format!(
                "unknown stereo `{s}`: use none, ods, parallel or cubemap[:N]"
            )),
        }
    }
}

/// Prints as `--stereo` parses.
impl std::fmt::Display for StereoKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StereoKind::Mono => write!(f, "none"),
            StereoKind::Ods => write!(f, "ods"),
            StereoKind::Parallel => write!(f, "parallel"),
            StereoKind::Cubemap(n) => write!(f, "cubemap:{n}"),
        }
    }
}

/// Mono or omnidirectional stereo.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stereo {
    /// One central panorama.
    Mono,
    /// An ODS pair.
    Ods {
        /// Interocular distance, metres ([`Stereo::DEFAULT_IPD`]).
        ipd: f64,
        /// Pole-merge profiles.
        merging: PoleMerging,
        /// Inverse used by the rasterizer.
        offset: OdsOffset,
    },
    /// Two parallel cameras at `C -+ (ipd/2) R` (DESIGN §9).
    Parallel {
        /// Distance between the cameras, metres.
        ipd: f64,
    },
    /// Trapp et al.: each eye's cube map of `face x face` pixels, rendered from its parallel
    /// camera and resampled per output pixel (DESIGN §9).
    Cubemap {
        /// Distance between the cameras, metres.
        ipd: f64,
        /// Cube-map face size, pixels.
        face: u32,
    },
}

impl Stereo {
    /// The interocular distance every command starts from, metres (DESIGN §3).
    pub const DEFAULT_IPD: f64 = 0.064;

    /// The ODS rig every command starts from: [`Stereo::DEFAULT_IPD`], comfortable merging at
    /// both poles, the exact inverse.
    pub const DEFAULT_ODS: Stereo = Stereo::Ods {
        ipd: Stereo::DEFAULT_IPD,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    };

    /// Largest interocular distance accepted, metres.
    pub const MAX_IPD: f64 = 10.0;

    /// `ipd` when it lies in `0..=MAX_IPD` metres (0 makes both eyes the mono view).
    ///
    /// # Errors
    /// A message giving the allowed range.
    pub fn check_ipd(ipd: f64) -> Result<f64, String> {
        if (0.0..=Self::MAX_IPD).contains(&ipd) {
            Ok(ipd)
        } else {
            Err(format!(
                "the interocular distance must lie in 0..={} metres, got `{ipd}`",
                Self::MAX_IPD
            ))
        }
    }

    /// The method without its parameters.
    pub fn kind(&self) -> StereoKind {
        match *self {
            Stereo::Mono => StereoKind::Mono,
            Stereo::Ods { .. } => StereoKind::Ods,
            Stereo::Parallel { .. } => StereoKind::Parallel,
            Stereo::Cubemap { face, .. } => StereoKind::Cubemap(face),
        }
    }

    /// Interocular distance, metres (0 for mono).
    pub fn ipd(&self) -> f64 {
        match *self {
            Stereo::Mono => 0.0,
            Stereo::Ods { ipd, .. } | Stereo::Parallel { ipd } | Stereo::Cubemap { ipd, .. } => ipd,
        }
    }

    /// The views this setting renders, in output order (left eye first).
    pub fn views(&self, camera: Camera) -> Vec<View> {
        match *self {
            Stereo::Mono => vec![View::mono(camera)],
            _ => vec![
                View::eye(camera, self, Eye::Left),
                View::eye(camera, self, Eye::Right),
            ],
        }
    }
}

/// One eye's (or the mono) projection: everything a renderer needs to map pixels and points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The camera.
    pub camera: Camera,
    /// `e`: -1 left, +1 right, 0 mono.
    pub eye_sign: f64,
    /// Half the interocular distance (`ipd / 2`), 0 for mono.
    pub half_ipd: f64,
    /// Pole-merge profiles.
    pub merging: PoleMerging,
    /// Inverse used by the rasterizer.
    pub offset: OdsOffset,
    /// How the eye's rays start: on the viewing circle or at a parallel camera.
    pub model: EyeModel,
    /// `--depth-map` (DESIGN §9): each sphere is seen in its own view
    /// ([`View::for_sphere`]); `None` for plain ODS, mono, parallel and identity maps. The
    /// other methods ignore it and use `half_ipd`.
    pub depth_map: Option<DepthMap>,
    basis: Basis,
}

/// Where an eye's rays start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EyeModel {
    /// On the viewing circle, tangent to it (DESIGN §3); mono when `eye_sign` is 0.
    #[default]
    Ods,
    /// At the parallel camera `C + e (ipd/2) R` for every direction (DESIGN §9).
    Parallel,
}

/// Fixed-point iterations before the inverse falls back to bisection.
pub const FIXED_POINT_ITERATIONS: usize = 8;
/// Bisection steps of the inverse's fallback (halves `[0, rho]` to f64 resolution).
pub const BISECTION_STEPS: usize = 64;

impl View {
    /// The central (mono) view.
    pub fn mono(camera: Camera) -> Self {
        View {
            camera,
            eye_sign: 0.0,
            half_ipd: 0.0,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
            model: EyeModel::Ods,
            depth_map: None,
            basis: camera.basis(),
        }
    }

    /// The view of `eye` under `stereo` (the mono view when `stereo` is mono).
    pub fn eye(camera: Camera, stereo: &Stereo, eye: Eye) -> Self {
        match *stereo {
            Stereo::Mono => View::mono(camera),
            Stereo::Ods {
                ipd,
                merging,
                offset,
            } => View {
                camera,
                eye_sign: eye.sign(),
                half_ipd: 0.5 * ipd,
                merging,
                offset,
                model: EyeModel::Ods,
                depth_map: None,
                basis: camera.basis(),
            },
            Stereo::Parallel { ipd } | Stereo::Cubemap { ipd, .. } => View {
                camera,
                eye_sign: eye.sign(),
                half_ipd: 0.5 * ipd,
                merging: PoleMerging::OFF,
                offset: OdsOffset::Exact,
                model: EyeModel::Parallel,
                depth_map: None,
                basis: camera.basis(),
            },
        }
    }

    /// The camera frame.
    pub fn basis(&self) -> &Basis {
        &self.basis
    }

    /// This view under `map`: kept for an ODS eye when the map is not the identity (identity
    /// pairs give plain ODS exactly, DESIGN §9), dropped otherwise.
    pub fn with_depth_map(self, map: Option<DepthMap>) -> Self {
        let ods_eye = self.model == EyeModel::Ods && self.eye_sign != 0.0;
        View {
            depth_map: map.filter(|m| ods_eye && !m.is_identity()),
            ..self
        }
    }

    /// Half-ipd `r_s` of the sphere centred at `centre` (DESIGN §9): the depth map's
    /// `ods_radius(ipd/2, rho_c)`, `rho_c` the centre's horizontal distance from C in the
    /// rig frame; `half_ipd` without a map.
    pub fn sphere_half_ipd(&self, centre: DVec3) -> f64 {
        let Some(map) = self.depth_map else {
            return self.half_ipd;
        };
        let v = centre - self.camera.center;
        let rho_c = v.dot(self.basis.right).hypot(v.dot(self.basis.forward));
        map.ods_radius(self.half_ipd, rho_c)
    }

    /// The view the sphere centred at `centre` is seen in: plain ODS with half-ipd
    /// [`View::sphere_half_ipd`] (this view itself without a depth map).
    pub fn for_sphere(&self, centre: DVec3) -> View {
        View {
            half_ipd: self.sphere_half_ipd(centre),
            depth_map: None,
            ..*self
        }
    }

    /// The largest [`View::sphere_half_ipd`] of any sphere: `r_s` is `rho_c s(D0)` up to
    /// `B0`, affine in `rho_c` between breakpoints and constant beyond `Bn`, so its maximum
    /// is at a breakpoint.
    pub fn max_sphere_half_ipd(&self) -> f64 {
        match self.depth_map {
            None => self.half_ipd,
            Some(map) => map
                .breakpoints()
                .iter()
                .map(|&b| map.ods_radius(self.half_ipd, b))
                .fold(0.0, f64::max),
        }
    }

    /// Viewing-circle radius `r(phi) = (ipd / 2) * merge(phi)`.
    #[inline]
    pub fn circle_radius(&self, phi: f64) -> f64 {
        if self.half_ipd == 0.0 {
            0.0
        } else {
            self.half_ipd * self.merging.factor(phi)
        }
    }

    /// The ray of longitude `lam`, latitude `phi`: origin and unit direction (DESIGN §3).
    #[inline]
    pub fn ray(&self, lam: f64, phi: f64) -> (DVec3, DVec3) {
        let b = &self.basis;
        let dir = equirect::direction(b, lam, phi);
        if self.eye_sign == 0.0 {
            return (self.camera.center, dir);
        }
        if self.model == EyeModel::Parallel {
            return (self.parallel_camera(), dir);
        }
        let origin = self.circle_origin(self.circle_radius(phi), self.side(lam));
        (origin, dir)
    }

    /// `side(lam) = cos(lam) R - sin(lam) F`: horizontal, to the right of longitude `lam`.
    #[inline]
    pub fn side(&self, lam: f64) -> DVec3 {
        let (sl, cl) = lam.sin_cos();
        cl * self.basis.right - sl * self.basis.forward
    }

    /// ODS ray origin `C + e r side` on the viewing circle of radius `r` (DESIGN §3).
    #[inline]
    pub fn circle_origin(&self, r: f64, side: DVec3) -> DVec3 {
        self.camera.center + self.eye_sign * r * side
    }

    /// The ray through the centre of pixel `(i, j)` of the equirectangular `image`.
    #[inline]
    pub fn pixel_ray(&self, image: &Equirect, i: u32, j: u32) -> (DVec3, DVec3) {
        let (lam, phi) = image.pixel_angles(i, j);
        self.ray(lam, phi)
    }

    /// The ray through the centre of pixel `(i, j)` of `image` in any projection (DESIGN §8),
    /// or `None` where the projection shows nothing. The map's rays are its own vertical
    /// ones, whatever the view.
    #[inline]
    pub fn image_ray(&self, image: &Image, i: u32, j: u32) -> Option<(DVec3, DVec3)> {
        if let Projection::Map(Some(frame)) = image.projection {
            let (u, v) = image.pixel_uv(i, j);
            return Some(frame.ray(u, v));
        }
        let (lam, phi) = image.pixel_angles(i, j)?;
        Some(self.ray(lam, phi))
    }

    /// The parallel camera of this eye, `C + e (ipd/2) R` (the centre for mono).
    #[inline]
    pub fn parallel_camera(&self) -> DVec3 {
        self.camera.center + self.eye_sign * self.half_ipd * self.basis.right
    }

    /// Longitude and latitude at which world point `p` appears in this view, or `None` when
    /// `p` has no projection (inside the viewing circle, or at the camera centre).
    ///
    /// `Exact` inverts [`View::ray`]: `lam = lamC - e asin(r / rho)`,
    /// `phi = atan2(dz, sqrt(rho^2 - r^2))`, `r = r(phi)` solved as a fixed point.
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let b = &self.basis;
        let v = if self.model == EyeModel::Parallel {
            p - self.parallel_camera()
        } else {
            p - self.camera.center
        };
        let (x, y, z) = (v.dot(b.right), v.dot(b.forward), v.dot(b.up));
        let rho = x.hypot(y);
        let lam_c = x.atan2(y);
        if self.eye_sign == 0.0 || self.half_ipd == 0.0 || self.model == EyeModel::Parallel {
            if rho == 0.0 && z == 0.0 {
                return None;
            }
            return Some((lam_c, z.atan2(rho)));
        }
        match self.offset {
            OdsOffset::Exact => {
                // Solve for the horizontal run `s` of the ray to the point, then take r from
                // the latitude so the returned ray passes through `p` even where the fixed
                // point is ill-conditioned (steep profiles, points near the circle).
                let s_run = self.solve_ray_run(rho, z)?;
                let phi = z.atan2(s_run);
                let r = self.circle_radius(phi);
                let dlam = r.atan2(s_run);
                Some((equirect::wrap_longitude(lam_c - self.eye_sign * dlam), phi))
            }
            OdsOffset::Paper => {
                if rho == 0.0 && z == 0.0 {
                    return None;
                }
                let r = self.circle_radius(z.atan2(rho));
                let phi = z.atan2(rho.hypot(r));
                let dlam = if rho == 0.0 { 0.0 } else { (r / rho).atan() };
                Some((equirect::wrap_longitude(lam_c - self.eye_sign * dlam), phi))
            }
        }
    }

    /// Continuous image position of world point `p`, or `None` when it has no projection.
    pub fn project_to_image(&self, image: &Equirect, p: DVec3) -> Option<(f64, f64)> {
        self.project(p)
            .map(|(lam, phi)| image.position_of_angles(lam, phi))
    }

    /// Solves `r = r(atan2(z, sqrt(rho^2 - r^2)))` for a point at horizontal distance `rho`
    /// and height `z` above the camera; `None` when the point lies inside the viewing circle.
    pub fn solve_circle_radius(&self, rho: f64, z: f64) -> Option<f64> {
        self.solve_ray_run(rho, z)
            .map(|s| self.circle_radius(z.atan2(s)))
    }

    /// Horizontal run `s = sqrt(rho^2 - r^2)` from the ray origin to a point at horizontal
    /// distance `rho` and height `z` above the camera, where `r = r(atan2(z, s))`; `None` when
    /// the point lies inside the viewing circle.
    ///
    /// `G(s) = r(atan2(z, s))^2 + s^2 - rho^2` increases with `s` (merging never grows
    /// towards a pole), so the root in `[0, rho]` is unique and exists iff `G(0) <= 0`.
    pub fn solve_ray_run(&self, rho: f64, z: f64) -> Option<f64> {
        let radius_at_run = |s: f64| self.circle_radius(z.atan2(s));
        if radius_at_run(0.0) > rho {
            return None;
        }
        if rho == 0.0 {
            return Some(0.0);
        }
        // Fixed point on r from the latitude seen from C: converges in a few steps for the
        // profiles in use; bisection on s guards the steep ones.
        let run_of = |r: f64| (rho * rho - r * r).max(0.0).sqrt();
        let mut r = self.circle_radius(z.atan2(rho)).min(rho);
        for _ in 0..FIXED_POINT_ITERATIONS {
            let next = radius_at_run(run_of(r)).min(rho);
            if (next - r).abs() <= 1e-13 * self.half_ipd {
                return Some(run_of(next));
            }
            r = next;
        }
        let (mut lo, mut hi) = (0.0, rho);
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            let r = radius_at_run(mid);
            if r * r + mid * mid < rho * rho {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ods(merging: PoleMerging) -> Stereo {
        Stereo::Ods {
            ipd: 0.064,
            merging,
            offset: OdsOffset::Exact,
        }
    }

    #[test]
    fn parallel_eyes_see_from_fixed_cameras() {
        let cam = Camera::new(DVec3::new(1.0, 2.0, 3.0), 90.0);
        let v = View::eye(cam, &Stereo::Parallel { ipd: 0.064 }, Eye::Left);
        let o = cam.center - 0.032 * cam.basis().right;
        for &(lam, phi) in &[(0.0, 0.0), (2.0, 0.3), (-2.5, -0.9)] {
            assert_eq!(v.ray(lam, phi).0, o);
        }
        // A point straight ahead is seen turned right by atan(h / d) from the left camera.
        let p = cam.center + 10.0 * cam.basis().forward;
        let (lam, phi) = v.project(p).unwrap();
        assert!((lam - (0.032f64 / 10.0).atan()).abs() < 1e-12 && phi.abs() < 1e-12);
        // Sideways, both cameras see the point in the same direction.
        let side = cam.center + 10.0 * cam.basis().right;
        let r = View::eye(cam, &Stereo::Parallel { ipd: 0.064 }, Eye::Right);
        assert_eq!(v.project(side).unwrap().0, r.project(side).unwrap().0);
    }

    #[test]
    fn a_depth_map_gives_each_sphere_its_own_half_ipd() {
        let cam = Camera::new(DVec3::new(1.0, 2.0, 3.0), 30.0).with_orientation(10.0, 5.0);
        let map: DepthMap = "0.5=1.5,2=3".parse().unwrap();
        let stereo = ods(PoleMerging::both(PoleMerge::COMFORTABLE));
        let right = View::eye(cam, &stereo, Eye::Right).with_depth_map(Some(map));
        assert_eq!(right.depth_map, Some(map));
        // Horizontal distance in the rig frame: 4 m ahead, 3 m up the rig's up axis.
        let b = cam.basis();
        let c = cam.center + 4.0 * b.forward + 3.0 * b.up;
        let r_s = right.sphere_half_ipd(c);
        assert!((r_s - map.ods_radius(0.032, 4.0)).abs() < 1e-15);
        let own = right.for_sphere(c);
        assert_eq!((own.half_ipd, own.depth_map), (r_s, None));
        // The largest radius any sphere gets is a * Bi / Di at a breakpoint.
        let max = right.max_sphere_half_ipd();
        assert!((max - 0.032 * 2.0 / 3.0).abs() < 1e-15);
        for k in 0..2000 {
            let rho = 0.001 * 1.005f64.powi(k);
            assert!(right.sphere_half_ipd(cam.center + rho * b.right) <= max * (1.0 + 1e-12));
        }
        // Identity maps, mono and parallel views keep no map.
        let identity: DepthMap = "0.01=0.01,1000=1000".parse().unwrap();
        let plain = View::eye(cam, &stereo, Eye::Left);
        assert_eq!(plain.with_depth_map(Some(identity)), plain);
        assert_eq!(View::mono(cam).with_depth_map(Some(map)).depth_map, None);
        let par = View::eye(cam, &Stereo::Parallel { ipd: 0.064 }, Eye::Left);
        assert_eq!(par.with_depth_map(Some(map)).depth_map, None);
        // Without a map every sphere sees the eye's view.
        assert_eq!(plain.for_sphere(c), plain);
    }

    #[test]
    fn stereo_kinds_parse_and_print() {
        for s in ["none", "ods", "parallel", "cubemap:256"] {
            let k: StereoKind = s.parse().unwrap();
            assert_eq!(k.to_string(), s);
        }
        assert_eq!(
            "cubemap".parse::<StereoKind>(),
            Ok(StereoKind::Cubemap(1024))
        );
        assert!(
            "cubemap:7"
                .parse::<StereoKind>()
                .unwrap_err()
                .contains("16 <= N")
        );
        assert!(
            "hammer"
                .parse::<StereoKind>()
                .unwrap_err()
                .contains("unknown stereo")
        );
    }

    #[test]
    fn rays_are_tangent_to_the_viewing_circle() {
        let cam = Camera::new(DVec3::new(1.0, 2.0, 3.0), 20.0);
        let v = View::eye(cam, &ods(PoleMerging::OFF), Eye::Right);
        for &(lam, phi) in &[(0.0, 0.0), (2.0, 0.3), (-2.5, -0.9)] {
            let (o, d) = v.ray(lam, phi);
            let oh = (o - cam.center).truncate();
            assert!((oh.length() - 0.032).abs() < 1e-12);
            assert!(oh.dot(d.truncate()).abs() < 1e-12);
        }
    }

    #[test]
    fn right_eye_sees_a_point_ahead_shifted_left() {
        let cam = Camera::new(DVec3::ZERO, 0.0);
        let v = View::eye(cam, &ods(PoleMerging::OFF), Eye::Right);
        let (lam, phi) = v.project(DVec3::new(0.0, 10.0, 0.0)).unwrap();
        assert!((lam + (0.032f64 / 10.0).asin()).abs() < 1e-12);
        assert!(phi.abs() < 1e-12);
    }

    #[test]
    fn inside_the_viewing_circle_is_unprojectable() {
        let cam = Camera::new(DVec3::ZERO, 0.0);
        let v = View::eye(cam, &ods(PoleMerging::OFF), Eye::Left);
        assert!(v.project(DVec3::new(0.01, 0.01, 0.0)).is_none());
        assert!(v.project(DVec3::new(0.0, 0.0, 5.0)).is_none());
        let merged = View::eye(
            cam,
            &ods(PoleMerging::both(PoleMerge::COMFORTABLE)),
            Eye::Left,
        );
        let (_, phi) = merged.project(DVec3::new(0.0, 0.0, 5.0)).unwrap();
        assert!((phi - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn paper_offset_differs_by_asin_minus_atan() {
        let cam = Camera::new(DVec3::ZERO, 0.0);
        let Stereo::Ods { ipd, merging, .. } = ods(PoleMerging::OFF) else {
            unreachable!()
        };
        let paper = Stereo::Ods {
            ipd,
            merging,
            offset: OdsOffset::Paper,
        };
        let v = View::eye(cam, &paper, Eye::Right);
        let (lam, _) = v.project(DVec3::new(0.0, 0.5, 0.0)).unwrap();
        assert!((lam + (0.032f64 / 0.5).atan()).abs() < 1e-12);
    }

    #[test]
    fn fixed_point_converges_in_three_iterations_for_cycles_and_comfortable() {
        let cam = Camera::new(DVec3::ZERO, 0.0);
        for profile in [PoleMerge::COMFORTABLE, PoleMerge::CYCLES_DEFAULT] {
            let v = View::eye(cam, &ods(PoleMerging::both(profile)), Eye::Right);
            for k in 1..200 {
                let phi_c = (k as f64 * 0.45f64).to_radians();
                let (rho, z) = (2.0 * phi_c.cos(), 2.0 * phi_c.sin());
                let exact = v.solve_circle_radius(rho, z).unwrap();
                let phi_of = |r: f64| z.atan2((rho * rho - r * r).sqrt());
                let mut r = v.circle_radius(z.atan2(rho));
                for _ in 0..3 {
                    r = v.circle_radius(phi_of(r));
                }
                assert!((r - exact).abs() < 1e-9, "profile {profile:?} phi {phi_c}");
            }
        }
    }
}
