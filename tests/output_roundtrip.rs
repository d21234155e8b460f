//! Writers round-trip: PNG pixels, EXR colour / coverage / depth (with +inf), ODS layouts,
//! depth-only EXR, anaglyph channels, and atomic writes that leave nothing behind on failure.

use std::path::Path;

use omnicloud::output::{
    AnaglyphMethod, Layout, LinearImage, OutputError, anaglyph, read_exr, read_image, read_png,
    write_anaglyph, write_depth, write_image,
};
use omnicloud::render::shading::{linear_to_srgb, srgb_to_linear};
use omnicloud::{Frame, Rendered};

/// A frame whose every hit pixel has a distinct colour and depth; every third pixel is
/// background.
fn pattern(width: u32, height: u32, seed: u8) -> Frame {
    let mut f = Frame::new(width, height);
    for k in 0..f.color.len() {
        if k % 3 == 0 {
            continue;
        }
        let b = (k as u32).wrapping_mul(2_654_435_761) >> 8;
        f.color[k] = [b as u8, (b >> 8) as u8 ^ seed, (b >> 16) as u8, 255];
        f.depth[k] = 0.5 + k as f32 * 0.013 + seed as f32;
    }
    f
}

/// Names of all entries in `dir`.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn png_round_trips_pixels_and_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pano.png");
    let f = pattern(16, 8, 1);
    let written = write_image(&path, &Rendered::Mono(f.clone()), Layout::TopBottom).unwrap();
    assert_eq!(written, vec![path.clone()]);
    let back = read_png(&path).unwrap();
    assert_eq!(back.color, f.color);
    assert_eq!((back.width, back.height), (16, 8));
    assert_eq!(entries(dir.path()), vec!["pano.png"]);
}

#[test]
fn exr_round_trips_linear_colour_coverage_and_depth() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pano.EXR");
    let f = pattern(16, 8, 2);
    write_image(&path, &Rendered::Mono(f.clone()), Layout::TopBottom).unwrap();
    let back = read_exr(&path).unwrap();
    assert_eq!((back.width, back.height), (16, 8));
    for k in 0..f.color.len() {
        let hit = f.color[k][3] == 255;
        assert_eq!(back.coverage[k], if hit { 1.0 } else { 0.0 });
        for c in 0..3 {
            let want = if hit {
                srgb_to_linear(f.color[k][c])
            } else {
                0.0
            };
            assert_eq!(back.color[k][c], want, "pixel {k} channel {c}");
        }
        if hit {
            assert_eq!(back.depth[k], f.depth[k]);
        } else {
            assert_eq!(
                back.depth[k],
                f32::INFINITY,
                "background depth must stay +inf"
            );
        }
    }
    assert_eq!(back.to_frame(), f);
}

#[test]
fn top_bottom_puts_left_eye_on_top() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ods.exr");
    let (left, right) = (pattern(8, 4, 3), pattern(8, 4, 7));
    let r = Rendered::Stereo {
        left: left.clone(),
        right: right.clone(),
    };
    write_image(&path, &r, Layout::TopBottom).unwrap();
    let back = read_exr(&path).unwrap();
    assert_eq!((back.width, back.height), (8, 8));
    let n = 8 * 4;
    assert_eq!(&back.depth[..n], &left.depth[..]);
    assert_eq!(&back.depth[n..], &right.depth[..]);

    let png = dir.path().join("ods.png");
    write_image(&png, &r, Layout::TopBottom).unwrap();
    let back = read_png(&png).unwrap();
    assert_eq!(&back.color[..n], &left.color[..]);
    assert_eq!(&back.color[n..], &right.color[..]);
}

#[test]
fn separate_eyes_write_named_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ods.png");
    let (left, right) = (pattern(8, 4, 3), pattern(8, 4, 7));
    let r = Rendered::Stereo {
        left: left.clone(),
        right: right.clone(),
    };
    let written = write_image(&path, &r, Layout::SeparateEyes).unwrap();
    let (lp, rp) = (
        dir.path().join("ods_left.png"),
        dir.path().join("ods_right.png"),
    );
    assert_eq!(written, vec![lp.clone(), rp.clone()]);
    assert_eq!(read_png(&lp).unwrap().color, left.color);
    assert_eq!(read_png(&rp).unwrap().color, right.color);
    assert_eq!(entries(dir.path()), vec!["ods_left.png", "ods_right.png"]);
}

#[test]
fn depth_only_exr_holds_z_and_derives_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("depth.exr");
    let f = pattern(16, 8, 4);
    write_depth(&path, &Rendered::Mono(f.clone()), Layout::TopBottom).unwrap();
    let back = read_exr(&path).unwrap();
    assert_eq!(back.depth, f.depth);
    for k in 0..f.color.len() {
        assert_eq!(back.coverage[k] == 1.0, f.color[k][3] == 255);
        assert_eq!(back.color[k], [0.0; 3]);
    }
    let err = write_depth(
        &dir.path().join("d.png"),
        &Rendered::Mono(f),
        Layout::TopBottom,
    );
    assert!(matches!(err, Err(OutputError::UnsupportedExtension { .. })));
}

#[test]
fn read_image_dispatches_by_extension() {
    let dir = tempfile::tempdir().unwrap();
    let f = pattern(8, 4, 5);
    for name in ["a.png", "a.exr"] {
        let p = dir.path().join(name);
        write_image(&p, &Rendered::Mono(f.clone()), Layout::TopBottom).unwrap();
        let img = read_image(&p).unwrap();
        let want = LinearImage::from_frame(&f);
        assert_eq!(img.color, want.color, "{name}");
        assert_eq!(img.coverage, want.coverage, "{name}");
    }
}

#[test]
fn unsupported_extension_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pano.tif");
    let err = write_image(&path, &Rendered::Mono(pattern(4, 2, 0)), Layout::TopBottom).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("pano.tif") && msg.contains(".png, .jpg, .vr.jpg or .exr"),
        "{msg}"
    );
    let vr = dir.path().join("mono.vr.jpg");
    let err = write_image(&vr, &Rendered::Mono(pattern(4, 2, 0)), Layout::TopBottom).unwrap_err();
    assert!(matches!(err, OutputError::NotStereo { .. }), "{err}");
    assert!(entries(dir.path()).is_empty());
}

#[test]
fn anaglyph_takes_red_from_left_and_cyan_from_right() {
    let mut left = Frame::new(4, 2);
    let mut right = Frame::new(4, 2);
    left.color[1] = [200, 50, 10, 255];
    right.color[1] = [30, 120, 220, 255];
    right.color[2] = [255, 255, 255, 255]; // only the right eye hits pixel 2
    left.color[3] = [255, 0, 0, 255]; // only the left eye hits pixel 3
    let img = anaglyph(&left, &right, AnaglyphMethod::HalfColor, Path::new("x.png")).unwrap();
    let px = |k: u32| img.get_pixel(k % 4, k / 4).0;
    let lum =
        0.2126 * srgb_to_linear(200) + 0.7152 * srgb_to_linear(50) + 0.0722 * srgb_to_linear(10);
    let red = linear_to_srgb(lum);
    assert_eq!(px(1), [red, 120, 220]);
    assert_eq!(px(2), [0, 255, 255], "right eye alone gives cyan, no red");
    assert_eq!(
        px(3),
        [linear_to_srgb(0.2126), 0, 0],
        "left eye alone gives red, no cyan"
    );
    assert_eq!(px(0), [0, 0, 0]);

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ana.png");
    let r = Rendered::Stereo { left, right };
    write_anaglyph(&path, &r, AnaglyphMethod::HalfColor).unwrap();
    let back = read_png(&path).unwrap();
    assert_eq!(back.color[1], [red, 120, 220, 255]);
    let mono = write_anaglyph(
        &path,
        &Rendered::Mono(Frame::new(4, 2)),
        AnaglyphMethod::Dubois,
    );
    assert!(matches!(mono, Err(OutputError::NotStereo { .. })));
}

#[test]
fn failed_write_leaves_no_file_and_no_temp() {
    let dir = tempfile::tempdir().unwrap();
    let f = Rendered::Mono(pattern(8, 4, 1));
    // Missing directory: the temporary file cannot even be created.
    let missing = dir.path().join("no_such_dir").join("pano.exr");
    let err = write_image(&missing, &f, Layout::TopBottom).unwrap_err();
    assert!(err.to_string().contains("pano.exr"), "{err}");
    assert!(entries(dir.path()).is_empty());

    // Encoder failure after the temporary file exists: a zero-sized EXR is rejected.
    let path = dir.path().join("empty.exr");
    let err = write_image(&path, &Rendered::Mono(Frame::new(0, 0)), Layout::TopBottom);
    assert!(err.is_err());
    assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));

    // Second eye fails: neither eye file may remain.
    let stereo = Rendered::Stereo {
        left: pattern(8, 4, 1),
        right: Frame::new(0, 0),
    };
    let path = dir.path().join("ods.exr");
    assert!(write_image(&path, &stereo, Layout::SeparateEyes).is_err());
    assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
}

#[test]
fn overwrite_replaces_existing_file_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pano.png");
    write_image(&path, &Rendered::Mono(pattern(8, 4, 1)), Layout::TopBottom).unwrap();
    let newer = pattern(8, 4, 9);
    write_image(&path, &Rendered::Mono(newer.clone()), Layout::TopBottom).unwrap();
    assert_eq!(read_png(&path).unwrap().color, newer.color);
    assert_eq!(entries(dir.path()), vec!["pano.png"]);
}

#[test]
fn jpeg_and_vr_photo_read_back_for_comparison() {
    let dir = tempfile::tempdir().unwrap();
    let (left, right) = (Frame::new(16, 8), pattern(16, 8, 9));
    let stereo = Rendered::Stereo {
        left: left.clone(),
        right: right.clone(),
    };
    let vr = dir.path().join("pair.vr.jpg");
    // A VR photo holds both eyes whatever the layout asks.
    assert_eq!(
        write_image(&vr, &stereo, Layout::SeparateEyes).unwrap(),
        vec![vr.clone()]
    );
    let back = read_image(&vr).unwrap();
    assert_eq!((back.width, back.height), (16, 16));
    assert!(back.coverage.iter().all(|&c| c == 1.0), "JPEG has no alpha");
    // The left eye is empty (black), the right eye is not.
    let mean =
        |range: std::ops::Range<usize>| range.map(|k| back.color[k][1] as f64).sum::<f64>() / 128.0;
    assert!(mean(0..128) < 0.01 && mean(128..256) > 0.05);

    let jpg = dir.path().join("pano.jpeg");
    write_image(&jpg, &Rendered::Mono(right), Layout::TopBottom).unwrap();
    let back = read_image(&jpg).unwrap();
    assert_eq!((back.width, back.height), (16, 8));
}
