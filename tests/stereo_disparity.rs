//! Angular disparity (DESIGN §9) of the stereo methods, ray traced: exact ODS gives
//! `2 asin(r/rho)`; parallel cameras and Trapp's cube maps agree with ODS straight ahead and
//! lose all depth sideways; cube maps converge to parallel cameras as their faces grow.

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::compare::rendered_disparity::left_eye_disparity;
use omnicloud::output::disparity_exr::{read_disparity_exr, write_disparity_exr};
use omnicloud::projection::disparity::ARCMIN_PER_RADIAN;
use omnicloud::projection::disparity_image::DisparityImage;
use omnicloud::projection::{Camera, Eye, OdsOffset, PoleMerging, Stereo, View};
use omnicloud::raytrace;
use omnicloud::render::RenderSettings;
use omnicloud::render::hit_points::hit_point;
use omnicloud::scene::Scene;

const IPD: f64 = 0.064;
const RADIUS: f32 = 0.2;

fn ods() -> Stereo {
    Stereo::Ods {
        ipd: IPD,
        merging: PoleMerging::OFF,
        offset: OdsOffset::Exact,
    }
}

/// Spheres 5 m ahead, right and left of a camera at the origin looking along +Y.
fn three_spheres() -> Scene {
    Scene::new(
        DVec3::ZERO,
        vec![
            Vec3::new(0.0, 5.0, 0.0),
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(-5.0, 0.0, 0.0),
        ],
        RADIUS,
    )
}

fn settings(width: u32, stereo: Stereo) -> RenderSettings {
    let mut s = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
    s.stereo = stereo;
    s
}

fn disparity(scene: &Scene, s: &RenderSettings) -> DisparityImage {
    let rendered = raytrace::render(scene, s, &ProgressBar::hidden()).unwrap();
    left_eye_disparity(&rendered, s, &s.image, None)
}

/// Horizontal disparity at the pixel looking at longitude `lam_deg` on the horizon.
fn dh_at(img: &DisparityImage, lam_deg: f64) -> f64 {
    let i = ((lam_deg / 360.0 + 0.5) * f64::from(img.width)) as u32;
    f64::from(img.dh[img.index(i, img.height / 2)])
}

#[test]
fn ods_disparity_of_a_sphere_is_two_asin_r_over_rho() {
    let scene = three_spheres();
    let s = settings(1024, ods());
    let rendered = raytrace::render(&scene, &s, &ProgressBar::hidden()).unwrap();
    let img = left_eye_disparity(&rendered, &s, &s.image, None);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.exr");
    write_disparity_exr(&path, &img).unwrap();
    let back = read_disparity_exr(&path).unwrap();
    assert_eq!(back.dh.len(), img.dh.len());

    // Every covered pixel: the surface point it sees, at horizontal distance rho.
    let left = View::eye(s.camera, &s.stereo, Eye::Left);
    let frame = rendered.frames()[0];
    let mut worst = 0.0f64;
    let mut covered = 0;
    for j in 0..frame.height {
        for i in 0..frame.width {
            let Some(p) = hit_point(frame, &left, &s.image, i, j) else {
                continue;
            };
            covered += 1;
            let rho = p.truncate().length();
            let want = 2.0 * (0.5 * IPD / rho).asin() * ARCMIN_PER_RADIAN;
            let got = f64::from(back.dh[back.index(i, j)]);
            worst = worst.max((got / want - 1.0).abs());
        }
    }
    eprintln!("{covered} pixels: worst relative error {worst:.2e}");
    assert!(covered > 150, "{covered}");
    assert!(worst < 2e-7, "{worst}");
    // The pixel straight ahead sees the sphere's front, 4.8 m away.
    let ahead = dh_at(&back, 0.0);
    let want = 2.0 * (0.032f64 / 4.8).asin() * ARCMIN_PER_RADIAN;
    assert!((ahead / want - 1.0).abs() < 0.005, "{ahead} vs {want}");
}

#[test]
fn parallel_and_cube_maps_match_ods_ahead_and_lose_depth_sideways() {
    let scene = three_spheres();
    let reference = disparity(&scene, &settings(1024, ods()));
    let ahead = dh_at(&reference, 0.0);
    let side = dh_at(&reference, 90.0);
    eprintln!("ods: ahead {ahead:.3}, sideways {side:.3} arcmin");
    assert!(side > 40.0, "ODS keeps its depth sideways: {side}");
    for stereo in [
        Stereo::Parallel { ipd: IPD },
        Stereo::Cubemap {
            ipd: IPD,
            face: 512,
        },
    ] {
        let img = disparity(&scene, &settings(1024, stereo));
        let (a, r, l) = (dh_at(&img, 0.0), dh_at(&img, 90.0), dh_at(&img, -90.0));
        eprintln!(
            "{}: ahead {a:.3}, right {r:.4}, left {l:.4} arcmin",
            stereo.kind()
        );
        assert!((a / ahead - 1.0).abs() < 0.01, "{a} vs ODS {ahead}");
        assert!(r.abs() <= 0.5 && l.abs() <= 0.5, "{r} {l}");
    }
}

#[test]
fn cube_maps_converge_to_parallel_cameras() {
    // A ring of spheres at 2-12 m around the camera, some above and below the horizon.
    let positions: Vec<Vec3> = (0..240)
        .map(|k| {
            let a = k as f32 * 0.41;
            let d = 2.0 + (k % 11) as f32;
            Vec3::new(d * a.sin(), d * a.cos(), ((k % 7) as f32 - 3.0) * 0.6)
        })
        .collect();
    let scene = Scene::new(DVec3::ZERO, positions, 0.15);
    let parallel = disparity(&scene, &settings(512, Stereo::Parallel { ipd: IPD }));
    let mut errors = Vec::new();
    for face in [256, 512, 1024] {
        let img = disparity(&scene, &settings(512, Stereo::Cubemap { ipd: IPD, face }));
        let (mut sum, mut n) = (0.0f64, 0usize);
        for (a, b) in img.dh.iter().zip(&parallel.dh) {
            if a.is_finite() && b.is_finite() {
                sum += f64::from((a - b).abs());
                n += 1;
            }
        }
        let mean = sum / n as f64;
        eprintln!("cubemap:{face}: mean |dh - parallel| {mean:.4} arcmin over {n} px");
        errors.push(mean);
    }
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 0.03, "{errors:?}");
}

fn omnicloud(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env_remove("OMNICLOUD_PROGRESS")
        .output()
        .unwrap()
}

#[test]
fn render_writes_the_disparity_and_says_how_comfortable_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("d.exr");
    let png = dir.path().join("p.png");
    let base = [
        "render",
        "data/autzen_trim.laz",
        "--renderer",
        "raytrace",
        "--width",
        "128",
    ];
    let out = omnicloud(
        &[
            &base[..],
            &[
                "-o",
                png.to_str().unwrap(),
                "--disparity",
                d.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("measure two eyes"),
        "{err}"
    );
    let out = omnicloud(
        &[
            &base[..],
            &[
                "-o",
                png.to_str().unwrap(),
                "--stereo",
                "ods",
                "--disparity",
            ],
            &[d.to_str().unwrap(), "--comfort-near", "30"],
        ]
        .concat(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("nearer than 30 m") && err.contains("disparity gradient"),
        "{err}"
    );
    let img = read_disparity_exr(&d).unwrap();
    assert_eq!((img.width, img.height), (128, 64));
    assert!(img.covered_count() > 2000, "{}", img.covered_count());
}

#[test]
fn bench_charts_the_stereo_methods() {
    let dir = tempfile::tempdir().unwrap();
    let out = omnicloud(&[
        "bench",
        "data/autzen_trim.laz",
        "--stereo-methods",
        "--width",
        "64",
        "--cubemap-faces",
        "32,64",
        "--out",
        dir.path().to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in [
        "disparity_error_longitude.png",
        "disparity_error_longitude.svg",
        "disparity_error_latitude.png",
        "disparity_error_latitude.svg",
    ] {
        assert!(
            std::fs::metadata(dir.path().join(f)).unwrap().len() > 10_000,
            "{f}"
        );
    }
    let md = std::fs::read_to_string(dir.path().join("stereo_methods.md")).unwrap();
    for m in [
        "ods paper offset",
        "parallel",
        "cubemap:32",
        "cubemap:64 vs parallel",
    ] {
        assert!(md.contains(m), "{m}: {md}");
    }
}

#[test]
fn a_depth_map_caps_the_disparity_image_at_its_nearest_perceived_distance() {
    // Spheres from 0.3 m to 20 m ahead and around.
    let positions: Vec<Vec3> = (0..60)
        .map(|k| {
            let d = 0.3 + 0.33 * k as f32;
            let a = k as f32 * 0.7;
            Vec3::new(d * a.sin(), d * a.cos(), 0.05 * (k % 5) as f32 - 0.1)
        })
        .collect();
    let scene = Scene::new(DVec3::ZERO, positions, 0.04);
    let mut s = settings(512, ods());
    let plain = disparity(&scene, &s);
    s.depth_map = Some("0.5=1.5".parse().unwrap());
    let mapped = disparity(&scene, &s);
    let max = |img: &DisparityImage| {
        img.dh
            .iter()
            .filter(|d| d.is_finite())
            .fold(0.0f64, |m, d| m.max(f64::from(*d)))
    };
    let cap = 2.0 * (0.032f64 / 1.5).asin() * ARCMIN_PER_RADIAN;
    eprintln!(
        "largest disparity: plain {:.2}, mapped {:.3}, cap {cap:.3} arcmin",
        max(&plain),
        max(&mapped)
    );
    assert!(max(&plain) > 3.0 * cap);
    assert!(max(&mapped) <= cap * (1.0 + 1e-5), "{}", max(&mapped));
    assert!(max(&mapped) >= cap * (1.0 - 1e-3), "{}", max(&mapped));
}
