//! The pixel rectangles of a sphere's image in any projection (DESIGN §8): every pixel whose
//! ray ([`View::image_ray`]) hits the sphere has its centre in one of them. The f64 twin of
//! `shaders/image_bounds.wgsl` (same names, same branches); the rasterizer ray-casts each
//! pixel of each rectangle.
//!
//! Two kinds of input bound the hit directions. The equirect, cylindrical and Hammer images
//! map the longitude/latitude box of [`sphere_bounds`] (exact ODS inverse) through their
//! monotone formulas. The fisheye and the cube map take the cone from C to the ball of radius
//! `radius + h` (`h` the half interocular distance of an eye, 0 for mono): a ray from an
//! origin `o` within `h` of C that hits `X` has direction `X - o`, and `C + (X - o)` lies
//! within `h` of `X`, so inside that ball. The map's vertical rays hit exactly the pixels
//! whose origin lies within `radius` of the centre horizontally.

use std::f64::consts::{FRAC_PI_2, PI, SQRT_2, TAU};

use glam::{DVec2, DVec3};

use super::cubemap::FACES;
use super::equirect::wrap_longitude;
use super::image::{Image, Projection};
use super::map::MapFrame;
use super::ods::View;
use super::sphere_bounds::{ABSOLUTE_SLACK, AXIS_SLACK, ENCLOSE_SLACK, Rect, sphere_bounds};

/// Most rectangles [`image_bounds`] returns (one per cube face).
pub const MAX_RECTS: usize = 6;

/// A rectangle of continuous image positions in pixels, `x` right, `y` down; pixel `(i, j)`
/// has its centre at `(i + 0.5, j + 0.5)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelRect {
    /// Top-left corner.
    pub lo: DVec2,
    /// Bottom-right corner.
    pub hi: DVec2,
}

impl PixelRect {
    /// Whether the centre of pixel `(i, j)` lies in the rectangle.
    pub fn contains_pixel(&self, i: u32, j: u32) -> bool {
        let (x, y) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
        x >= self.lo.x && x <= self.hi.x && y >= self.lo.y && y <= self.hi.y
    }

    /// Pixels whose centres lie in the rectangle.
    pub fn pixel_count(&self) -> u64 {
        let n = |lo: f64, hi: f64| ((hi - 0.5).floor() - (lo - 0.5).ceil() + 1.0).max(0.0);
        (n(self.lo.x, self.hi.x) * n(self.lo.y, self.hi.y)) as u64
    }
}

/// Slack added around the bounds for the rounding of their evaluation and of the rays (the
/// rasterizer's f32): `angle` radians around angular bounds, then `pixel` pixels around the
/// rectangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margins {
    /// Radians.
    pub angle: f64,
    /// Pixels.
    pub pixel: f64,
}

impl Margins {
    /// No slack: the exact bounds.
    pub const NONE: Margins = Margins {
        angle: 0.0,
        pixel: 0.0,
    };
}

/// The rectangles collected so far, clipped to the image.
struct Rects {
    size: DVec2,
    pixel: f64,
    rects: Vec<PixelRect>,
}

impl Rects {
    fn new(image: &Image, m: Margins) -> Self {
        Rects {
            size: DVec2::new(f64::from(image.width), f64::from(image.height)),
            pixel: m.pixel,
            rects: Vec::with_capacity(MAX_RECTS),
        }
    }

    /// Adds `[lo, hi]` grown by the pixel margin and clipped to the image, unless empty.
    fn push_rect(&mut self, lo: DVec2, hi: DVec2) {
        let lo = (lo - DVec2::splat(self.pixel)).max(DVec2::ZERO);
        let hi = (hi + DVec2::splat(self.pixel)).min(self.size);
        if lo.x <= hi.x && lo.y <= hi.y {
            self.rects.push(PixelRect { lo, hi });
        }
    }

    /// The whole image.
    fn push_full(&mut self) {
        self.push_rect(DVec2::ZERO, self.size);
    }
}

/// Pixel rectangles holding every pixel whose ray in view `v` hits the sphere (`s` relative
/// to C, `radius`), with margins `m`; at most [`MAX_RECTS`], none when no pixel can see it.
pub fn image_bounds(image: &Image, v: &View, s: DVec3, radius: f64, m: Margins) -> Vec<PixelRect> {
    let mut out = Rects::new(image, m);
    match image.projection {
        Projection::Map(Some(frame)) => map_rect(&mut out, &frame, v.camera.center + s, radius),
        Projection::Map(None) => {}
        Projection::Fisheye { fov_deg } => match cone_of(v, s, radius, m.angle) {
            Some((axis, alpha)) => fisheye_rect(&mut out, axis, alpha, fov_deg.to_radians()),
            None => out.push_full(),
        },
        Projection::Cubemap => match cone_of(v, s, radius, m.angle) {
            Some((axis, alpha)) => cubemap_rects(&mut out, axis, alpha),
            None => out.push_full(),
        },
        p => {
            let r = sphere_bounds(v, s, radius).rect;
            let grown = Rect {
                lo: r.lo - DVec2::splat(m.angle),
                hi: r.hi + DVec2::splat(m.angle),
            };
            latlong_rects(&mut out, &p, grown);
        }
    }
    out.rects
}

/// Most rectangles [`image_bounds`] returns for `projection`.
pub fn max_rects(projection: &Projection) -> usize {
    match projection {
        Projection::Cubemap => MAX_RECTS,
        Projection::Fisheye { .. } | Projection::Map(_) => 1,
        // The two sides of the seam (or of the window's edge).
        _ => 2,
    }
}

/// The cone from C holding every hit direction: unit axis in rig components
/// `(d.R, d.F, d.U)` and half-angle grown by `angle_margin`; `None` when some ray origin may
/// lie in the sphere (every direction).
pub fn cone_of(v: &View, s: DVec3, radius: f64, angle_margin: f64) -> Option<(DVec3, f64)> {
    let h = if v.eye_sign != 0.0 { v.half_ipd } else { 0.0 };
    let d = s.length();
    let ball = radius + h;
    if d <= ball * (1.0 + ENCLOSE_SLACK) + ABSOLUTE_SLACK {
        return None;
    }
    let b = v.basis();
    let axis = DVec3::new(s.dot(b.right), s.dot(b.forward), s.dot(b.up)) / d;
    Some((axis, (ball / d).min(1.0).asin() + angle_margin))
}

/// `[lo, hi]` (longitude unwrapped, width under `2 pi`) intersected with `[-half, half]`
/// modulo `2 pi`: at most two pieces of positive width when `half <= pi`.
pub fn longitude_pieces(lo: f64, hi: f64, half: f64) -> Vec<(f64, f64)> {
    if hi - lo >= TAU {
        return vec![(-half, half)];
    }
    let c = 0.5 * (lo + hi);
    // Exactly zero when the centre is in range already, so an in-range box stays unrounded.
    let shift = if (-PI..PI).contains(&c) {
        0.0
    } else {
        wrap_longitude(c) - c
    };
    let mut pieces = Vec::with_capacity(2);
    for k in [-1.0, 0.0, 1.0] {
        let a = (lo + shift + k * TAU).max(-half);
        let b = (hi + shift + k * TAU).min(half);
        // A piece that only touches the window's edge holds no pixel centre.
        if a < b {
            pieces.push((a, b));
        }
    }
    pieces
}

/// The rectangles of longitude/latitude box `r` in the equirect, cylindrical or Hammer
/// image.
fn latlong_rects(out: &mut Rects, p: &Projection, r: Rect) {
    let size = out.size;
    let (half_w, half_h) = match *p {
        Projection::Equirect { hfov_deg, vfov_deg } => {
            (0.5 * hfov_deg.to_radians(), 0.5 * vfov_deg.to_radians())
        }
        Projection::Cylindrical { vfov_deg } => (PI, 0.5 * vfov_deg.to_radians()),
        _ => (PI, FRAC_PI_2),
    };
    let p0 = r.lo.y.max(-half_h);
    let p1 = r.hi.y.min(half_h);
    if p0 > p1 {
        return;
    }
    for (l0, l1) in longitude_pieces(r.lo.x, r.hi.x, half_w) {
        match *p {
            Projection::Hammer => {
                let (lo, hi) = hammer_box(l0, l1, p0, p1);
                out.push_rect(lo * size, hi * size);
            }
            Projection::Cylindrical { .. } => {
                let t = half_h.tan();
                let x = |l: f64| (l / TAU + 0.5) * size.x;
                let y = |p: f64| 0.5 * (1.0 - p.tan() / t) * size.y;
                out.push_rect(DVec2::new(x(l0), y(p1)), DVec2::new(x(l1), y(p0)));
            }
            _ => {
                let x = |l: f64| (l / (2.0 * half_w) + 0.5) * size.x;
                let y = |p: f64| (0.5 - p / (2.0 * half_h)) * size.y;
                out.push_rect(DVec2::new(x(l0), y(p1)), DVec2::new(x(l1), y(p0)));
            }
        }
    }
}

/// Hammer plane coordinates `(x, y)` (y up) of longitude `lam` in `[-pi, pi]`, latitude `phi`.
fn hammer_xy(lam: f64, phi: f64) -> DVec2 {
    let (sp, cp) = phi.sin_cos();
    let (sh, ch) = (0.5 * lam).sin_cos();
    let k = (1.0 + cp * ch).sqrt();
    DVec2::new(2.0 * SQRT_2 * cp * sh / k, SQRT_2 * sp / k)
}

/// Image-position box `(u, v)` in `[0, 1]^2` (v down) of the Hammer image of
/// `[l0, l1] x [p0, p1]` (`-pi <= l0 <= l1 <= pi`). `x` grows with `lam` and `|x|` is largest
/// at the smallest `|phi|`; `y` grows with `phi` and `|y|` with `|lam|`: the extremes lie at
/// the corners or where the box crosses `phi = 0` (x) and `lam = 0` (y).
pub fn hammer_box(l0: f64, l1: f64, p0: f64, p1: f64) -> (DVec2, DVec2) {
    let p_mid = 0.0f64.clamp(p0, p1);
    let l_mid = 0.0f64.clamp(l0, l1);
    let x_lo = hammer_xy(l0, p0)
        .x
        .min(hammer_xy(l0, p1).x)
        .min(hammer_xy(l0, p_mid).x);
    let x_hi = hammer_xy(l1, p0)
        .x
        .max(hammer_xy(l1, p1).x)
        .max(hammer_xy(l1, p_mid).x);
    let y_lo = hammer_xy(l0, p0)
        .y
        .min(hammer_xy(l1, p0).y)
        .min(hammer_xy(l_mid, p0).y);
    let y_hi = hammer_xy(l0, p1)
        .y
        .max(hammer_xy(l1, p1).y)
        .max(hammer_xy(l_mid, p1).y);
    let u = |x: f64| (x / (2.0 * SQRT_2) + 1.0) / 2.0;
    let v = |y: f64| (1.0 - y / SQRT_2) / 2.0;
    (DVec2::new(u(x_lo), v(y_hi)), DVec2::new(u(x_hi), v(y_lo)))
}

/// The fisheye rectangle of the cone (`axis` in rig components, half-angle `alpha`): the
/// annular sector of angles from F `[theta_a - alpha, theta_a + alpha]` and azimuths
/// `psi_a +- asin(sin alpha / sin theta_a)` (every azimuth when the cone holds F or -F),
/// bounded by its corners and the outer arc's axis crossings.
fn fisheye_rect(out: &mut Rects, axis: DVec3, alpha: f64, fov: f64) {
    let half = 0.5 * fov;
    let theta_a = axis.x.hypot(axis.z).atan2(axis.y);
    let s0 = (theta_a - alpha).max(0.0) / half;
    let s1 = ((theta_a + alpha).min(PI) / half).min(1.0);
    if s0 > s1 {
        return;
    }
    let (sin_a, sin_t) = (alpha.min(FRAC_PI_2).sin(), theta_a.sin());
    let (lo, hi) = if sin_a >= sin_t * (1.0 - AXIS_SLACK) {
        (DVec2::splat(-s1), DVec2::splat(s1))
    } else {
        let psi_a = axis.z.atan2(axis.x);
        let beta = (sin_a / sin_t).asin();
        let (psi0, psi1) = (psi_a - beta, psi_a + beta);
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for (s, psi) in [(s0, psi0), (s0, psi1), (s1, psi0), (s1, psi1)] {
            let q = s * DVec2::new(psi.cos(), psi.sin());
            lo = lo.min(q);
            hi = hi.max(q);
        }
        for k in 0..4 {
            let psi = f64::from(k) * FRAC_PI_2;
            if (psi - psi0).rem_euclid(TAU) <= psi1 - psi0 {
                let q = s1 * DVec2::new(psi.cos(), psi.sin());
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
        (lo, hi)
    };
    // Plane (x right, y up) in [-1, 1]^2 to pixels.
    let size = out.size;
    let px = |x: f64, y: f64| DVec2::new(0.5 * (x + 1.0) * size.x, 0.5 * (1.0 - y) * size.y);
    out.push_rect(px(lo.x, hi.y), px(hi.x, lo.y));
}

/// Range of the face coordinate `d.B / d.A` over the pixels of face `(A, B, C)` that see the
/// cone (`ka = k.A`, `kb = k.B`, `sin_a = sin alpha`), or `None` when none does. Face pixels
/// have `d.B / d.A = tan(psi)` with `psi = atan2(d.B, d.A)` in `[-pi/4, pi/4]`, and `psi` is
/// the direction's longitude about axis C: over the cone it lies within
/// `atan2(kb, ka) +- asin(sin_a / hypot(ka, kb))` (every angle when the cone holds +-C, with
/// [`AXIS_SLACK`]). The tangent planes of that range are the roots of
/// `a^2 (ka^2 - sin_a^2) - 2 a ka kb + kb^2 - sin_a^2 = 0`.
pub fn face_range(ka: f64, kb: f64, sin_a: f64) -> Option<(f64, f64)> {
    let rho = ka.hypot(kb);
    if sin_a >= rho * (1.0 - AXIS_SLACK) {
        return Some((-1.0, 1.0));
    }
    let psi = kb.atan2(ka);
    let beta = (sin_a / rho).asin();
    let quarter = 0.25 * PI;
    let pieces = longitude_pieces(psi - beta, psi + beta, quarter);
    let lo = pieces.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let hi = pieces.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    (lo < hi).then(|| (lo.tan().max(-1.0), hi.tan().min(1.0)))
}

/// The cube-map rectangles of the cone: per face in front of the cone's far side, the
/// [`face_range`] of each face coordinate.
fn cubemap_rects(out: &mut Rects, axis: DVec3, alpha: f64) {
    let sin_a = alpha.min(FRAC_PI_2).sin();
    let size = out.size;
    for (k, [fa, fb, fc]) in FACES.iter().enumerate() {
        let ka = axis.dot(*fa);
        if ka < -sin_a {
            continue;
        }
        let (Some(a), Some(b)) = (
            face_range(ka, axis.dot(*fb), sin_a),
            face_range(ka, axis.dot(*fc), sin_a),
        ) else {
            continue;
        };
        let x = |a: f64| (k as f64 + 0.5 * (a + 1.0)) / 6.0 * size.x;
        let y = |b: f64| 0.5 * (1.0 - b) * size.y;
        out.push_rect(DVec2::new(x(a.0), y(b.1)), DVec2::new(x(a.1), y(b.0)));
    }
}

/// The map's square around `centre` (local frame): the pixels whose vertical ray passes
/// within `radius` of it.
fn map_rect(out: &mut Rects, f: &MapFrame, centre: DVec3, radius: f64) {
    let size = out.size;
    let x = |x: f64| (x - f.x0) / (f.x1 - f.x0) * size.x;
    let y = |y: f64| (f.y1 - y) / (f.y1 - f.y0) * size.y;
    out.push_rect(
        DVec2::new(x(centre.x - radius), y(centre.y + radius)),
        DVec2::new(x(centre.x + radius), y(centre.y - radius)),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::sphere;
    use crate::projection::{Camera, Eye, OdsOffset, PoleMerging, Stereo};

    /// Hit pixels outside every rectangle, and hit pixels in all.
    fn misses(image: &Image, v: &View, s: DVec3, r: f64) -> (usize, usize) {
        let rects = image_bounds(image, v, s, r, Margins::NONE);
        let (mut missed, mut hits) = (0, 0);
        for j in 0..image.height {
            for i in 0..image.width {
                let Some((o, d)) = v.image_ray(image, i, j) else {
                    continue;
                };
                if sphere::intersect(o, d, v.camera.center + s, r).is_some() {
                    hits += 1;
                    if !rects.iter().any(|q| q.contains_pixel(i, j)) {
                        missed += 1;
                    }
                }
            }
        }
        (missed, hits)
    }

    fn right_eye() -> View {
        let stereo = Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
        View::eye(Camera::new(DVec3::ZERO, 30.0), &stereo, Eye::Right)
    }

    fn images() -> Vec<Image> {
        [
            "equirect",
            "equirect:200,100",
            "hammer",
            "cylindrical:100",
            "fisheye:200",
            "cubemap",
        ]
        .iter()
        .map(|p| Image::new(p.parse().unwrap(), 96).unwrap())
        .collect()
    }

    #[test]
    fn rects_hold_every_hit_pixel_of_a_few_spheres() {
        let v = right_eye();
        let spheres = [
            (DVec3::new(1.0, 3.0, 0.5), 0.8),
            (DVec3::new(-2.0, -3.0, 0.1), 0.5),
            (DVec3::new(0.1, 0.0, 2.0), 0.4),
            (DVec3::new(0.0, 0.05, 0.0), 0.2),
            (DVec3::new(2.0, 0.5, -1.0), 0.9),
        ];
        for image in images() {
            let mut seen = 0;
            for &(s, r) in &spheres {
                let (missed, hits) = misses(&image, &v, s, r);
                assert_eq!(missed, 0, "{} {s}", image.projection);
                seen += usize::from(hits > 0);
            }
            // Partial views miss the sphere behind.
            assert!(seen >= 3, "{}: {seen}", image.projection);
        }
    }

    #[test]
    fn a_sphere_ahead_is_bounded_tightly() {
        let v = View::mono(Camera::new(DVec3::ZERO, 0.0));
        let (s, r) = (DVec3::new(0.0, 5.0, 0.0), 1.0);
        for image in images() {
            let rects = image_bounds(&image, &v, s, r, Margins::NONE);
            let area: u64 = rects.iter().map(PixelRect::pixel_count).sum();
            let (_, hits) = misses(&image, &v, s, r);
            // The disc's box holds 4/pi of its area, plus the rim pixels.
            assert!(
                area as f64 <= 1.6 * hits as f64 + 12.0,
                "{}: {area} px for {hits} hits",
                image.projection
            );
        }
    }

    #[test]
    fn the_seam_splits_the_box_and_an_enclosing_sphere_fills_the_image() {
        let v = View::mono(Camera::new(DVec3::ZERO, 0.0));
        let hammer = Image::new(Projection::Hammer, 96).unwrap();
        let behind = image_bounds(&hammer, &v, DVec3::new(0.0, -5.0, 0.0), 0.5, Margins::NONE);
        assert_eq!(behind.len(), 2);
        assert!(behind[0].lo.x == 0.0 || behind[1].lo.x == 0.0);
        for image in images() {
            let full = image_bounds(&image, &v, DVec3::new(0.1, 0.1, 0.0), 1.0, Margins::NONE);
            let all: u64 = full.iter().map(PixelRect::pixel_count).sum();
            assert!(
                all >= u64::from(image.width) * u64::from(image.height),
                "{}",
                image.projection
            );
        }
    }

    #[test]
    fn cube_faces_behind_the_cone_are_skipped() {
        let v = View::mono(Camera::new(DVec3::ZERO, 0.0));
        let cube = Image::new(Projection::Cubemap, 96).unwrap();
        // Ahead and small: the front face only, around its centre.
        let rects = image_bounds(&cube, &v, DVec3::new(0.0, 10.0, 0.0), 0.5, Margins::NONE);
        assert_eq!(rects.len(), 1);
        let c = 0.5 * (rects[0].lo + rects[0].hi);
        assert!((c - DVec2::new(8.0, 8.0)).length() < 1e-9, "{c}");
        // The face range is symmetric about the axis's face coordinate, and empty for a cone
        // whose angles about C miss the face's quarter.
        let (lo, hi) = face_range(1.0, 0.0, 0.05).unwrap();
        assert!((lo + hi).abs() < 1e-15 && (hi - 0.05 / (1.0 - 0.0025f64).sqrt()).abs() < 1e-15);
        assert_eq!(face_range(0.0, 1.0, 0.05), None);
        // A cone 0.9 rad about C from A, 0.2 rad wide, reaches the face from 0.7 rad on.
        let (lo, hi) = face_range(0.9f64.cos(), 0.9f64.sin(), 0.2f64.sin()).unwrap();
        assert!(
            (lo - 0.7f64.tan()).abs() < 1e-12 && (hi - 1.0).abs() < 1e-15,
            "{lo} {hi}"
        );
    }

    #[test]
    fn longitude_pieces_wrap_into_the_window() {
        assert_eq!(longitude_pieces(-0.1, 0.2, PI), vec![(-0.1, 0.2)]);
        let p = longitude_pieces(3.0, 3.4, PI);
        assert_eq!(p.len(), 2);
        assert!((p[0].0 + PI).abs() < 1e-15 && (p[0].1 - (3.4 - TAU)).abs() < 1e-15);
        assert!((p[1].0 - 3.0).abs() < 1e-15 && p[1].1 == PI);
        assert!(longitude_pieces(2.0, 2.5, 1.0).is_empty());
        assert_eq!(longitude_pieces(-4.0, 4.0, 1.0), vec![(-1.0, 1.0)]);
    }
}
