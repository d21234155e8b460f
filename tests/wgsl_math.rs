//! The WGSL math (`shaders/ods.wgsl`, `pole_merge.wgsl`, `equirect.wgsl`) agrees with the f64
//! Rust functions it mirrors, on random points and angles, for mono and ODS views with each
//! merge profile and both offsets.
//!
//! Tolerances (f32 on the GPU): inputs are the same f32 values on both sides, so the
//! differences are f32 arithmetic only. Angles: 2e-5 rad, 1/80 of a pixel at 3840 wide
//! (1.6e-3 rad/px); a few ulp of atan2/asin of values near 1 plus the fixed point's f32
//! convergence. Ray origins: 1e-6 m (|origin| <= 0.032 m). Directions: 1e-6. Merge factors:
//! 1e-5 (f32 pow/cos of degrees). Points within 1% of the viewing circle may
//! legitimately flip between projectable and not, and their latitude is ill-conditioned in
//! the circle radius; they are skipped (and counted: under 5% of a sample that over-samples the eye region).

mod raster_common;

use glam::DVec3;
use omnicloud::projection::{
    Camera, Eye, OdsOffset, PoleMerge, PoleMerging, Stereo, View, equirect,
};
use omnicloud::render::RenderSettings;
use omnicloud::rng::SplitMix64 as Rng;
use raster_common::rasterizer;

const ANGLE_TOL: f64 = 2e-5;

fn cases() -> Vec<(String, Stereo)> {
    let mut v = vec![("mono".to_string(), Stereo::Mono)];
    for (name, merging) in [
        ("off", PoleMerging::OFF),
        ("marrinan", PoleMerging::both(PoleMerge::COMFORTABLE)),
        ("cycles", PoleMerging::both(PoleMerge::CYCLES_DEFAULT)),
        (
            "cycles/marrinan",
            PoleMerging {
                north: PoleMerge::CYCLES_DEFAULT,
                south: PoleMerge::Marrinan {
                    start_deg: 30.0,
                    end_deg: 10.0,
                    exponent: 1.5,
                },
            },
        ),
    ] {
        for offset in [OdsOffset::Exact, OdsOffset::Paper] {
            v.push((
                format!("{name} {offset:?}"),
                Stereo::Ods {
                    ipd: 0.064,
                    merging,
                    offset,
                },
            ));
        }
    }
    v
}

#[test]
fn wgsl_project_ray_and_merge_match_rust() {
    let Some(raster) = rasterizer() else { return };
    let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 23.0);
    let mut rng = Rng::new(99);
    let n = 4000;
    let mut points = Vec::new();
    let mut angles = Vec::new();
    for k in 0..n {
        // Log-uniform distance 0.01..200 m, uniform on the sphere; some near the axis.
        let d = 10f64.powf(rng.range(-2.0, 2.3));
        let z = rng.range(-1.0, 1.0);
        let z = if k % 10 == 0 { z.signum() * 0.9999 } else { z };
        let a = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
        let s = (1.0 - z * z).sqrt();
        let p = d * DVec3::new(s * a.cos(), s * a.sin(), z);
        points.push(p.as_vec3().to_array());
        angles.push([
            rng.range(-std::f64::consts::PI, std::f64::consts::PI) as f32,
            rng.range(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2) as f32,
        ]);
    }
    let mut worst = [0f64; 4];
    for (name, stereo) in cases() {
        let mut settings = RenderSettings::new(512, camera);
        settings.stereo = stereo;
        for eye in [Eye::Left, Eye::Right] {
            let view = View::eye(camera, &stereo, eye);
            let got = raster
                .probe_math(&view, &settings, &points, &angles)
                .expect("probe");
            let (mut projected, mut skipped) = (0, 0);
            for i in 0..n {
                let p = DVec3::from_array(points[i].map(|x| x as f64));
                let want = view.project(camera.center + p);
                let rho = p.truncate().length();
                // Within 1% of the viewing circle (r/rho > 0.99) phi = atan2(z, sqrt(rho^2 -
                // r^2)) is ill-conditioned in r: f32 cannot match f64 there, nor does it need
                // to (such points are centimetres from the eye).
                let z = p.z;
                let r = view.solve_circle_radius(rho, z).unwrap_or(rho);
                let near_circle = view.offset == OdsOffset::Exact && r >= 0.99 * rho;
                match (want, got[i].projected) {
                    (Some(_), Some(_)) if near_circle => skipped += 1,
                    (Some((wl, wp)), Some((gl, gp))) => {
                        let dl = equirect::wrap_longitude(wl - gl as f64).abs();
                        let dp = (wp - gp as f64).abs();
                        // Near the poles longitude is ill-conditioned: scale it by cos(phi).
                        let dl = dl * wp.cos().max(1e-3);
                        worst[0] = worst[0].max(dl);
                        worst[1] = worst[1].max(dp);
                        assert!(
                            dl <= ANGLE_TOL && dp <= ANGLE_TOL,
                            "{name} {eye:?} point {p:?}: rust ({wl}, {wp}) wgsl ({gl}, {gp})"
                        );
                        projected += 1;
                    }
                    (None, None) => {}
                    _ if near_circle => skipped += 1,
                    (w, g) => panic!("{name} {eye:?} point {p:?}: rust {w:?} wgsl {g:?}"),
                }
                let [lam, phi] = angles[i].map(|x| x as f64);
                let (o, d) = view.ray(lam, phi);
                let go = DVec3::from_array(got[i].ray_origin.map(|x| x as f64));
                let gd = DVec3::from_array(got[i].ray_dir.map(|x| x as f64));
                worst[2] = worst[2].max((o - camera.center - go).length());
                worst[2] = worst[2].max((d - gd).length());
                assert!(
                    (o - camera.center - go).length() <= 1e-6,
                    "{name} ray origin"
                );
                assert!((d - gd).length() <= 1e-6, "{name} ray dir");
                let m = view.merging.factor(phi);
                worst[3] = worst[3].max((m - got[i].merge as f64).abs());
                assert!(
                    (m - got[i].merge as f64).abs() <= 1e-5,
                    "{name} merge at {phi}"
                );
            }
            assert!(projected > n / 2, "{name}: only {projected} projected");
            assert!(
                skipped < n / 20,
                "{name}: {skipped} skipped near the circle"
            );
        }
    }
    eprintln!(
        "worst |dlam|cos(phi) {:.2e}, |dphi| {:.2e}, ray {:.2e}, merge {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}
