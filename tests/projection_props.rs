//! Property tests for the camera/ODS math (DESIGN §2–4): the exact inverse returns every ray
//! point to the pixel it came from, at every latitude and longitude, for every eye and profile.

mod projection_strategies;

use std::f64::consts::TAU;

use glam::DVec3;
use omnicloud::projection::{Camera, Equirect, Eye, PoleMerge, View};
use projection_strategies::{CENTRE, eye, eye_view, profile};
use proptest::prelude::*;

const WIDTH: u32 = 3840;

/// Image rows: anywhere, or within 1° of either pole (1° is 10.67 rows at 1920 rows).
fn row() -> impl Strategy<Value = f64> {
    let h = WIDTH as f64 / 2.0;
    let polar = h / 180.0;
    prop_oneof![0.5..h - 0.5, 0.5..polar, h - polar..h - 0.5,]
}

/// Image columns: anywhere, or within two pixels of the seam on either side.
fn column() -> impl Strategy<Value = f64> {
    let w = WIDTH as f64;
    prop_oneof![0.0..w, 0.0..2.0, w - 2.0..w]
}

fn view(eye: Option<Eye>, north: PoleMerge, south: PoleMerge, ipd: f64, yaw: f64) -> View {
    eye_view(Camera::new(CENTRE, yaw), eye, north, south, ipd)
}

/// Horizontal pixel distance, across the seam where shorter.
fn column_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(WIDTH as f64 - d)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn forward_then_inverse_returns_to_the_pixel(
        x in column(), y in row(), eye in eye(),
        north in profile(), south in profile(),
        ipd in 0.01..0.5f64, yaw in -360.0..360.0f64,
        log_t in -1.0..4.0f64,
    ) {
        let image = Equirect::from_width(WIDTH);
        let v = view(eye, north, south, ipd, yaw);
        let (lam, phi) = image.angles_of_position(x, y);
        let (origin, dir) = v.ray(lam, phi);
        let p = origin + 10f64.powf(log_t) * dir;
        let (x2, y2) = v.project_to_image(&image, p).expect("a point on a ray projects");
        prop_assert!(column_distance(x, x2) < 1e-3, "x {} -> {}", x, x2);
        prop_assert!((y - y2).abs() < 1e-3, "y {} -> {}", y, y2);
    }

    #[test]
    fn points_inside_the_viewing_circle_are_unprojectable_never_nan(
        eye in prop_oneof![Just(Eye::Left), Just(Eye::Right)],
        angle in 0.0..TAU, frac in 0.0..0.999f64, z in -1.0..1.0f64,
        north in profile(), south in profile(), ipd in 0.01..0.5f64,
    ) {
        let v = view(Some(eye), north, south, ipd, 0.0);
        let rho = frac * ipd / 2.0;
        let p = v.camera.center + DVec3::new(rho * angle.cos(), rho * angle.sin(), z * 1e-3);
        match v.project(p) {
            None => {
                // Unprojectable exactly when no radius r <= rho solves the fixed point.
                let phi_edge = if p.z == v.camera.center.z { 0.0 } else { (p.z - v.camera.center.z).signum() * std::f64::consts::FRAC_PI_2 };
                prop_assert!(v.circle_radius(phi_edge) > rho);
            }
            Some((lam, phi)) => {
                prop_assert!(lam.is_finite() && phi.is_finite());
                // Projectable only where merging shrank the circle: the ray of the pixel it
                // lands on passes through the point (to 1 nm), in front of its origin.
                let (origin, dir) = v.ray(lam, phi);
                let t = (p - origin).dot(dir);
                prop_assert!(t > 0.0);
                prop_assert!((origin + t * dir - p).length() < 1e-9, "miss {}", (origin + t * dir - p).length());
            }
        }
    }
}

#[test]
fn unmerged_points_inside_the_circle_are_always_culled() {
    let v = view(Some(Eye::Left), PoleMerge::Off, PoleMerge::Off, 0.064, 0.0);
    for k in 0..1000 {
        let a = k as f64 * 0.1;
        let p = DVec3::new(
            3.0 + 0.03 * a.cos(),
            -2.0 + 0.03 * a.sin(),
            1.5 + (k as f64 - 500.0),
        );
        assert!(v.project(p).is_none());
    }
}
