//! The ray tracer against analytic scenes: sphere sizes and positions, ODS disparity, pole
//! merging, the seam, the poles, and cameras inside spheres or spheres inside the viewing
//! circle.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::projection::{Camera, Eye, OdsOffset, PoleMerge, PoleMerging, Stereo, View};
use omnicloud::raytrace::render;
use omnicloud::render::RenderSettings;
use omnicloud::{Frame, Rendered, Scene};

fn mono(scene: &Scene, width: u32, camera: Camera) -> Frame {
    let settings = RenderSettings::new(width, camera);
    match render(scene, &settings, &ProgressBar::hidden()).unwrap() {
        Rendered::Mono(f) => f,
        other => panic!("expected mono, got {} frames", other.frames().len()),
    }
}

fn ods(scene: &Scene, width: u32, camera: Camera, stereo: Stereo) -> (Frame, Frame) {
    let mut settings = RenderSettings::new(width, camera);
    settings.stereo = stereo;
    match render(scene, &settings, &ProgressBar::hidden()).unwrap() {
        Rendered::Stereo { left, right } => (left, right),
        _ => panic!("expected stereo"),
    }
}

fn ods_stereo(ipd: f64, merging: PoleMerging) -> Stereo {
    Stereo::Ods {
        ipd,
        merging,
        offset: OdsOffset::Exact,
    }
}

/// Covered pixels of row `j`, as (first, last) column of the single run, or `None`.
fn row_run(f: &Frame, j: u32) -> Option<(u32, u32)> {
    let cols: Vec<u32> = (0..f.width).filter(|&i| f.covered(i, j)).collect();
    let (first, last) = (*cols.first()?, *cols.last()?);
    assert_eq!(cols.len() as u32, last - first + 1, "row {j} run has holes");
    Some((first, last))
}

fn col_run(f: &Frame, i: u32) -> Option<(u32, u32)> {
    let rows: Vec<u32> = (0..f.height).filter(|&j| f.covered(i, j)).collect();
    let (first, last) = (*rows.first()?, *rows.last()?);
    assert_eq!(
        rows.len() as u32,
        last - first + 1,
        "column {i} run has holes"
    );
    Some((first, last))
}

/// Coverage centroid (x, y) in pixel coordinates (pixel centres at +0.5) over rows `rows`.
fn centroid(f: &Frame, rows: std::ops::Range<u32>) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for j in rows {
        for i in 0..f.width {
            if f.covered(i, j) {
                sx += i as f64 + 0.5;
                sy += j as f64 + 0.5;
                n += 1.0;
            }
        }
    }
    assert!(n > 0.0, "nothing covered");
    (sx / n, sy / n)
}

#[test]
fn sphere_ahead_is_centred_with_angular_radius_asin_r_over_d() {
    let yaw = 30.0;
    let camera = Camera::new(DVec3::new(1.0, -2.0, 0.5), yaw);
    let (d, r) = (5.0f64, 0.5f64);
    let center = camera.center + d * camera.basis().forward;
    let scene = Scene::new(DVec3::ZERO, vec![center.as_vec3()], r as f32);
    let w = 1024u32;
    let f = mono(&scene, w, camera);
    let h = f.height;
    let alpha = (r / d).asin();
    let px = TAU / w as f64;

    // Centre row j = h/2 - 1 (latitude +half a pixel), centre column i = w/2.
    let j = h / 2 - 1;
    let phi = (0.5 - (j as f64 + 0.5) / h as f64) * PI;
    let half_lon = (alpha.cos() / phi.cos()).acos();
    let (first, last) = row_run(&f, j).unwrap();
    let measured = (last - first + 1) as f64;
    let expect = 2.0 * half_lon / px;
    assert!(
        (measured - expect).abs() <= 1.0,
        "row run {measured} px, expect {expect:.2}"
    );
    let mid = 0.5 * (first as f64 + last as f64 + 1.0);
    assert!((mid - w as f64 / 2.0).abs() <= 0.5, "row centre {mid}");

    let i = w / 2;
    let lam = ((i as f64 + 0.5) / w as f64 - 0.5) * TAU;
    let half_lat = (alpha.cos() / lam.cos()).acos();
    let (first, last) = col_run(&f, i).unwrap();
    let measured = (last - first + 1) as f64;
    let expect = 2.0 * half_lat / (PI / h as f64);
    assert!(
        (measured - expect).abs() <= 1.0,
        "column run {measured} px, expect {expect:.2}"
    );
    let mid = 0.5 * (first as f64 + last as f64 + 1.0);
    assert!((mid - h as f64 / 2.0).abs() <= 0.5, "column centre {mid}");

    // Depth at the pixel nearest the centre, against the analytic chord (relative 1e-6).
    let view = View::mono(camera);
    let (o, dir) = view.pixel_ray(&omnicloud::projection::Equirect::from_width(w), i, j);
    let oc = center - o;
    let b = dir.dot(oc);
    let expect = b - (r * r - (oc.length_squared() - b * b)).sqrt();
    let got = f.depth[f.index(i, j)] as f64;
    assert!(
        (got - expect).abs() <= 1e-6 * expect,
        "depth {got} expect {expect}"
    );
    assert_eq!(
        f.coverage_count(),
        f.depth.iter().filter(|d| d.is_finite()).count()
    );
}

#[test]
fn ods_disparity_of_a_point_ahead_is_twice_asin_half_ipd_over_rho() {
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let (ipd, rho) = (1.0f64, 4.0f64);
    let scene = Scene::new(DVec3::ZERO, vec![Vec3::new(0.0, rho as f32, 0.0)], 0.1);
    let w = 1024u32;
    let (left, right) = ods(&scene, w, camera, ods_stereo(ipd, PoleMerging::OFF));
    let h = left.height;
    let (xl, yl) = centroid(&left, 0..h);
    let (xr, yr) = centroid(&right, 0..h);
    let px = TAU / w as f64;
    let disparity = (xl - xr) * px;
    let expect = 2.0 * (0.5 * ipd / rho).asin();
    assert!(
        (disparity - expect).abs() <= px,
        "disparity {:.3} px, expect {:.3} px",
        disparity / px,
        expect / px
    );
    // Each eye is where the exact inverse puts the centre; the right eye sees it left.
    let image = omnicloud::projection::Equirect::from_width(w);
    for (eye, x, y) in [(Eye::Left, xl, yl), (Eye::Right, xr, yr)] {
        let view = View::eye(camera, &ods_stereo(ipd, PoleMerging::OFF), eye);
        let (ex, ey) = view
            .project_to_image(&image, DVec3::new(0.0, rho, 0.0))
            .unwrap();
        assert!(
            (x - ex).abs() < 0.5 && (y - ey).abs() < 0.5,
            "{eye:?} ({x},{y}) vs ({ex},{ey})"
        );
    }
    assert!(xr < w as f64 / 2.0 && xl > w as f64 / 2.0);
}

/// Disparity (radians) of a small sphere at distance `dist` and elevation `elev` seen from
/// C, for both eyes, and the latitude it appears at.
fn disparity_at(merging: PoleMerging, elev: f64, dist: f64) -> (f64, f64, Frame, Frame) {
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let p = DVec3::new(0.0, dist * elev.cos(), dist * elev.sin());
    let scene = Scene::new(DVec3::ZERO, vec![p.as_vec3()], 0.06);
    let w = 1024u32;
    let (left, right) = ods(&scene, w, camera, ods_stereo(1.0, merging));
    let h = left.height;
    let (xl, yl) = centroid(&left, 0..h);
    let (xr, yr) = centroid(&right, 0..h);
    let phi = (0.5 - 0.5 * (yl + yr) / h as f64) * PI;
    ((xl - xr) * TAU / w as f64, phi, left, right)
}

#[test]
fn pole_merging_shrinks_disparity_by_the_profile_factor_and_ends_it_past_the_end_angle() {
    let px = TAU / 1024.0;
    let marrinan = PoleMerge::Marrinan {
        start_deg: 45.0,
        end_deg: 20.0,
        exponent: 1.0,
    };
    for (profile, mid_deg, end_deg) in [
        (marrinan, 57.5, 70.0),
        (PoleMerge::CYCLES_DEFAULT, 67.5, 75.0),
    ] {
        let merging = PoleMerging::both(profile);
        let dist = 3.0;
        for sign in [1.0, -1.0] {
            let elev = sign * f64::to_radians(mid_deg);
            let (disparity, phi, _, _) = disparity_at(merging, elev, dist);
            let rho = dist * elev.cos();
            let factor = merging.factor(phi);
            assert!(factor > 0.2 && factor < 0.9, "{profile:?} factor {factor}");
            let expect = 2.0 * (0.5 * factor / rho).asin();
            assert!(
                (disparity - expect).abs() <= px,
                "{profile:?} at {:.2}°: disparity {:.2} px, expect {:.2} px",
                phi.to_degrees(),
                disparity / px,
                expect / px
            );
            // Without merging the same point is clearly farther apart.
            let (unmerged, _, _, _) = disparity_at(PoleMerging::OFF, elev, dist);
            assert!(
                unmerged - disparity > 5.0 * px,
                "{profile:?}: merging had no effect"
            );
        }
        // Beyond the end angle both eyes' rays coincide: identical rows.
        let elev = f64::to_radians(end_deg + 6.0);
        let (disparity, _, left, right) = disparity_at(merging, elev, dist);
        assert!(disparity.abs() < 1e-9, "{profile:?}: disparity {disparity}");
        let h = left.height;
        let last_row = ((0.5 - f64::to_radians(end_deg) / PI) * h as f64).floor() as usize - 1;
        let n = last_row * left.width as usize;
        assert!(left.color[..n].iter().any(|c| c[3] != 0));
        assert_eq!(left.color[..n], right.color[..n]);
        assert_eq!(left.depth[..n], right.depth[..n]);
    }
}

#[test]
fn sphere_behind_appears_at_both_edges() {
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let scene = Scene::new(DVec3::ZERO, vec![Vec3::new(0.0, -5.0, 0.0)], 0.4);
    let f = mono(&scene, 512, camera);
    let j = f.height / 2;
    assert!(f.covered(0, j) && f.covered(f.width - 1, j));
    assert!(!f.covered(f.width / 2, j));
    // Symmetric about the seam: as many covered columns on each side.
    let left = (0..f.width / 2).filter(|&i| f.covered(i, j)).count();
    let right = (f.width / 2..f.width).filter(|&i| f.covered(i, j)).count();
    assert_eq!(left, right);
    // Half the disc: asin(r/d) of longitude, 6.5 columns at 512 wide.
    let half = (0.4f64 / 5.0).asin().to_degrees() * f.width as f64 / 360.0;
    assert!(
        (left as f64 - half).abs() <= 1.0,
        "{left} columns, expect {half:.2}"
    );
}

#[test]
fn sphere_over_a_pole_fills_the_polar_rows() {
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let (d, r) = (3.0f64, 0.5f64);
    let w = 512u32;
    for up in [1.0f64, -1.0] {
        let scene = Scene::new(
            DVec3::ZERO,
            vec![Vec3::new(0.0, 0.0, (up * d) as f32)],
            r as f32,
        );
        let f = mono(&scene, w, camera);
        let h = f.height;
        let edge = FRAC_PI_2 - (r / d).asin();
        for j in 0..h {
            let phi = up * (0.5 - (j as f64 + 0.5) / h as f64) * PI;
            let covered = (0..w).filter(|&i| f.covered(i, j)).count() as u32;
            if phi > edge + 1e-9 {
                assert_eq!(covered, w, "row {j} (phi {phi}) should be full");
            } else if phi < edge - 1e-9 {
                assert_eq!(covered, 0, "row {j} (phi {phi}) should be empty");
            }
        }
        let top = if up > 0.0 { 0 } else { h - 1 };
        let depth = f.depth[f.index(0, top)] as f64;
        assert!((depth - (d - r)).abs() < 1e-4 * d, "polar depth {depth}");
    }
}

#[test]
fn camera_inside_a_sphere_sees_its_inside_surface_everywhere() {
    let center = DVec3::new(0.3, 0.2, 0.1);
    let r = 2.0;
    let scene = Scene::new(DVec3::ZERO, vec![center.as_vec3()], r as f32);
    let camera = Camera::new(DVec3::ZERO, 10.0);
    let frames = {
        let (l, r) = ods(&scene, 256, camera, ods_stereo(0.5, PoleMerging::OFF));
        vec![mono(&scene, 256, camera), l, r]
    };
    let image = omnicloud::projection::Equirect::from_width(256);
    let views = [
        View::mono(camera),
        View::eye(camera, &ods_stereo(0.5, PoleMerging::OFF), Eye::Left),
        View::eye(camera, &ods_stereo(0.5, PoleMerging::OFF), Eye::Right),
    ];
    for (f, view) in frames.iter().zip(views) {
        assert_eq!(f.coverage_count(), f.color.len());
        for j in 0..f.height {
            for i in 0..f.width {
                let (o, d) = view.pixel_ray(&image, i, j);
                let oc = o - center;
                let b = d.dot(oc);
                let far = -b + (b * b - (oc.length_squared() - r * r)).sqrt();
                let got = f.depth[f.index(i, j)] as f64;
                assert!((got - far).abs() <= 1e-6 * far, "({i},{j}) {got} vs {far}");
            }
        }
    }
}

#[test]
fn spheres_inside_the_viewing_circle_never_produce_nan() {
    // Points at and inside the 0.5 m viewing circle, one on the camera itself.
    let pts = vec![
        Vec3::ZERO,
        Vec3::new(0.2, 0.1, 0.0),
        Vec3::new(-0.5, 0.0, 0.0),
        Vec3::new(0.0, 0.5, 0.3),
        Vec3::new(0.0, 0.0, 0.4),
    ];
    let scene = Scene::new(DVec3::ZERO, pts, 0.05);
    let merging = PoleMerging::both(PoleMerge::COMFORTABLE);
    for m in [PoleMerging::OFF, merging] {
        let (l, r) = ods(
            &scene,
            512,
            Camera::new(DVec3::ZERO, 0.0),
            ods_stereo(1.0, m),
        );
        for f in [&l, &r] {
            assert!(f.depth.iter().all(|d| !d.is_nan() && *d > 0.0));
            for (c, d) in f.color.iter().zip(&f.depth) {
                assert_eq!(c[3] == 255, d.is_finite());
            }
            assert!(f.coverage_count() > 0);
        }
    }
}
