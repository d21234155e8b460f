//! The longitude/latitude box of a sphere's image in one view: every `(lam, phi)` whose ray
//! (DESIGN §3) hits the sphere lies in it. The f64 twin of `shaders/sphere_bounds.wgsl`
//! (same names, same branches); the derivation is in `docs/SPHERE_BOUNDS.md`.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DVec2, DVec3};

use super::camera::Basis;
use super::ods::{EyeModel, View};

/// Relative slack of the "ball meets the vertical axis" test in [`cap_rect`]: a ball this
/// close to the axis gets the band to the pole (its longitude half-width `asin(radius/rho)`
/// is ill-conditioned in f32 there).
pub const AXIS_SLACK: f64 = 1e-4;
/// Relative slack of the "eye may lie in the ball" test in [`sphere_bounds`].
pub const ENCLOSE_SLACK: f64 = 1e-5;
/// Relative slack of the "ball meets the viewing cylinder" test in [`sphere_bounds`].
pub const CYLINDER_SLACK: f64 = 1e-3;
/// Absolute slack (metres) of both tests in [`sphere_bounds`].
pub const ABSOLUTE_SLACK: f64 = 1e-6;

/// A `(lam, phi)` box: `lo` and `hi` corners, `x` longitude, `y` latitude. The longitude is
/// unwrapped: `lo.x` and `hi.x` may leave `[-pi, pi)`, the box covering `[lo.x, hi.x]`
/// modulo `2 pi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// `(lam, phi)` of the low corner.
    pub lo: DVec2,
    /// `(lam, phi)` of the high corner.
    pub hi: DVec2,
}

impl Rect {
    /// Every direction: longitude `[-pi, pi]`, latitude `[-pi/2, pi/2]`.
    pub fn full() -> Self {
        Rect {
            lo: DVec2::new(-PI, -FRAC_PI_2),
            hi: DVec2::new(PI, FRAC_PI_2),
        }
    }

    /// Whether `(lam, phi)` lies in the box, longitude taken modulo `2 pi`.
    pub fn contains(&self, lam: f64, phi: f64) -> bool {
        if phi < self.lo.y || phi > self.hi.y {
            return false;
        }
        let width = self.hi.x - self.lo.x;
        if width >= TAU {
            return true;
        }
        (lam - self.lo.x).rem_euclid(TAU) <= width
    }
}

/// [`sphere_bounds`]' answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// The box.
    pub rect: Rect,
    /// The box is not the tight image of the sphere (the eye may lie in it, the ball meets
    /// the viewing cylinder, or it spans every longitude): the rasterizer ray-casts such
    /// spheres whatever its imposter mode.
    pub special: bool,
}

/// Pole-merge factor of `v` at latitude `phi`.
fn merge(v: &View, phi: f64) -> f64 {
    v.merging.factor(phi)
}

/// Longitude/latitude box of the cone of directions from C to a ball of `radius` around `s`
/// (relative to C, `|s| > radius`): latitude `phi +- asin(radius/|s|)`, longitude
/// `+- asin(radius/rho)`; a band to the pole when the ball meets the vertical axis
/// (`radius >= rho`, with [`AXIS_SLACK`]).
pub fn cap_rect(b: &Basis, s: DVec3, radius: f64) -> Rect {
    let x = s.dot(b.right);
    let y = s.dot(b.forward);
    let z = s.dot(b.up);
    let rho = x.hypot(y);
    let d = s.length();
    let a = (radius / d).min(1.0).asin();
    let phi = z.atan2(rho);
    if radius >= rho * (1.0 - AXIS_SLACK) {
        return if z > 0.0 {
            Rect {
                lo: DVec2::new(-PI, phi - a),
                hi: DVec2::new(PI, FRAC_PI_2),
            }
        } else {
            Rect {
                lo: DVec2::new(-PI, -FRAC_PI_2),
                hi: DVec2::new(PI, phi + a),
            }
        };
    }
    let lam = x.atan2(y);
    let half = (radius / rho).asin();
    Rect {
        lo: DVec2::new(lam - half, phi - a),
        hi: DVec2::new(lam + half, phi + a),
    }
}

/// Conservative box of every `(lam, phi)` whose ray (view `v`) hits the sphere (`centre`
/// relative to C, `radius`). A parallel eye sees it as the mono view from its camera does.
pub fn sphere_bounds(v: &View, centre: DVec3, radius: f64) -> Bounds {
    eye_bounds(&shared_bounds(v, centre, radius), v.eye_sign)
}

/// The part of [`sphere_bounds`] an ODS view's two eyes share: the box before the eye's
/// longitude offset `lam -= e o`, `o` between `offsets.x` and `offsets.y` (both 0 where there
/// is none). A parallel eye's is its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedBounds {
    /// The box, longitudes before the offset.
    pub rect: Rect,
    /// The offset's range, unsigned.
    pub offsets: DVec2,
    /// As [`Bounds::special`].
    pub special: bool,
}

/// The box of the eye of sign `e`.
pub fn eye_bounds(b: &SharedBounds, e: f64) -> Bounds {
    let o1 = e * b.offsets.x;
    let o2 = e * b.offsets.y;
    Bounds {
        rect: Rect {
            lo: DVec2::new(b.rect.lo.x - o1.max(o2), b.rect.lo.y),
            hi: DVec2::new(b.rect.hi.x - o1.min(o2), b.rect.hi.y),
        },
        special: b.special,
    }
}

/// [`SharedBounds`] of the sphere in view `v`.
///
/// Exact-inverse argument: a hit `X` projects to its pixel,
/// `lam(X) = lamC(X) - e asin(r/rho(X))`, `tan phi(X) = k tan phiC(X)` with
/// `k = rho / sqrt(rho^2 - r^2)`; bound each factor over the ball.
pub fn shared_bounds(v: &View, centre: DVec3, radius: f64) -> SharedBounds {
    let (s, h) = if v.model == EyeModel::Parallel && v.eye_sign != 0.0 {
        // One camera for every ray: the mono box seen from it.
        (centre - v.eye_sign * v.half_ipd * v.basis().right, 0.0)
    } else if v.eye_sign != 0.0 {
        (centre, v.half_ipd)
    } else {
        (centre, 0.0)
    };
    let d = s.length();
    if d <= (radius + h) * (1.0 + ENCLOSE_SLACK) + ABSOLUTE_SLACK {
        return SharedBounds {
            rect: Rect::full(),
            offsets: DVec2::ZERO,
            special: true,
        };
    }
    let b = v.basis();
    let rho = s.dot(b.right).hypot(s.dot(b.forward));
    if h == 0.0 || rho - radius <= h * (1.0 + CYLINDER_SLACK) + ABSOLUTE_SLACK {
        // Every ray origin lies within h of C: hit directions lie in the cone of the ball of
        // radius + h.
        let c = cap_rect(b, s, radius + h);
        return SharedBounds {
            rect: c,
            offsets: DVec2::ZERO,
            special: h > 0.0 || c.hi.x - c.lo.x >= TAU,
        };
    }
    let mono = cap_rect(b, s, radius);
    let rho_min = rho - radius;
    let rho_max = rho + radius;
    // merge() does not grow with |phi| and |phi(X)| >= |phiC(X)|: the largest circle radius
    // is at the mono range's smallest |phi|.
    let rmax = if mono.lo.y > 0.0 {
        h * merge(v, mono.lo.y)
    } else if mono.hi.y < 0.0 {
        h * merge(v, mono.hi.y)
    } else {
        h
    };
    let kmax = rho_min / (rho_min * rho_min - rmax * rmax).sqrt();
    let phi_lo = mono.lo.y.min((kmax * mono.lo.y.tan()).atan());
    let phi_hi = mono.hi.y.max((kmax * mono.hi.y.tan()).atan());
    let rmin = h * merge(v, phi_lo).min(merge(v, phi_hi));
    SharedBounds {
        rect: Rect {
            lo: DVec2::new(mono.lo.x, phi_lo),
            hi: DVec2::new(mono.hi.x, phi_hi),
        },
        offsets: DVec2::new((rmin / rho_max).asin(), (rmax / rho_min).asin()),
        special: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{Camera, Eye, OdsOffset, PoleMerging, Stereo};

    fn right_eye() -> View {
        let stereo = Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
        View::eye(Camera::new(DVec3::ZERO, 0.0), &stereo, Eye::Right)
    }

    #[test]
    fn contains_wraps_longitude() {
        let r = Rect {
            lo: DVec2::new(3.0, -0.1),
            hi: DVec2::new(3.4, 0.1),
        };
        assert!(r.contains(3.2, 0.0));
        assert!(r.contains(3.3 - TAU, 0.0));
        assert!(r.contains(-3.0, 0.05));
        assert!(!r.contains(2.9, 0.0));
        assert!(!r.contains(-2.8, 0.0));
        assert!(!r.contains(3.2, 0.2));
        assert!(Rect::full().contains(-PI, FRAC_PI_2));
    }

    #[test]
    fn mono_box_of_a_ball_ahead_is_its_cone() {
        let v = View::mono(Camera::new(DVec3::ZERO, 0.0));
        let got = sphere_bounds(&v, DVec3::new(0.0, 10.0, 0.0), 1.0);
        let a = 0.1f64.asin();
        assert!(!got.special);
        assert!((got.rect.lo - DVec2::new(-a, -a)).length() < 1e-15);
        assert!((got.rect.hi - DVec2::new(a, a)).length() < 1e-15);
    }

    #[test]
    fn right_eye_box_is_shifted_left_by_the_offset() {
        let got = sphere_bounds(&right_eye(), DVec3::new(0.0, 10.0, 0.0), 1.0);
        assert!(!got.special);
        let a = 0.1f64.asin();
        // Offsets asin(r/rho) over rho in [9, 11].
        assert!((got.rect.lo.x - (-a - (0.032f64 / 9.0).asin())).abs() < 1e-15);
        assert!((got.rect.hi.x - (a - (0.032f64 / 11.0).asin())).abs() < 1e-15);
        // Latitude grows by k = rho / sqrt(rho^2 - r^2) at most.
        assert!(got.rect.hi.y > a && got.rect.hi.y < a * 1.0001);
    }

    #[test]
    fn an_ods_pair_shares_its_bounds_but_for_the_eyes_sign() {
        let stereo = Stereo::Ods {
            ipd: 0.5,
            merging: PoleMerging::both(crate::projection::PoleMerge::COMFORTABLE),
            offset: OdsOffset::Exact,
        };
        let camera = Camera::new(DVec3::new(1.0, 2.0, 3.0), 30.0).with_orientation(10.0, 5.0);
        let left = View::eye(camera, &stereo, Eye::Left);
        let right = View::eye(camera, &stereo, Eye::Right);
        let mut rng = crate::rng::SplitMix64::new(7);
        let mut ordinary = 0;
        for _ in 0..2000 {
            let centre = DVec3::new(
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
            );
            let radius = rng.range(0.01, 2.0);
            let shared = shared_bounds(&left, centre, radius);
            assert_eq!(shared, shared_bounds(&right, centre, radius));
            // The eyes' boxes are the shared one moved apart: the left eye's by the offset's
            // range to the east, the right eye's by it to the west (DESIGN §3).
            let (l, r) = (
                sphere_bounds(&left, centre, radius).rect,
                sphere_bounds(&right, centre, radius).rect,
            );
            assert_eq!((l.lo.y, l.hi.y), (shared.rect.lo.y, shared.rect.hi.y));
            assert_eq!((r.lo.y, r.hi.y), (shared.rect.lo.y, shared.rect.hi.y));
            assert_eq!(l.lo.x, shared.rect.lo.x + shared.offsets.x);
            assert_eq!(l.hi.x, shared.rect.hi.x + shared.offsets.y);
            assert_eq!(r.lo.x, shared.rect.lo.x - shared.offsets.y);
            assert_eq!(r.hi.x, shared.rect.hi.x - shared.offsets.x);
            ordinary += usize::from(!shared.special && shared.offsets.y > 0.0);
        }
        // Most spheres take the offset branch.
        assert!(ordinary > 1500, "{ordinary}");
    }

    /// The splat (`ordinary_bounds` in splat.wgsl) relies on it: a ball whose bounds are not
    /// special lies off the viewing cylinder, beyond every circle radius, so its centre
    /// projects.
    #[test]
    fn bounds_that_are_not_special_have_a_projected_centre() {
        let camera = Camera::new(DVec3::new(1.0, 2.0, 3.0), 30.0).with_orientation(10.0, 5.0);
        let merge = crate::projection::PoleMerge::COMFORTABLE;
        // Without merging, the centres inside the viewing circle have no projection.
        let unmerged = Stereo::Ods {
            ipd: 0.5,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
        let stereos = [
            Stereo::Mono,
            Stereo::Parallel { ipd: 0.5 },
            Stereo::Ods {
                ipd: 0.5,
                merging: PoleMerging::both(merge),
                offset: OdsOffset::Exact,
            },
            unmerged,
            Stereo::Ods {
                ipd: 0.5,
                merging: PoleMerging::OFF,
                offset: OdsOffset::Paper,
            },
        ];
        let mut rng = crate::rng::SplitMix64::new(11);
        for stereo in stereos {
            for eye in [Eye::Left, Eye::Right] {
                let v = View::eye(camera, &stereo, eye);
                let (mut ordinary, mut culled) = (0, 0);
                for _ in 0..4000 {
                    // Many centres near the viewing circle (radius 0.25), some inside it.
                    let centre = DVec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-2.0, 2.0),
                    );
                    let radius = rng.range(0.001, 0.3);
                    let projects = v.project(camera.center + centre).is_some();
                    culled += usize::from(!projects);
                    if !sphere_bounds(&v, centre, radius).special {
                        ordinary += 1;
                        assert!(projects, "{stereo:?} {eye:?} {centre} r {radius}");
                    }
                }
                assert!(ordinary > 1000, "{stereo:?}: {ordinary} ordinary");
                if stereo == unmerged {
                    assert!(culled > 100, "{stereo:?}: {culled} culled");
                }
            }
        }
    }

    #[test]
    fn special_cases() {
        let v = right_eye();
        // The eye's circle may lie in the ball.
        assert!(sphere_bounds(&v, DVec3::new(0.0, 0.5, 0.0), 0.48).special);
        assert_eq!(
            sphere_bounds(&v, DVec3::new(0.0, 0.5, 0.0), 0.48).rect,
            Rect::full()
        );
        // Over the camera: a band to the north pole, every longitude.
        let up = sphere_bounds(&v, DVec3::new(0.01, 0.0, 3.0), 0.5);
        assert!(up.special);
        assert_eq!(up.rect.hi.y, FRAC_PI_2);
        assert!(up.rect.hi.x - up.rect.lo.x >= TAU);
        // Meeting the viewing cylinder, not the axis: special only for an eye.
        let s = DVec3::new(0.0, 0.2, 1.0);
        assert!(sphere_bounds(&v, s, 0.18).special);
        let mono = sphere_bounds(&View::mono(Camera::new(DVec3::ZERO, 0.0)), s, 0.18);
        assert!(!mono.special && mono.rect.hi.x - mono.rect.lo.x < TAU);
    }
}
