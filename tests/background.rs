//! `--background`: the default output is what the renderer and writer give without any pass,
//! `transparent` keeps it, a colour fills exactly the uncovered pixels, and a JPEG refuses
//! transparency. Ray-traced at 128 wide: no GPU needed.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::output::{self, OutputOptions, read_exr};
use omnicloud::prepare::{PrepareOptions, prepare_files};
use omnicloud::projection::{Camera, Image, Stereo};
use omnicloud::raytrace;
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings, Shading};

const SAMPLE: &str = "data/autzen_trim.laz";

fn render(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        SAMPLE,
        "-o",
        out.to_str().unwrap(),
        "--width",
        "128",
        "--renderer",
        "raytrace",
        "-q",
    ];
    args.extend(extra);
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(&args)
        .output()
        .unwrap()
}

fn ok(out: &Path, extra: &[&str]) -> PathBuf {
    let o = render(out, extra);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.to_path_buf()
}

fn rgba(path: &Path) -> image::RgbaImage {
    image::open(path).unwrap().into_rgba8()
}

#[test]
fn the_default_output_is_the_plain_render_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    // The renderer and writer alone, as before any pass existed.
    let prepared = prepare_files(
        &[PathBuf::from(SAMPLE)],
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap();
    let settings = RenderSettings {
        image: Image::equirect(128),
        camera: Camera::new(DVec3::ZERO, 0.0),
        stereo: Stereo::Mono,
        color: ColorMode::Auto,
        shading: Shading::Unlit,
        proxy: Proxy::default(),
        imposter: Imposter::default(),
        depth_map: None,
    };
    let rendered = raytrace::render(&prepared.scene, &settings, &ProgressBar::hidden()).unwrap();
    for ext in ["png", "jpg", "exr"] {
        let reference = dir.path().join(format!("reference.{ext}"));
        // The sample's feet, as `render` records them in the description.
        let options = OutputOptions {
            metres_per_unit: Some(0.3048),
            ..OutputOptions::default()
        };
        output::write_image_with(&reference, &rendered, &options).unwrap();
        let cli = ok(&dir.path().join(format!("cli.{ext}")), &[]);
        let reference = std::fs::read(reference).unwrap();
        assert_eq!(std::fs::read(&cli).unwrap(), reference, ".{ext}");
        if ext != "jpg" {
            let transparent = ok(
                &dir.path().join(format!("transparent.{ext}")),
                &["--background", "transparent"],
            );
            assert_eq!(std::fs::read(transparent).unwrap(), reference, ".{ext}");
        }
    }
}

#[test]
fn a_colour_fills_exactly_the_uncovered_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let plain = rgba(&ok(&dir.path().join("plain.png"), &[]));
    let filled = rgba(&ok(
        &dir.path().join("filled.png"),
        &["--background", "#336699"],
    ));
    let mut background = 0;
    for (p, f) in plain.pixels().zip(filled.pixels()) {
        assert_eq!(f[3], 255);
        match p[3] {
            0 => {
                background += 1;
                assert_eq!(f.0, [0x33, 0x66, 0x99, 255]);
            }
            _ => assert_eq!(f.0, p.0),
        }
    }
    assert!(background > 1000, "{background} background pixels");

    // EXR: A becomes 1 and RGB the colour in linear light; Z still marks the background.
    let exr = read_exr(&ok(
        &dir.path().join("filled.exr"),
        &["--background", "white"],
    ))
    .unwrap();
    let plain = read_exr(&ok(&dir.path().join("plain.exr"), &[])).unwrap();
    for k in 0..exr.len() {
        assert_eq!(exr.coverage[k], 1.0);
        assert_eq!(exr.depth[k].to_bits(), plain.depth[k].to_bits());
        if plain.coverage[k] == 0.0 {
            assert_eq!(exr.color[k], [1.0; 3]);
        }
    }
    // A JPEG gets the colour instead of black.
    let jpg = ok(
        &dir.path().join("white.jpg"),
        &["--background", "255,255,255"],
    );
    let top = image::open(jpg).unwrap().into_rgb8();
    // The sky over the scan is background.
    assert!(top.get_pixel(64, 1).0.iter().all(|&c| c > 245));
}

#[test]
fn a_jpeg_cannot_be_transparent_and_bad_colours_are_named() {
    let dir = tempfile::tempdir().unwrap();
    for (name, stereo) in [("x.jpg", "none"), ("x.vr.jpg", "ods")] {
        let o = render(
            &dir.path().join(name),
            &["--background", "transparent", "--stereo", stereo],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(
            stderr.contains("no alpha") && stderr.contains(".png"),
            "{stderr}"
        );
        assert!(!dir.path().join(name).exists());
    }
    let o = render(&dir.path().join("x.png"), &["--background", "teal"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("#rrggbb") && stderr.contains("teal"),
        "{stderr}"
    );
}
