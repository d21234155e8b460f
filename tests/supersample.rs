//! `--supersample N`: a constant scene gives the plain render, colours mix in linear light,
//! both renderers agree, and the command line reduces the streamed raster render too.

mod raster_common;

use std::process::Command;

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::output::{self, Layout};
use omnicloud::projection::{Camera, Image};
use omnicloud::render::{Background, ColorMode, Look, RenderSettings};
use omnicloud::{Frame, Rendered, Scene, raytrace};

fn look(n: u32) -> Look {
    Look {
        supersample: n,
        ..Look::default()
    }
}

/// `settings` drawn `n` times wider, then reduced.
fn supersampled(scene: &Scene, settings: &RenderSettings, n: u32) -> Rendered {
    let look = look(n);
    let wide = RenderSettings {
        image: look.render_image(&settings.image).unwrap(),
        ..*settings
    };
    look.finish(raytrace::render(scene, &wide, &ProgressBar::hidden()).unwrap())
}

fn mono(r: &Rendered) -> &Frame {
    match r {
        Rendered::Mono(f) => f,
        Rendered::Stereo { .. } => panic!("stereo"),
    }
}

#[test]
fn a_constant_scene_supersampled_is_the_plain_render() {
    // The camera at the centre of one sphere: every ray hits it 5 m away, in one colour.
    let scene = Scene::new(DVec3::ZERO, vec![Vec3::ZERO], 5.0);
    let settings = RenderSettings::new(128, Camera::new(DVec3::ZERO, 0.0));
    let plain = raytrace::render(&scene, &settings, &ProgressBar::hidden()).unwrap();
    for n in [2, 3] {
        let s = supersampled(&scene, &settings, n);
        let (s, p) = (mono(&s), mono(&plain));
        assert_eq!((s.width, s.height), (128, 64));
        assert_eq!(s.color, p.color, "N = {n}");
        let worst = s
            .depth
            .iter()
            .zip(&p.depth)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-5, "depth differs by {worst} m");
    }
}

#[test]
fn a_half_covered_white_pixel_over_black_is_srgb_188() {
    // Every other column white, the rest background: each 2 x 2 block is half covered.
    let mut wide = Frame::new(32, 16);
    for j in 0..16 {
        for i in (0..32).step_by(2) {
            let k = wide.index(i, j);
            wide.color[k] = [255, 255, 255, 255];
            wide.depth[k] = 2.0;
        }
    }
    let reduced = look(2).finish(Rendered::Mono(wide.clone()));
    assert!(
        mono(&reduced)
            .color
            .iter()
            .all(|&c| c == [255, 255, 255, 128])
    );
    // Written as a JPEG (laid over black): linear 0.5, not sRGB 128.
    let dir = tempfile::tempdir().unwrap();
    let jpg = dir.path().join("half.jpg");
    output::write_image(&jpg, &reduced, Layout::TopBottom).unwrap();
    let img = image::open(&jpg).unwrap().into_rgb8();
    let mean = img.pixels().map(|p| p[1] as f64).sum::<f64>() / img.len() as f64 * 3.0;
    assert!((mean - 188.0).abs() < 2.0, "JPEG grey {mean}");
    // With a black background: exactly 188.
    let black = Look {
        background: Some(Background::Color([0, 0, 0])),
        ..look(2)
    }
    .finish(Rendered::Mono(wide));
    assert!(
        mono(&black)
            .color
            .iter()
            .all(|&c| c == [188, 188, 188, 255])
    );
}

#[test]
fn the_sample_supersampled_keeps_its_silhouette_and_both_renderers_agree() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");
    let (mut scene, _) = omnicloud::io::load_scene(path.as_ref(), &Default::default()).unwrap();
    omnicloud::prepare::placement::center_on_camera(
        &mut scene,
        omnicloud::prepare::CameraChoice::Center,
        Default::default(),
    )
    .unwrap();
    scene.radii = omnicloud::Radii::Uniform(omnicloud::prepare::radius::auto_radius(&scene));
    let mut settings = RenderSettings::new(128, Camera::new(DVec3::ZERO, 0.0));
    settings.color = ColorMode::Rgb;
    let plain = raytrace::render(&scene, &settings, &ProgressBar::hidden()).unwrap();
    let cpu = supersampled(&scene, &settings, 2);
    let (p, s) = (mono(&plain), mono(&cpu));
    // Pixels at least half covered are about as many as the plain render covers (measured
    // 1.071 at this width: 4 samples find more of the sub-pixel spheres one sample misses).
    let half = |f: &Frame| f.color.iter().filter(|c| c[3] >= 128).count() as f64;
    let ratio = half(s) / half(p);
    assert!((1.0..1.12).contains(&ratio), "covered share ratio {ratio}");
    // Silhouettes are anti-aliased: some pixels are partly covered.
    let partial = s.color.iter().filter(|c| (1..255).contains(&c[3])).count();
    assert!(partial > 100, "{partial} partial pixels");
    // Depth is the nearest sample's. With N = 3 the pixel's centre is one of the samples, so
    // the depth is never farther than the plain render's.
    let three = supersampled(&scene, &settings, 3);
    let nearer = mono(&three)
        .depth
        .iter()
        .zip(&p.depth)
        .filter(|(s, p)| **s < **p * (1.0 - 1e-6))
        .count();
    assert!(
        nearer > 100,
        "{nearer} pixels nearer than the centre sample"
    );
    assert!(
        mono(&three)
            .depth
            .iter()
            .zip(&p.depth)
            .all(|(s, p)| !p.is_finite() || *s <= *p * (1.0 + 1e-6))
    );

    let Some(raster) = raster_common::rasterizer() else {
        return;
    };
    let wide = RenderSettings {
        image: Image::equirect(256),
        ..settings
    };
    let (gpu, _) = raster
        .render(&scene, &wide, &ProgressBar::hidden())
        .unwrap();
    let gpu = look(2).finish(gpu);
    let differ = mono(&gpu)
        .color
        .iter()
        .zip(&s.color)
        .filter(|(a, b)| (0..4).any(|c| a[c].abs_diff(b[c]) > 1))
        .count();
    assert!(differ <= 5, "{differ} pixels differ between the renderers");
}

#[test]
fn the_command_line_supersamples_the_streamed_raster_render() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec![
            "render",
            "data/autzen_trim.laz",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
            .args(&args)
            .output()
            .unwrap();
        (o, out)
    };
    let (o, _) = run("wide.png", &["--supersample", "4", "--width", "8192"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("32768") && stderr.contains("lower --width or --supersample"),
        "{stderr}"
    );

    let (o, raster_png) = run("raster.png", &["--supersample", "2", "--width", "128"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    if !o.status.success() && stderr.contains("no GPU adapter") {
        raster_common::gpu::require_or_skip(&stderr);
        return;
    }
    assert!(o.status.success(), "{stderr}");
    assert!(
        stderr.contains("rendered 256x128 per eye, reduced to 128x64"),
        "{stderr}"
    );
    let (o, cpu_png) = run(
        "cpu.png",
        &[
            "--supersample",
            "2",
            "--width",
            "128",
            "--renderer",
            "raytrace",
        ],
    );
    assert!(o.status.success());
    let (a, b) = (
        image::open(raster_png).unwrap().into_rgba8(),
        image::open(cpu_png).unwrap().into_rgba8(),
    );
    assert_eq!(a.dimensions(), (128, 64));
    let partial = a.pixels().filter(|p| (1..255).contains(&p[3])).count();
    assert!(partial > 100, "{partial} partial pixels");
    let differ = a
        .pixels()
        .zip(b.pixels())
        .filter(|(a, b)| (0..4).any(|c| a[c].abs_diff(b[c]) > 1))
        .count();
    assert!(differ <= 5, "{differ} pixels differ between the renderers");
}
