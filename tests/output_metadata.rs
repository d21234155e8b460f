//! Metadata that 360° players read, written by `omnicloud render` (ray tracer, small images):
//! Photo Sphere XMP in PNG and JPEG, EXIF in JPEG, Google's VR photo (`.vr.jpg`), multi-view
//! ODS EXR and `envmap` in every EXR. Files are read back with the `image` and `exr` crates
//! and, where installed, with exiftool (CI installs it and sets
//! `OMNICLOUD_REQUIRE_EXIFTOOL=1`, which turns its absence into a failure).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use base64::Engine;
use image::ImageDecoder;
use md5::{Digest, Md5};

const AUTZEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");
/// Width per eye: big enough for the comparison to mean something, small enough to be quick.
const WIDTH: u32 = 256;

/// `omnicloud render AUTZEN -o out --renderer raytrace --width 256` plus `extra`; panics
/// with the command's stderr when it fails.
fn render(out: &Path, extra: &[&str]) -> Output {
    render_at(WIDTH, out, extra)
}

/// [`render`] at another width.
fn render_at(width: u32, out: &Path, extra: &[&str]) -> Output {
    let width = width.to_string();
    let output = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", AUTZEN, "-o", out.to_str().unwrap()])
        .args(["--renderer", "raytrace", "--width", &width])
        .args(extra)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "render {} {extra:?} failed: {}",
        out.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// The value of the XML attribute `name="..."`.
fn attr<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
    let start = xml.find(&format!("{name}=\""))? + name.len() + 2;
    let len = xml[start..].find('"')?;
    Some(&xml[start..start + len])
}

/// Checks the GPano fields of a panorama `width` wide with heading `heading`.
fn check_gpano(xml: &str, width: u32, heading: &str, what: &str) {
    let w = width.to_string();
    let h = (width / 2).to_string();
    for (name, want) in [
        ("GPano:ProjectionType", "equirectangular"),
        ("GPano:UsePanoramaViewer", "True"),
        ("GPano:FullPanoWidthPixels", w.as_str()),
        ("GPano:FullPanoHeightPixels", h.as_str()),
        ("GPano:CroppedAreaImageWidthPixels", w.as_str()),
        ("GPano:CroppedAreaImageHeightPixels", h.as_str()),
        ("GPano:CroppedAreaLeftPixels", "0"),
        ("GPano:CroppedAreaTopPixels", "0"),
        ("GPano:PoseHeadingDegrees", heading),
        (
            "GPano:CaptureSoftware",
            concat!("omnicloud ", env!("CARGO_PKG_VERSION")),
        ),
    ] {
        assert_eq!(attr(xml, name), Some(want), "{what}: {name} in\n{xml}");
    }
}

/// exiftool's JSON for `file` (`-G1`: names prefixed by their group, e.g. `XMP-GPano`), or
/// `None` when exiftool is not installed (a failure when `OMNICLOUD_REQUIRE_EXIFTOOL` is set).
fn exiftool(file: &Path) -> Option<serde_json::Value> {
    let out = match Command::new("exiftool")
        .args(["-j", "-G1"])
        .arg(file)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            assert!(
                std::env::var_os("OMNICLOUD_REQUIRE_EXIFTOOL").is_none(),
                "exiftool is required (OMNICLOUD_REQUIRE_EXIFTOOL) but cannot run: {e}"
            );
            writeln!(
                std::io::stderr().lock(),
                "SKIPPED the exiftool check of {}: exiftool is not installed \
                 (apt-get install libimage-exiftool-perl)",
                file.display()
            )
            .unwrap();
            return None;
        }
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    Some(json[0].clone())
}

/// The chunk types of a PNG file in order.
fn png_chunks(bytes: &[u8]) -> Vec<String> {
    let mut at = 8;
    let mut types = Vec::new();
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        types.push(String::from_utf8_lossy(&bytes[at + 4..at + 8]).into_owned());
        at += 12 + len;
    }
    types
}

#[test]
fn png_and_jpeg_panoramas_carry_photo_sphere_xmp_with_the_heading_from_yaw() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("pano.png");
    let jpg = dir.path().join("pano.jpg");
    render(&png, &["--yaw", "-30", "--quiet"]);
    render(&jpg, &["--yaw", "100", "--quality", "80", "--quiet"]);

    let bytes = std::fs::read(&png).unwrap();
    let chunks = png_chunks(&bytes);
    let itxt = chunks
        .iter()
        .position(|c| c == "iTXt")
        .expect("an iTXt chunk");
    let idat = chunks.iter().position(|c| c == "IDAT").unwrap();
    assert!(itxt < idat, "XMP must precede the image data: {chunks:?}");
    let mut decoder =
        image::codecs::png::PngDecoder::new(std::io::Cursor::new(bytes.as_slice())).unwrap();
    let xmp = String::from_utf8(decoder.xmp_metadata().unwrap().expect("PNG XMP")).unwrap();
    // DESIGN: yaw -30 looks 30° anticlockwise of +Y (north): compass heading 330°.
    check_gpano(&xmp, WIDTH, "330.0", "png");

    let bytes = std::fs::read(&jpg).unwrap();
    let mut decoder =
        image::codecs::jpeg::JpegDecoder::new(std::io::Cursor::new(bytes.as_slice())).unwrap();
    let xmp = String::from_utf8(decoder.xmp_metadata().unwrap().expect("JPEG XMP")).unwrap();
    check_gpano(&xmp, WIDTH, "100.0", "jpeg");
    let exif = decoder.exif_metadata().unwrap().expect("JPEG EXIF");
    assert!(
        exif.windows(10).any(|w| w == b"omnicloud\0"),
        "EXIF: {exif:?}"
    );
    assert_eq!(decoder.dimensions(), (WIDTH, WIDTH / 2));

    for (file, heading) in [(&png, 330.0), (&jpg, 100.0)] {
        let Some(tags) = exiftool(file) else { continue };
        let what = file.display();
        assert_eq!(
            tags["XMP-GPano:ProjectionType"], "equirectangular",
            "{what}"
        );
        assert_eq!(tags["XMP-GPano:UsePanoramaViewer"], true, "{what}");
        assert_eq!(tags["XMP-GPano:FullPanoWidthPixels"], WIDTH, "{what}");
        assert_eq!(
            tags["XMP-GPano:CroppedAreaImageHeightPixels"],
            WIDTH / 2,
            "{what}"
        );
        assert_eq!(tags["XMP-GPano:PoseHeadingDegrees"], heading, "{what}");
        if file == &jpg {
            assert_eq!(tags["IFD0:Make"], "omnicloud");
            assert_eq!(tags["IFD0:Model"], "omnicloud");
        }
    }
}

/// The bodies of a JPEG's APP1 segments (walked here, not with the library's reader).
fn app1_bodies(jpeg: &[u8]) -> Vec<&[u8]> {
    let mut at = 2;
    let mut out = Vec::new();
    while jpeg[at] == 0xFF && jpeg[at + 1] != 0xDA {
        let end = at + 2 + u16::from_be_bytes([jpeg[at + 2], jpeg[at + 3]]) as usize;
        if jpeg[at + 1] == 0xE1 {
            out.push(&jpeg[at + 4..end]);
        }
        at = end;
    }
    out
}

/// PSNR in dB between two RGB byte buffers.
fn psnr(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mse = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
        .sum::<f64>()
        / a.len() as f64;
    10.0 * (255.0f64 * 255.0 / mse).log10()
}

/// RGB bytes of an RGBA image composited over black (what the JPEG writer stores).
fn over_black(rgba: &image::RgbaImage) -> Vec<u8> {
    rgba.pixels()
        .flat_map(|p| {
            let [r, g, b, a] = p.0;
            let m = |c: u8| ((c as u32 * a as u32 + 127) / 255) as u8;
            [m(r), m(g), m(b)]
        })
        .collect()
}

#[test]
fn vr_jpg_holds_both_eyes_of_the_same_render() {
    // Wide enough that the right eye needs more than one extended-XMP segment.
    const VR_WIDTH: u32 = 1024;
    let dir = tempfile::tempdir().unwrap();
    let vr = dir.path().join("pano.vr.jpg");
    let tb = dir.path().join("pano_360_TB.png");
    // The old defaults: at the centre, 1.7 m up, near objects make the eyes differ (the
    // default camera, 27 m up on this sparse sample, sees little parallax), and half-spacing
    // spheres leave the detail that needs more than one extended-XMP segment.
    let out = render_at(
        VR_WIDTH,
        &vr,
        &[
            "--stereo", "ods", "--yaw", "45", "--camera", "center", "--radius", "auto", "--quiet",
        ],
    );
    assert!(out.stderr.is_empty(), "--quiet prints nothing");
    let out = render_at(
        VR_WIDTH,
        &tb,
        &[
            "--stereo", "ods", "--yaw", "45", "--camera", "center", "--radius", "auto",
        ],
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("hint"));

    // The reference eyes: halves of the top-bottom PNG (left on top).
    let pair = image::open(&tb).unwrap().into_rgba8();
    assert_eq!(pair.dimensions(), (VR_WIDTH, VR_WIDTH));
    let half = |top: u32| {
        over_black(&image::imageops::crop_imm(&pair, 0, top, VR_WIDTH, VR_WIDTH / 2).to_image())
    };
    let (left_ref, right_ref) = (half(0), half(VR_WIDTH / 2));

    let bytes = std::fs::read(&vr).unwrap();
    let main = image::load_from_memory(&bytes).unwrap().into_rgb8();
    assert_eq!(main.dimensions(), (VR_WIDTH, VR_WIDTH / 2));

    let segments = app1_bodies(&bytes);
    let xmp = segments
        .iter()
        .find_map(|s| s.strip_prefix(b"http://ns.adobe.com/xap/1.0/\0".as_slice()))
        .expect("main XMP");
    let xmp = std::str::from_utf8(xmp).unwrap();
    check_gpano(xmp, VR_WIDTH, "45.0", "vr.jpg");
    let guid = attr(xmp, "xmpNote:HasExtendedXMP").expect("HasExtendedXMP");
    let mut extended = Vec::new();
    let mut pieces = 0;
    for s in &segments {
        let Some(rest) = s.strip_prefix(b"http://ns.adobe.com/xmp/extension/\0".as_slice()) else {
            continue;
        };
        assert_eq!(&rest[..32], guid.as_bytes());
        let total = u32::from_be_bytes(rest[32..36].try_into().unwrap()) as usize;
        let offset = u32::from_be_bytes(rest[36..40].try_into().unwrap()) as usize;
        assert_eq!(offset, extended.len(), "pieces in order");
        assert!(rest.len() - 40 < 65_400);
        extended.extend_from_slice(&rest[40..]);
        assert!(extended.len() <= total);
        pieces += 1;
    }
    assert!(pieces >= 2, "{pieces} extended segments");
    let md5: String = Md5::digest(&extended)
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect();
    assert_eq!(md5, guid, "the GUID is the MD5 of the extended packet");
    let extended = std::str::from_utf8(&extended).unwrap();
    assert_eq!(attr(extended, "GImage:Mime"), Some("image/jpeg"));
    let right_jpeg = base64::engine::general_purpose::STANDARD
        .decode(attr(extended, "GImage:Data").unwrap())
        .unwrap();
    let right = image::load_from_memory(&right_jpeg).unwrap().into_rgb8();
    assert_eq!(right.dimensions(), (VR_WIDTH, VR_WIDTH / 2));

    let (ll, rr) = (
        psnr(main.as_raw(), &left_ref),
        psnr(right.as_raw(), &right_ref),
    );
    let (lr, rl) = (
        psnr(main.as_raw(), &right_ref),
        psnr(right.as_raw(), &left_ref),
    );
    writeln!(
        std::io::stderr().lock(),
        "vr.jpg ({} bytes, {pieces} extended pieces): left {ll:.2} dB, right {rr:.2} dB \
         against their own eye; {lr:.2} / {rl:.2} dB against the other eye",
        bytes.len()
    )
    .unwrap();
    // Measured 42.9 dB each at quality 90 (4:4:4); against the other eye 25.1 dB, so the
    // file holds two different eyes, each the one it claims to be.
    assert!(ll >= 40.0 && rr >= 40.0, "eyes: {ll:.2} / {rr:.2} dB");
    assert!(lr < 30.0 && rl < 30.0, "crossed eyes: {lr:.2} / {rl:.2} dB");

    if let Some(tags) = exiftool(&vr) {
        // exiftool reassembles the extended XMP (checking its MD5) and names the GImage
        // fields ImageMimeType and ImageData.
        assert_eq!(tags["XMP-GImage:ImageMimeType"], "image/jpeg");
        let data = tags["XMP-GImage:ImageData"].as_str().unwrap_or_default();
        let want = format!("(Binary data {} bytes", right_jpeg.len());
        assert!(data.starts_with(&want), "GImage:Data: {data}, want {want}");
        assert_eq!(tags["XMP-GPano:FullPanoWidthPixels"], VR_WIDTH);
        assert_eq!(tags["XMP-xmpNote:HasExtendedXMP"], guid);
    }
}

#[test]
fn top_bottom_png_and_jpeg_carry_no_gpano_and_render_hints_at_the_name() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("ods.png");
    let out = render(&png, &["--stereo", "ods"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let hints: Vec<&str> = stderr.lines().filter(|l| l.contains("_360_TB")).collect();
    assert_eq!(hints.len(), 1, "{stderr}");
    assert!(hints[0].contains("ods_360_TB.png"), "{}", hints[0]);
    let bytes = std::fs::read(&png).unwrap();
    assert!(!png_chunks(&bytes).contains(&"iTXt".to_owned()));
    let jpg = dir.path().join("ods_360_TB.jpg");
    let out = render(&jpg, &["--stereo", "ods"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("hint"));
    let bytes = std::fs::read(&jpg).unwrap();
    let mut decoder =
        image::codecs::jpeg::JpegDecoder::new(std::io::Cursor::new(bytes.as_slice())).unwrap();
    assert_eq!(decoder.dimensions(), (WIDTH, WIDTH));
    assert_eq!(decoder.xmp_metadata().unwrap(), None);

    // A VR photo needs two eyes; the refusal comes before any rendering.
    let bad = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", AUTZEN, "-o"])
        .arg(dir.path().join("mono.vr.jpg"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--stereo ods"));
}

/// An EXR file's first layer: its channel names and attributes.
fn exr_header(path: &Path) -> (Vec<String>, exr::meta::header::LayerAttributes) {
    let image = exr::prelude::read_first_flat_layer_from_file(path).unwrap();
    let names = image
        .layer_data
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    (names, image.layer_data.attributes)
}

#[test]
fn ods_exr_is_multi_view_and_every_exr_is_a_latlong_environment_map() {
    use exr::meta::attribute::EnvironmentMap;
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| -> PathBuf { dir.path().join(n) };
    render(&p("mono.exr"), &["--quiet"]);
    render(
        &p("ods.exr"),
        &[
            "--stereo",
            "ods",
            "--depth",
            p("depth.exr").to_str().unwrap(),
            "--quiet",
        ],
    );
    render(
        &p("eyes.exr"),
        &["--stereo", "ods", "--separate-eyes", "--quiet"],
    );

    let (names, attrs) = exr_header(&p("mono.exr"));
    assert_eq!(names, ["A", "B", "G", "R", "Z"]);
    assert_eq!(
        attrs.environment_map,
        Some(EnvironmentMap::LatitudeLongitude)
    );
    assert_eq!(attrs.multi_view_names, None);

    let (names, attrs) = exr_header(&p("ods.exr"));
    let mut want: Vec<String> = ["A", "B", "G", "R", "Z"].map(String::from).to_vec();
    want.extend(["A", "B", "G", "R", "Z"].map(|c| format!("right.{c}")));
    assert_eq!(names, want);
    assert_eq!(
        attrs.environment_map,
        Some(EnvironmentMap::LatitudeLongitude)
    );
    let views: Vec<String> = attrs
        .multi_view_names
        .expect("multiView")
        .iter()
        .map(|t| t.to_string())
        .collect();
    assert_eq!(views, ["left", "right"]);
    let image = exr::prelude::read_first_flat_layer_from_file(p("ods.exr")).unwrap();
    assert_eq!(image.layer_data.size.width(), WIDTH as usize);
    assert_eq!(image.layer_data.size.height(), WIDTH as usize / 2);

    if let Some(tags) = exiftool(&p("ods.exr")) {
        assert_eq!(
            tags["OpenEXR:MultiView"],
            serde_json::json!(["left", "right"])
        );
        assert_eq!(tags["OpenEXR:EnvironmentMap"], "Latitude/Longitude");
    }

    let (names, attrs) = exr_header(&p("depth.exr"));
    assert_eq!(names, ["Z", "right.Z"]);
    assert!(attrs.multi_view_names.is_some() && attrs.environment_map.is_some());

    // The reader stacks the views top-bottom: the same eyes as the separate files.
    let stacked = omnicloud::output::read_exr(&p("ods.exr")).unwrap();
    assert_eq!((stacked.width, stacked.height), (WIDTH, WIDTH));
    let n = (WIDTH * WIDTH / 2) as usize;
    for (eye, range) in [("left", 0..n), ("right", n..2 * n)] {
        let file = p(&format!("eyes_{eye}.exr"));
        let (names, attrs) = exr_header(&file);
        assert_eq!(names.len(), 5, "{eye}");
        assert_eq!(
            attrs.environment_map,
            Some(EnvironmentMap::LatitudeLongitude)
        );
        let single = omnicloud::output::read_exr(&file).unwrap();
        assert_eq!(single.depth, stacked.depth[range.clone()], "{eye} depth");
        assert_eq!(single.color, stacked.color[range], "{eye} colour");
    }
    let depth = omnicloud::output::read_exr(&p("depth.exr")).unwrap();
    assert_eq!(depth.depth, stacked.depth);

    // `omnicloud compare` still sees an ODS pair.
    let report = p("r.json");
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .arg("compare")
        .args([p("ods.exr"), p("ods.exr")])
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(json["layout"], "top-bottom");
    assert_eq!(json["eyes"].as_array().unwrap().len(), 2);
}

#[test]
fn other_projections_carry_no_360_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| -> PathBuf { dir.path().join(n) };
    render(&p("hammer.png"), &["--projection", "hammer", "--quiet"]);
    render(
        &p("front.jpg"),
        &["--projection", "equirect:180,90", "--quiet"],
    );
    render(
        &p("fish.exr"),
        &[
            "--projection",
            "fisheye",
            "--stereo",
            "ods",
            "--depth",
            p("fish_z.exr").to_str().unwrap(),
            "--quiet",
        ],
    );
    render(&p("pano.png"), &["--quiet"]);
    let has_gpano = |n: &str| {
        let bytes = std::fs::read(p(n)).unwrap();
        bytes.windows(5).any(|w| w == b"GPano")
    };
    assert!(has_gpano("pano.png"), "the full panorama keeps its GPano");
    assert!(!has_gpano("hammer.png") && !has_gpano("front.jpg"));
    for exr in ["fish.exr", "fish_z.exr"] {
        let (_, attrs) = exr_header(&p(exr));
        assert_eq!(attrs.environment_map, None, "{exr}");
        assert_eq!(attrs.multi_view_names.map(|v| v.len()), Some(2), "{exr}");
    }
    let refused = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", AUTZEN, "-o", p("h.vr.jpg").to_str().unwrap()])
        .args(["--projection", "hammer", "--stereo", "ods", "--width", "64"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && err.contains("equirectangular eyes"),
        "{err}"
    );
    assert!(!p("h.vr.jpg").exists());
}
