//! Tours on the GPU rasterizer: a scene uploaded once renders correctly from camera centres
//! away from the point it was uploaded for (as a tour moves its camera), mono and ODS, and a
//! raster tour's frame is the file `omnicloud render --origin` writes at its pose.

#[path = "raster_common/gpu.rs"]
mod gpu;

use std::process::Command;

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{ColorMode, RenderSettings};
use omnicloud::{Frame, Rendered, Scene};

/// A closed 24 m x 18 m room, 6 m high, walls, floor and ceiling sampled every 0.3 m, spheres of 0.2 m.
fn room() -> Scene {
    let mut pts = Vec::new();
    let (w, d, h, step) = (24.0f32, 18.0f32, 6.0f32, 0.3f32);
    let n = |len: f32| (len / step) as i32;
    for i in 0..=n(w) {
        for j in 0..=n(d) {
            let (x, y) = (i as f32 * step - w / 2.0, j as f32 * step - d / 2.0);
            pts.push(Vec3::new(x, y, 0.0));
            pts.push(Vec3::new(x, y, h));
        }
        for k in 0..=n(h) {
            let (x, z) = (i as f32 * step - w / 2.0, k as f32 * step);
            pts.push(Vec3::new(x, -d / 2.0, z));
            pts.push(Vec3::new(x, d / 2.0, z));
        }
    }
    for j in 0..=n(d) {
        for k in 0..=n(h) {
            let (y, z) = (j as f32 * step - d / 2.0, k as f32 * step);
            pts.push(Vec3::new(-w / 2.0, y, z));
            pts.push(Vec3::new(w / 2.0, y, z));
        }
    }
    // A world far from the file origin, as LiDAR is.
    Scene::new(DVec3::new(636_000.0, 849_000.0, 400.0), pts, 0.2)
}

/// An ODS pair at a 64 mm IPD with comfortable pole merging.
fn ods() -> Stereo {
    Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    }
}

fn eyes(r: &Rendered) -> Vec<&Frame> {
    match r {
        Rendered::Mono(f) => vec![f],
        Rendered::Stereo { left, right } => vec![left, right],
    }
}

/// Fraction of pixels whose coverage and colour agree, and the largest relative depth
/// difference where both hit.
fn agreement(a: &Rendered, b: &Rendered) -> (f64, f64) {
    let (mut same, mut total, mut depth) = (0usize, 0usize, 0.0f64);
    for (fa, fb) in eyes(a).into_iter().zip(eyes(b)) {
        for i in 0..fa.color.len() {
            total += 1;
            if fa.color[i] == fb.color[i] {
                same += 1;
            }
            let (da, db) = (fa.depth[i] as f64, fb.depth[i] as f64);
            if da.is_finite() && db.is_finite() && fa.color[i] == fb.color[i] {
                depth = depth.max((da - db).abs() / da);
            }
        }
    }
    (same as f64 / total as f64, depth)
}

#[test]
fn an_uploaded_scene_renders_from_any_camera_centre() {
    let Some(rasterizer) = gpu::rasterizer() else {
        return;
    };
    let scene = room();
    let hidden = ProgressBar::hidden();
    let at_zero = RenderSettings {
        color: ColorMode::Elevation,
        ..RenderSettings::new(256, Camera::new(DVec3::ZERO, 0.0))
    };
    let resident = rasterizer.upload(&scene, &at_zero).unwrap();
    let ods = ods();
    for (stereo, center, yaw) in [
        (Stereo::Mono, DVec3::new(5.3, -2.1, 1.7), 30.0),
        (ods, DVec3::new(-7.9, 4.4, 1.2), -120.0),
    ] {
        let name = if stereo == Stereo::Mono {
            "mono"
        } else {
            "ods"
        };
        let settings = RenderSettings {
            stereo,
            camera: Camera::new(center, yaw),
            ..at_zero
        };
        // Uploaded relative to the camera itself: the single-render path.
        let own = rasterizer.upload(&scene, &settings).unwrap();
        let (want, _, _) = rasterizer
            .render_uploaded(&own, &settings, &hidden)
            .unwrap();
        // Uploaded once at the room's zero, the camera moved to `center`.
        let (got, _, _) = rasterizer
            .render_uploaded(&resident, &settings, &hidden)
            .unwrap();
        let (same, depth) = agreement(&want, &got);
        eprintln!(
            "{name}: {:.4} % of pixels agree, depth within {depth:.2e}",
            100.0 * same
        );
        assert!(same > 0.999, "{same}");
        assert!(depth < 1e-4, "{depth}");
        // And the camera sees the closed room all around: nearly every pixel is covered.
        let covered = eyes(&got)
            .iter()
            .flat_map(|f| &f.color)
            .filter(|c| c[3] > 0)
            .count();
        assert!(covered as f64 > 0.95 * (256 * 128 * eyes(&got).len()) as f64);

        // The ray tracer likewise: the scene around the camera, or the camera in the scene.
        let traced = omnicloud::raytrace::render(&scene, &settings, &hidden).unwrap();
        let mut centred = scene.clone();
        centred.recenter(scene.origin + center);
        let at_camera = RenderSettings {
            camera: Camera::new(DVec3::ZERO, yaw),
            ..settings
        };
        let traced_centred = omnicloud::raytrace::render(&centred, &at_camera, &hidden).unwrap();
        let (same, _) = agreement(&traced, &traced_centred);
        assert!(same > 0.999, "ray tracer: {same}");
        let (same, depth) = agreement(&traced, &got);
        eprintln!(
            "{name}: raster vs ray tracer {:.3} % of pixels agree, depth within {depth:.2e}",
            100.0 * same
        );
        assert!(
            same > 0.99 && depth < 1e-4,
            "raster vs ray tracer: {same}, {depth}"
        );
    }
}

#[test]
fn a_raster_tour_frame_is_the_file_render_writes_at_its_pose() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_omnicloud"))
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&[
        "tour",
        "data/autzen_trim.laz",
        "--path",
        "data/tours/autzen_walk.csv",
        "-o",
        dir.path().to_str().unwrap(),
        "--frames",
        "2",
        "--width",
        "64",
        "--stereo",
        "ods",
        "--radius",
        "0.3",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && err.contains("no GPU adapter") {
        gpu::require_or_skip(&format!("omnicloud tour found no adapter: {}", err.trim()));
        return;
    }
    assert!(out.status.success(), "{err}");
    assert!(err.contains("points resident on the GPU"), "{err}");
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("tour.json")).unwrap())
            .unwrap();
    let command = m["frames"][1]["command"].as_str().unwrap();
    // No quoting needed: a temporary folder's name is plain.
    let mut words: Vec<String> = command.split(' ').map(str::to_string).collect();
    let o = words.iter().position(|w| w == "-o").unwrap();
    let again = dir.path().join("again.png");
    words[o + 1] = again.display().to_string();
    let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let out = run(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::read(&again).unwrap()
            == std::fs::read(dir.path().join("frame_000001.png")).unwrap(),
        "the raster tour's frame 1 differs from `omnicloud render` at its pose"
    );
}

#[test]
fn a_scene_streamed_every_frame_renders_as_the_resident_upload() {
    use omnicloud::render::RendererKind;
    use omnicloud::renderer::Resident;
    let Some(rasterizer) = gpu::rasterizer() else {
        return;
    };
    let scene = room();
    let hidden = ProgressBar::hidden();
    let at_zero = RenderSettings {
        color: ColorMode::Elevation,
        ..RenderSettings::new(256, Camera::new(DVec3::ZERO, 0.0))
    };
    let resident = Resident::new(&scene, RendererKind::Raster, &at_zero).unwrap();
    assert!(!resident.is_streamed());
    let streamed =
        Resident::streamed(Box::new(rasterizer), &scene, &at_zero, "forced".into()).unwrap();
    assert!(streamed.is_streamed());
    assert!(
        streamed.describe().starts_with("warning: "),
        "{}",
        streamed.describe()
    );
    let ods = ods();
    for (stereo, center, yaw) in [
        (Stereo::Mono, DVec3::new(5.3, -2.1, 1.7), 30.0),
        (ods, DVec3::new(-7.9, 4.4, 1.2), -120.0),
    ] {
        let settings = RenderSettings {
            stereo,
            camera: Camera::new(center, yaw),
            ..at_zero
        };
        let want = resident.render(&settings, &hidden).unwrap();
        let got = streamed.render(&settings, &hidden).unwrap();
        let (same, depth) = agreement(&want, &got);
        eprintln!(
            "streamed: {:.4} % agree, depth within {depth:.2e}",
            100.0 * same
        );
        assert!(same > 0.999, "{same}");
        assert!(depth < 1e-5, "{depth}");
    }
}

#[test]
fn a_resident_placed_at_each_camera_renders_as_the_upload_for_that_camera() {
    use omnicloud::render::RendererKind;
    use omnicloud::renderer::{Anchor, Resident, ResidentError};
    let Some(rasterizer) = gpu::rasterizer() else {
        return;
    };
    let scene = room();
    let hidden = ProgressBar::hidden();
    let at = |center: DVec3| RenderSettings {
        color: ColorMode::Elevation,
        stereo: ods(),
        ..RenderSettings::new(256, Camera::new(center, 0.0))
    };
    // What serve did with its own upload per camera position.
    let uploaded_for = |settings: &RenderSettings| {
        let own = rasterizer.upload(&scene, settings).unwrap();
        rasterizer
            .render_uploaded(&own, settings, &hidden)
            .unwrap()
            .0
    };
    let (first, second) = (
        at(DVec3::new(6.1, 3.3, 1.7)),
        at(DVec3::new(-8.2, -5.4, 2.9)),
    );
    let mut resident = Resident::anchored(
        &scene,
        RendererKind::Raster,
        &first,
        Anchor::Camera(first.camera.center),
    )
    .unwrap();
    assert!(
        resident
            .describe()
            .contains(" points resident on the GPU (")
    );
    assert_eq!(resident.device(), rasterizer.adapter_name());
    assert_eq!(
        resident.max_image_width(),
        Some(rasterizer.max_image_width())
    );
    let got = resident.render(&first, &hidden).unwrap();
    assert!(got == uploaded_for(&first), "first camera differs");
    assert!(eyes(&got)[0].coverage_count() > 256 * 128 * 9 / 10);
    resident.recycle(got);

    resident
        .place(Anchor::Camera(second.camera.center))
        .unwrap();
    assert!(
        resident.render(&second, &hidden).unwrap() == uploaded_for(&second),
        "re-placed camera differs"
    );
    // Released points render nothing until placed again, at the same camera.
    resident.release();
    assert!(matches!(
        resident.render(&second, &hidden),
        Err(ResidentError::NotPlaced)
    ));
    resident
        .place(Anchor::Camera(second.camera.center))
        .unwrap();
    assert!(resident.render(&second, &hidden).unwrap() == uploaded_for(&second));
}
