//! Every PNG, JPEG and EXR render names its projection and eyes, and `compare`, `view` and
//! `video` go by it rather than by the image's shape: a square fisheye is one image, not a
//! top-bottom pair, and neither it nor a 2:1 Hammer map is shown or encoded as a 360° sphere.

#[path = "raster_common/gpu.rs"]
mod gpu;

use std::path::{Path, PathBuf};
use std::process::Command;

use omnicloud::compare::{CompareError, compare_files};
use omnicloud::frame::{Frame, Rendered};
use omnicloud::output::{
    ImageDescription, Layout, OutputError, OutputOptions, StoredEyes, read_description,
    write_image_with,
};
use omnicloud::projection::Projection;

/// A `w x h` frame whose first `hits` pixels are hit at 3 m, the rest background.
fn frame(w: u32, h: u32, hits: usize) -> Frame {
    let mut f = Frame::new(w, h);
    for k in 0..hits {
        f.color[k] = [90, 140, 200, 255];
        f.depth[k] = 3.0;
    }
    f
}

/// Writes `rendered` to `path` under `projection` and `layout`; the files written.
fn write(path: &Path, rendered: &Rendered, projection: &str, layout: Layout) -> Vec<PathBuf> {
    let options = OutputOptions {
        layout,
        projection: projection.parse().unwrap(),
        ..OutputOptions::default()
    };
    write_image_with(path, rendered, &options).unwrap()
}

fn described(projection: &str, eyes: StoredEyes) -> Option<ImageDescription> {
    Some(ImageDescription {
        projection: projection.parse::<Projection>().unwrap(),
        eyes,
        metres_per_unit: None,
    })
}

#[test]
fn every_format_carries_its_projection_and_eyes() {
    let dir = tempfile::tempdir().unwrap();
    let mono = Rendered::Mono(frame(64, 64, 100));
    let pair = Rendered::Stereo {
        left: frame(64, 32, 10),
        right: frame(64, 32, 20),
    };
    for ext in ["png", "jpg", "exr"] {
        let fish = dir.path().join(format!("fish.{ext}"));
        write(&fish, &mono, "fisheye:180", Layout::TopBottom);
        assert_eq!(
            read_description(&fish).unwrap(),
            described("fisheye:180", StoredEyes::Mono),
            "{ext}"
        );
        let tb = dir.path().join(format!("tb.{ext}"));
        write(&tb, &pair, "equirect", Layout::TopBottom);
        assert_eq!(
            read_description(&tb).unwrap(),
            described("equirect", StoredEyes::TopBottom),
            "{ext}"
        );
        let sep = dir.path().join(format!("sep.{ext}"));
        let files = write(&sep, &pair, "equirect", Layout::SeparateEyes);
        let eyes: Vec<_> = files
            .iter()
            .map(|f| read_description(f).unwrap().unwrap().eyes)
            .collect();
        assert_eq!(eyes, [StoredEyes::Left, StoredEyes::Right], "{ext}");
    }
    // A VR photo's own XMP describes it; it carries no description.
    let vr = dir.path().join("pair.vr.jpg");
    write(&vr, &pair, "equirect", Layout::TopBottom);
    assert_eq!(read_description(&vr).unwrap(), None);
    // Other programs' files have none.
    let plain = dir.path().join("plain.png");
    image::RgbImage::new(8, 8).save(&plain).unwrap();
    assert_eq!(read_description(&plain).unwrap(), None);
    let plain_jpg = dir.path().join("plain.jpg");
    image::RgbImage::new(8, 8).save(&plain_jpg).unwrap();
    assert_eq!(read_description(&plain_jpg).unwrap(), None);
}

#[test]
fn a_bad_or_unreadable_description_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("odd.png");
    let mut encoder = png::Encoder::new(std::fs::File::create(&path).unwrap(), 4, 4);
    encoder.set_color(png::ColorType::Rgba);
    encoder
        .add_text_chunk("omnicloud".into(), "projection=globe eyes=mono".into())
        .unwrap();
    let mut w = encoder.write_header().unwrap();
    w.write_image_data(&[0u8; 64]).unwrap();
    w.finish().unwrap();
    let err = read_description(&path).unwrap_err();
    assert!(matches!(err, OutputError::BadDescription { .. }), "{err}");
    let text = err.to_string();
    assert!(
        text.contains("odd.png") && text.contains("unknown projection `globe`"),
        "{text}"
    );

    // A JPEG header that does not parse holds no description (the decoder then says what is
    // wrong); fill bytes before a marker are skipped.
    let truncated = dir.path().join("cut.jpg");
    std::fs::write(&truncated, [0xFF, 0xD8, 0xFF, 0xE0, 0x00]).unwrap();
    assert_eq!(read_description(&truncated).unwrap(), None);
    let filled = dir.path().join("filled.jpg");
    let mut bytes = vec![0xFF, 0xD8, 0xFF, 0xFF, 0xFF, 0xFE, 0x00];
    let comment = b"omnicloud projection=hammer eyes=mono";
    bytes.push(2 + comment.len() as u8);
    bytes.extend_from_slice(comment);
    bytes.extend_from_slice(&[0xFF, 0xDA, 0x00, 0x02]);
    std::fs::write(&filled, bytes).unwrap();
    assert_eq!(
        read_description(&filled).unwrap(),
        described("hammer", StoredEyes::Mono)
    );
    let garbage = dir.path().join("garbage.png");
    std::fs::write(&garbage, b"not a PNG at all").unwrap();
    let err = read_description(&garbage).unwrap_err().to_string();
    assert!(
        err.contains("garbage.png: cannot read its metadata"),
        "{err}"
    );
    let err = read_description(&dir.path().join("missing.exr"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("missing.exr"), "{err}");
}

#[test]
fn compare_measures_a_square_fisheye_as_one_image_without_bands_or_seam() {
    let dir = tempfile::tempdir().unwrap();
    let (r, t) = (dir.path().join("r.exr"), dir.path().join("t.exr"));
    // The test misses the reference's last hit pixel, in the lower half.
    write(
        &r,
        &Rendered::Mono(frame(64, 64, 3000)),
        "fisheye:180",
        Layout::TopBottom,
    );
    write(
        &t,
        &Rendered::Mono(frame(64, 64, 2999)),
        "fisheye:180",
        Layout::TopBottom,
    );
    let report = compare_files(&r, &t, None, None).unwrap();
    assert_eq!(report.layout, "mono");
    assert_eq!(report.projection.as_deref(), Some("fisheye:180"));
    assert_eq!(report.eyes.len(), 1);
    let eye = &report.eyes[0];
    assert_eq!((eye.eye.as_str(), eye.height), ("mono", 64));
    assert_eq!((eye.all.pixels, eye.all.only_ref), (64 * 64, 1));
    assert!(eye.latitude_bands.is_empty() && eye.seam.is_none());
    let text = report.to_string();
    assert!(text.starts_with("64x64 fisheye:180 mono image"), "{text}");
    assert!(
        !text.contains("seam") && !text.contains("latitude"),
        "{text}"
    );

    // The same pixels without descriptions are taken for a top-bottom equirect pair.
    let (ru, tu) = (dir.path().join("ru.png"), dir.path().join("tu.png"));
    for (path, hits) in [(&ru, 3000), (&tu, 2999)] {
        let f = frame(64, 64, hits);
        image::RgbaImage::from_raw(64, 64, f.color.concat())
            .unwrap()
            .save(path)
            .unwrap();
    }
    let guessed = compare_files(&ru, &tu, None, None).unwrap();
    assert_eq!(guessed.layout, "top-bottom");
    assert_eq!(guessed.projection, None);
    assert_eq!(guessed.eyes[1].all.only_ref, 1);
    assert!(guessed.eyes[1].seam.is_some());
    assert!(
        guessed
            .to_string()
            .contains("layout guessed from the shape")
    );
}

#[test]
fn compare_refuses_files_whose_descriptions_disagree() {
    let dir = tempfile::tempdir().unwrap();
    let pair = Rendered::Stereo {
        left: frame(64, 32, 10),
        right: frame(64, 32, 20),
    };
    let (tb, fish) = (dir.path().join("tb.exr"), dir.path().join("fish.exr"));
    write(&tb, &pair, "equirect", Layout::TopBottom);
    write(
        &fish,
        &Rendered::Mono(frame(64, 64, 30)),
        "fisheye:180",
        Layout::TopBottom,
    );
    let err = compare_files(&tb, &fish, None, None).unwrap_err();
    assert!(matches!(err, CompareError::Layout { .. }), "{err}");
    let text = err.to_string();
    assert!(
        text.contains("reference is equirect top-bottom but test is fisheye:180 mono"),
        "{text}"
    );
    // One eye of a pair against the other is one image against one image.
    let files = write(
        &dir.path().join("e.exr"),
        &pair,
        "equirect",
        Layout::SeparateEyes,
    );
    let report = compare_files(&files[0], &files[1], None, None).unwrap();
    assert_eq!(report.eyes.len(), 1);
    assert_eq!(report.eyes[0].eye, "left");
    assert_eq!(report.eyes[0].all.only_test, 10);
    assert_eq!(report.eyes[0].latitude_bands.len(), 18);
}

#[cfg(feature = "web")]
#[test]
fn the_viewer_refuses_renders_of_other_projections() {
    use omnicloud::web::{Panorama, PanoramaKind, WebError};
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("fish.png", 64, 64, "fisheye:180"),
        ("hammer.jpg", 64, 32, "hammer"),
    ];
    for (name, w, h, projection) in cases {
        let path = dir.path().join(name);
        write(
            &path,
            &Rendered::Mono(frame(w, h, 50)),
            projection,
            Layout::TopBottom,
        );
        let err = Panorama::open(&path).unwrap_err();
        assert!(matches!(err, WebError::NotPanorama { .. }), "{err}");
        let text = err.to_string();
        assert!(text.contains(name) && text.contains(projection), "{text}");
    }
    // A described equirect pair and one eye of it open as what they are.
    let pair = Rendered::Stereo {
        left: frame(64, 32, 10),
        right: frame(64, 32, 20),
    };
    let tb = dir.path().join("tb.png");
    write(&tb, &pair, "equirect", Layout::TopBottom);
    assert_eq!(Panorama::open(&tb).unwrap().kind, PanoramaKind::Ods);
    let eyes = write(
        &dir.path().join("e.png"),
        &pair,
        "equirect",
        Layout::SeparateEyes,
    );
    assert_eq!(Panorama::open(&eyes[0]).unwrap().kind, PanoramaKind::Mono);
}

#[cfg(feature = "video")]
#[test]
fn a_video_is_not_made_of_frames_of_other_projections() {
    use omnicloud::frames::{FrameFolder, FramesError, StereoChoice};
    let dir = tempfile::tempdir().unwrap();
    for k in 0..2 {
        let path = dir.path().join(format!("frame_{k:06}.png"));
        write(
            &path,
            &Rendered::Mono(frame(64, 32, 50)),
            "hammer",
            Layout::TopBottom,
        );
    }
    let err = FrameFolder::open(dir.path(), StereoChoice::Auto).unwrap_err();
    assert!(matches!(err, FramesError::Shape { .. }), "{err}");
    assert!(err.to_string().contains("it is a hammer render"), "{err}");
}

/// The sample in a 180° fisheye, 256 pixels square, by `renderer` into `path`; `false` when the
/// rasterizer has no adapter (after [`gpu::require_or_skip`]).
fn render_fisheye(renderer: &str, path: &Path) -> bool {
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args([
            "render",
            "data/autzen_trim.laz",
            "--projection",
            "fisheye:180",
        ])
        .args(["--width", "256", "--renderer", renderer, "-o"])
        .arg(path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && stderr.contains("no GPU adapter") {
        gpu::require_or_skip(&format!(
            "omnicloud render found no adapter: {}",
            stderr.trim()
        ));
        return false;
    }
    assert!(out.status.success(), "{stderr}");
    true
}

#[test]
fn the_sample_in_a_fisheye_compares_as_one_exact_image() {
    let dir = tempfile::tempdir().unwrap();
    let (rt, raster) = (dir.path().join("rt.exr"), dir.path().join("raster.exr"));
    assert!(render_fisheye("raytrace", &rt));
    if !render_fisheye("raster", &raster) {
        return;
    }
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .arg("compare")
        .args([&rt, &raster])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines[0], "256x256 fisheye:180 mono image", "{stdout}");
    assert!(
        lines[1].starts_with(" mono: coverage mismatch 0 px"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("left") && !stdout.contains("seam"),
        "{stdout}"
    );
}
