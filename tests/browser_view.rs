//! The viewer page in a real headless Chromium (Debian's `chromium`, driven over the DevTools
//! protocol by `headless_chrome`): synthetic panoramas whose colours encode direction show,
//! at a pixel of the screenshot, the colour of that pixel's view direction; an ODS pair's
//! anaglyph mixes the eyes as `omnicloud render --anaglyph` does; with a stub WebXR runtime,
//! "Enter VR" asks for an `immersive-vr` session and draws each eye from its own half.
//! Chromium and its flags: `browser_common`. Without Chromium the tests skip with a notice,
//! and fail when `OMNICLOUD_REQUIRE_BROWSER=1` (CI).
#![cfg(feature = "web")]

mod browser_common;

use std::f64::consts::PI;
use std::path::Path;

use browser_common::{XR_STUB, chromium, js, launch, mouse, open_viewer, page_size, screenshot};
use headless_chrome::Tab;
use headless_chrome::protocol::cdp::Input;
use image::{Rgb, RgbImage, RgbaImage};
use omnicloud::output::AnaglyphMethod;
use omnicloud::output::anaglyph::anaglyph_pixel;
use omnicloud::web::{Panorama, Running, ViewServer};

/// Largest difference allowed per channel between a screenshot pixel and the colour its view
/// direction has in the panorama (a continuous code; the page shows it filtered between
/// whole codes and rounded to a byte). Measured worst: 0.50. One code is 1.4° of longitude
/// and 0.7° of latitude.
const TOLERANCE: f64 = 1.0;

/// The same for the anaglyph, whose red is the left eye's luminance re-encoded to sRGB, which
/// turns a half-code difference in green into up to one in red. Measured worst: 1.00.
const ANAGLYPH_TOLERANCE: f64 = 1.5;

fn serve(path: &Path) -> Running {
    ViewServer::bind("127.0.0.1", 0, Panorama::open(path).unwrap())
        .unwrap()
        .spawn()
}

/// The code the synthetic panoramas give a longitude or latitude fraction: 0..=255.
fn code(fraction: f64) -> f64 {
    (fraction * 256.0).clamp(0.0, 255.0)
}

/// A 2:1 image whose pixel (i, j) is (code(u), code(v), blue), u and v its centre's
/// coordinates (DESIGN.md section 2: u = 0.5 is longitude 0, v = 0 the top row).
fn direction_image(width: u32, blue: u8, invert: bool) -> RgbImage {
    let height = width / 2;
    RgbImage::from_fn(width, height, |i, j| {
        let u = (f64::from(i) + 0.5) / f64::from(width);
        let v = (f64::from(j) + 0.5) / f64::from(height);
        let (r, g) = (code(u).floor() as u8, code(v).floor() as u8);
        if invert {
            Rgb([255 - r, 255 - g, blue])
        } else {
            Rgb([r, g, blue])
        }
    })
}

/// A view: heading and pitch in degrees, vertical field of view in degrees, over a viewport
/// (x, y, width, height) of the screenshot, in pixels from its top left.
#[derive(Clone, Copy, Debug)]
struct View {
    yaw: f64,
    pitch: f64,
    fov: f64,
    viewport: (f64, f64, f64, f64),
}

impl View {
    /// (u, v) in the panorama of the ray through the centre of screenshot pixel (px, py).
    /// Camera space as in DESIGN.md section 8: right, forward, up; pitch turns forward
    /// towards up, then yaw turns it to the right.
    fn uv(&self, px: u32, py: u32) -> (f64, f64) {
        let (x0, y0, w, h) = self.viewport;
        let ndc_x = (f64::from(px) + 0.5 - x0) / w * 2.0 - 1.0;
        let ndc_y = 1.0 - (f64::from(py) + 0.5 - y0) / h * 2.0;
        let f = (self.fov.to_radians() / 2.0).tan();
        let (right, forward, up) = (ndc_x * (w / h) * f, 1.0, ndc_y * f);
        let (sp, cp) = self.pitch.to_radians().sin_cos();
        let (forward, up) = (forward * cp - up * sp, forward * sp + up * cp);
        let (sy, cy) = self.yaw.to_radians().sin_cos();
        let (right, forward) = (right * cy + forward * sy, forward * cy - right * sy);
        let norm = (right * right + forward * forward + up * up).sqrt();
        let lon = right.atan2(forward);
        let lat = (up / norm).asin();
        (lon / (2.0 * PI) + 0.5, 0.5 - lat / PI)
    }

    /// Points to check: the viewport's centre and four points halfway to its corners.
    fn probes(&self) -> Vec<(u32, u32)> {
        let (x0, y0, w, h) = self.viewport;
        [
            (0.5, 0.5),
            (0.25, 0.25),
            (0.75, 0.25),
            (0.25, 0.75),
            (0.75, 0.75),
        ]
        .iter()
        .map(|(a, b)| ((x0 + a * w) as u32, (y0 + b * h) as u32))
        .collect()
    }
}

/// Worst channel difference between the screenshot and `expected(u, v)` over the probes.
fn worst_difference(
    shot: &RgbaImage,
    view: &View,
    expected: impl Fn(f64, f64) -> [f64; 3],
) -> (f64, String) {
    let mut worst = (0.0, String::new());
    for (px, py) in view.probes() {
        let (u, v) = view.uv(px, py);
        let want = expected(u, v);
        let got = shot.get_pixel(px, py).0;
        for c in 0..3 {
            let d = (f64::from(got[c]) - want[c]).abs();
            if d >= worst.0 {
                worst = (
                    d,
                    format!("pixel ({px}, {py}) of {view:?}: got {got:?}, expected {want:.1?}"),
                );
            }
        }
    }
    worst
}

fn set_view(tab: &Tab, yaw: f64, pitch: f64, fov: f64) {
    js(tab, &format!("viewer.setView({yaw}, {pitch}, {fov})"));
}

fn full_page(tab: &Tab, yaw: f64, pitch: f64, fov: f64) -> View {
    let (w, h) = page_size(tab);
    View {
        yaw,
        pitch,
        fov,
        viewport: (0.0, 0.0, f64::from(w), f64::from(h)),
    }
}

/// Expected colour of the mono direction image: codes of u and v, blue as written.
fn mono_colour(blue: f64) -> impl Fn(f64, f64) -> [f64; 3] {
    move |u, v| [code(u) - 0.5, code(v) - 0.5, blue]
}

#[test]
fn each_pixel_shows_the_colour_of_its_view_direction() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("directions.png");
    direction_image(2048, 128, false).save(&file).unwrap();
    let server = serve(&file);
    let chromium = launch(path);
    let tab = open_viewer(&chromium, &format!("http://{}/", server.addr()), None);

    let opened = js(&tab, "viewer.view()");
    assert_eq!(opened, serde_json::json!({"yaw": 0, "pitch": 0, "fov": 90}));

    // The page opens on the heading: the image centre.
    let shot = screenshot(&tab);
    let (worst, at) = worst_difference(&shot, &full_page(&tab, 0.0, 0.0, 90.0), mono_colour(128.0));
    assert!(worst <= TOLERANCE, "opening view: {worst} at {at}");

    for (yaw, pitch, fov) in [
        (35.0, 20.0, 60.0),
        (-110.0, -30.0, 75.0),
        (120.0, 45.0, 50.0),
    ] {
        set_view(&tab, yaw, pitch, fov);
        let shot = screenshot(&tab);
        let view = full_page(&tab, yaw, pitch, fov);
        let (worst, at) = worst_difference(&shot, &view, mono_colour(128.0));
        assert!(worst <= TOLERANCE, "{worst} at {at}");
    }
}

#[test]
fn dragging_grabs_the_image_and_the_wheel_zooms() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("directions.png");
    direction_image(2048, 64, false).save(&file).unwrap();
    let server = serve(&file);
    let chromium = launch(path);
    let tab = open_viewer(&chromium, &format!("http://{}/", server.addr()), None);

    use Input::DispatchMouseEventTypeOption as M;
    let (w, h) = page_size(&tab);
    let (x, y) = (f64::from(w / 2), f64::from(h / 2));
    mouse(&tab, M::MouseMoved, x, y, false);
    mouse(&tab, M::MousePressed, x, y, true);
    for step in 1..=10 {
        let t = f64::from(step) / 10.0;
        mouse(&tab, M::MouseMoved, x - 100.0 * t, y - 50.0 * t, true);
    }
    mouse(&tab, M::MouseReleased, x - 100.0, y - 50.0, false);
    // 100 px left and 50 px up at 2 tan(45°)/h rad per pixel: the image follows the
    // pointer, so the view turns right and down (by 25.1° and 12.5° on a 457 px page).
    let per_pixel = (2.0 / f64::from(h)).to_degrees();
    let view = js(&tab, "viewer.view()");
    let (yaw, pitch) = (
        view["yaw"].as_f64().unwrap(),
        view["pitch"].as_f64().unwrap(),
    );
    assert!((yaw - 100.0 * per_pixel).abs() < 0.01, "yaw {yaw}");
    assert!((pitch + 50.0 * per_pixel).abs() < 0.01, "pitch {pitch}");
    js(
        &tab,
        "viewer.setView(viewer.view().yaw, viewer.view().pitch)",
    );
    let shot = screenshot(&tab);
    let (worst, at) =
        worst_difference(&shot, &full_page(&tab, yaw, pitch, 90.0), mono_colour(64.0));
    assert!(worst <= TOLERANCE, "after the drag: {worst} at {at}");

    tab.call_method(Input::DispatchMouseEvent {
        Type: M::MouseWheel,
        x,
        y,
        modifiers: None,
        timestamp: None,
        button: None,
        buttons: None,
        click_count: None,
        force: None,
        tangential_pressure: None,
        tilt_x: None,
        tilt_y: None,
        twist: None,
        delta_x: Some(0.0),
        delta_y: Some(100.0),
        pointer_Type: None,
    })
    .unwrap();
    // Scrolling down widens the view by e^(0.001 * deltaY).
    let fov = js(
        &tab,
        "new Promise((r) => setTimeout(r, 100)).then(() => viewer.view().fov)",
    )
    .as_f64()
    .unwrap();
    assert!((fov - 90.0 * 0.1_f64.exp()).abs() < 0.01, "fov {fov}");
}

/// An ODS pair of direction images: left eye (top) as [`direction_image`] with blue 32, right
/// eye (bottom) with red and green inverted and blue 224.
fn ods_image(width: u32) -> RgbImage {
    let left = direction_image(width, 32, false);
    let right = direction_image(width, 224, true);
    let mut pair = RgbImage::new(width, width);
    image::imageops::replace(&mut pair, &left, 0, 0);
    image::imageops::replace(&mut pair, &right, 0, i64::from(width / 2));
    pair
}

fn left_colour(u: f64, v: f64) -> [f64; 3] {
    [code(u) - 0.5, code(v) - 0.5, 32.0]
}

fn right_colour(u: f64, v: f64) -> [f64; 3] {
    [255.5 - code(u), 255.5 - code(v), 224.0]
}

/// The project's own half-colour anaglyph of the two eyes' colours.
fn anaglyph_colour(u: f64, v: f64) -> [f64; 3] {
    let byte = |c: [f64; 3]| c.map(|x| x.round().clamp(0.0, 255.0) as u8);
    let [lr, lg, lb] = byte(left_colour(u, v));
    let [rr, rg, rb] = byte(right_colour(u, v));
    anaglyph_pixel(
        [lr, lg, lb, 255],
        [rr, rg, rb, 255],
        AnaglyphMethod::HalfColor,
    )
    .map(f64::from)
}

#[test]
fn an_ods_pair_shows_each_eye_and_a_red_cyan_anaglyph() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("pair.png");
    ods_image(2048).save(&file).unwrap();
    let server = serve(&file);
    let chromium = launch(path);
    let tab = open_viewer(
        &chromium,
        &format!("http://{}/?mode=anaglyph", server.addr()),
        None,
    );
    assert_eq!(js(&tab, "viewer.mode()"), serde_json::json!("anaglyph"));
    assert_eq!(
        js(&tab, "document.getElementById('mode-box').hidden"),
        serde_json::json!(false)
    );

    let view = full_page(&tab, 25.0, 10.0, 70.0);
    set_view(&tab, view.yaw, view.pitch, view.fov);
    let shot = screenshot(&tab);
    let (worst, at) = worst_difference(&shot, &view, anaglyph_colour);
    assert!(worst <= ANAGLYPH_TOLERANCE, "anaglyph: {worst} at {at}");
    // Red comes from the left eye alone, green and blue from the right eye alone.
    let (w, h) = page_size(&tab);
    let c = shot.get_pixel(w / 2, h / 2).0;
    assert!(c[2] > 200, "blue is the right eye's 224: {c:?}");

    for (mode, expected) in [
        ("mono", left_colour as fn(f64, f64) -> [f64; 3]),
        ("left", left_colour),
        ("right", right_colour),
    ] {
        js(&tab, &format!("viewer.setMode('{mode}')"));
        let shot = screenshot(&tab);
        let (worst, at) = worst_difference(&shot, &view, expected);
        assert!(worst <= TOLERANCE, "{mode}: {worst} at {at}");
    }
}

#[test]
fn enter_vr_asks_for_immersive_vr_and_draws_each_eye_from_its_half() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("pair.png");
    ods_image(2048).save(&file).unwrap();
    let server = serve(&file);
    let chromium = launch(path);
    let tab = open_viewer(
        &chromium,
        &format!("http://{}/", server.addr()),
        Some(XR_STUB),
    );
    // The headset starts at the page's heading.
    set_view(&tab, 40.0, 0.0, 90.0);
    let button = tab.wait_for_element("#enter-vr:not([disabled])").unwrap();
    button.click().unwrap();
    let frames = js(
        &tab,
        "new Promise((resolve) => { const wait = () => window.__xr.frames >= 3 ? \
         resolve(window.__xr.frames) : setTimeout(wait, 20); wait(); })",
    );
    assert!(frames.as_u64().unwrap() >= 3);
    let log = js(&tab, "window.__xr");
    assert_eq!(log["requested"], serde_json::json!(["immersive-vr"]));
    assert_eq!(log["spaces"], serde_json::json!(["local"]));
    assert_eq!(log["layers"], 1);
    let (w, h) = page_size(&tab);
    let views = js(&tab, "viewer.xrViews");
    assert_eq!(
        views,
        serde_json::json!([
            {"eye": "left", "viewport": [0, 0, w / 2, h]},
            {"eye": "right", "viewport": [w / 2, 0, w / 2, h]},
        ])
    );
    assert_eq!(
        js(&tab, "document.getElementById('enter-vr').textContent"),
        "Exit VR"
    );

    // 40° heading + 25° head turn; GL's viewport y counts from the bottom, the same rows here.
    let eye = |x0: f64| View {
        yaw: 65.0,
        pitch: 0.0,
        fov: 90.0,
        viewport: (x0, 0.0, f64::from(w / 2), f64::from(h)),
    };
    let shot = screenshot(&tab);
    let (worst, at) = worst_difference(&shot, &eye(0.0), left_colour);
    assert!(worst <= TOLERANCE, "left eye: {worst} at {at}");
    let (worst, at) = worst_difference(&shot, &eye(f64::from(w / 2)), right_colour);
    assert!(worst <= TOLERANCE, "right eye: {worst} at {at}");

    tab.find_element("#enter-vr").unwrap().click().unwrap();
    assert_eq!(
        js(&tab, "document.getElementById('enter-vr').textContent"),
        "Enter VR"
    );
}

#[test]
fn a_tour_folder_steps_and_plays_through_its_frames() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let colours = [[200u8, 30, 30], [30, 200, 30], [30, 30, 200]];
    for (k, c) in colours.iter().enumerate() {
        RgbImage::from_pixel(256, 128, Rgb(*c))
            .save(dir.path().join(format!("frame_{k:06}.png")))
            .unwrap();
    }
    let server = serve(dir.path());
    let chromium = launch(path);
    let tab = open_viewer(
        &chromium,
        &format!("http://{}/?frame=1", server.addr()),
        None,
    );
    let (w, h) = page_size(&tab);
    let centre = |tab: &Tab| screenshot(tab).get_pixel(w / 2, h / 2).0;
    assert_eq!(js(&tab, "viewer.frame()"), 1);
    assert_eq!(&centre(&tab)[..3], &colours[1]);
    assert_eq!(
        js(&tab, "document.getElementById('frame-label').textContent"),
        "2 / 3"
    );
    // An ordinary tour has no stations to hop between.
    assert_eq!(js(&tab, "document.getElementById('stations').hidden"), true);

    js(&tab, "viewer.setFrame(2)");
    assert_eq!(&centre(&tab)[..3], &colours[2]);
    assert_eq!(js(&tab, "document.getElementById('frame').value"), "2");

    // Play steps one frame at a time, from the last to the first; pause holds the frame.
    tab.find_element("#play").unwrap().click().unwrap();
    let seen = js(
        &tab,
        "new Promise((resolve) => { const seen = []; const poll = () => { \
         const f = viewer.frame(); if (seen[seen.length - 1] !== f) seen.push(f); \
         if (seen.length >= 4) resolve(seen); else setTimeout(poll, 5); }; poll(); })",
    );
    let seen: Vec<u64> = serde_json::from_value(seen).unwrap();
    for pair in seen.windows(2) {
        assert_eq!(
            pair[1],
            (pair[0] + 1) % 3,
            "frames shown in order: {seen:?}"
        );
    }
    tab.find_element("#play").unwrap().click().unwrap();
    let held = js(
        &tab,
        "new Promise((r) => setTimeout(r, 300)).then(() => viewer.frame())",
    );
    let later = js(
        &tab,
        "new Promise((r) => setTimeout(r, 300)).then(() => viewer.frame())",
    );
    assert_eq!(held, later, "paused playback still advances");
}

#[test]
fn a_station_folder_lists_and_maps_its_stations_and_a_click_shows_one() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let colours = [[200u8, 30, 30], [30, 30, 200]];
    for (k, c) in colours.iter().enumerate() {
        RgbImage::from_pixel(256, 128, Rgb(*c))
            .save(dir.path().join(format!("frame_{k:06}.png")))
            .unwrap();
    }
    // What `render FILE.e57 --camera station:all` records: North in the north-east, South
    // to the south-west of it.
    std::fs::write(
        dir.path().join("tour.json"),
        r#"{"version": 1, "path": "stations", "fps": 30, "frames": [{}, {}], "stations": [
            {"frame": 0, "scan": 0, "name": "North", "position": [10, 20, 1.5]},
            {"frame": 1, "scan": 1, "name": "South", "position": [-5, 3, 0.5]}]}"#,
    )
    .unwrap();
    let server = serve(dir.path());
    let chromium = launch(path);
    let tab = open_viewer(&chromium, &format!("http://{}/", server.addr()), None);
    let (w, h) = page_size(&tab);
    let centre = |tab: &Tab| screenshot(tab).get_pixel(w / 2, h / 2).0;
    assert_eq!(
        js(&tab, "document.getElementById('stations').hidden"),
        false
    );
    assert_eq!(
        js(
            &tab,
            "[...document.querySelectorAll('#station-list button')].map((b) => b.textContent)"
        ),
        serde_json::json!(["North", "South"])
    );
    // The markers keep the plan: South lies left of and below North.
    let markers = js(
        &tab,
        "[...document.querySelectorAll('#station-map circle')].map((c) =>          [Number(c.getAttribute('cx')), Number(c.getAttribute('cy'))])",
    );
    let markers: Vec<[f64; 2]> = serde_json::from_value(markers).unwrap();
    assert_eq!(markers.len(), 2);
    assert!(
        markers[1][0] < markers[0][0] && markers[1][1] > markers[0][1],
        "{markers:?}"
    );
    assert_eq!(js(&tab, "viewer.frame()"), 0);
    assert_eq!(&centre(&tab)[..3], &colours[0]);

    // A click on the second marker shows the second station's panorama.
    tab.find_element("#station-map circle:nth-of-type(2)")
        .unwrap()
        .click()
        .unwrap();
    let wait_frame = |n: u32| {
        js(
            &tab,
            &format!(
                "new Promise((resolve) => {{ const wait = () => viewer.frame() === {n} ? \
                 requestAnimationFrame(() => requestAnimationFrame(() => resolve(true))) : \
                 setTimeout(wait, 10); wait(); }})"
            ),
        )
    };
    wait_frame(1);
    assert_eq!(&centre(&tab)[..3], &colours[1]);
    assert_eq!(
        js(
            &tab,
            "document.querySelector('#station-map circle.current').dataset.frame"
        ),
        "1"
    );
    // And the list's first entry goes back to the first.
    tab.find_element("#station-list li:nth-of-type(1) button")
        .unwrap()
        .click()
        .unwrap();
    wait_frame(0);
    assert_eq!(&centre(&tab)[..3], &colours[0]);
}

/// Colour of frame `k` of the video test, left eye (`eye` 0) or right: red counts frames.
#[cfg(feature = "video")]
fn video_colour(k: usize, eye: usize) -> [u8; 3] {
    [
        40 + 8 * k as u8,
        if eye == 0 { 200 } else { 60 },
        if eye == 0 { 60 } else { 200 },
    ]
}

/// The frame a red value stands for (frames are 8 codes apart).
#[cfg(feature = "video")]
fn video_frame_of(red: u8) -> i64 {
    ((f64::from(red) - 40.0) / 8.0).round() as i64
}

/// A 24-frame, 12 fps top-bottom MP4 of flat `video_colour` eyes, in `dir`.
#[cfg(feature = "video")]
fn colour_video(dir: &Path) -> std::path::PathBuf {
    use omnicloud::video::{VideoOptions, encode_folder};
    for k in 0..24 {
        let frame = RgbImage::from_fn(256, 256, |_, j| Rgb(video_colour(k, (j >= 128) as usize)));
        frame.save(dir.join(format!("frame_{k:06}.png"))).unwrap();
    }
    let mp4 = dir.join("tour.mp4");
    let options = VideoOptions {
        fps: Some(12.0),
        ..VideoOptions::default()
    };
    encode_folder(dir, &mp4, &options, &indicatif::ProgressBar::hidden()).unwrap();
    mp4
}

#[cfg(feature = "video")]
#[test]
fn an_mp4_plays_in_vr_with_each_eye_from_its_half() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&colour_video(dir.path()));
    let chromium = launch(path);
    let tab = open_viewer(
        &chromium,
        &format!("http://{}/", server.addr()),
        Some(XR_STUB),
    );
    tab.wait_for_element("#enter-vr:not([disabled])")
        .unwrap()
        .click()
        .unwrap();
    js(&tab, "viewer.play()");
    // Wait until the headset has drawn while the video is a few frames in.
    js(
        &tab,
        "new Promise((resolve) => { const start = window.__xr.frames; const wait = () => \
         viewer.frame() >= 4 && window.__xr.frames > start + 2 ? resolve() : setTimeout(wait, 20); \
         wait(); })",
    );
    js(&tab, "viewer.pause()");
    let frames = js(
        &tab,
        "new Promise((r) => setTimeout(r, 300)).then(() => window.__xr.frames)",
    );
    assert!(frames.as_u64().unwrap() >= 3);
    let (w, h) = page_size(&tab);
    let shot = screenshot(&tab);
    let left = shot.get_pixel(w / 4, h / 2).0;
    let right = shot.get_pixel(3 * w / 4, h / 2).0;
    eprintln!("VR: left eye {left:?}, right eye {right:?}");
    // Each eye shows its own half of the pair (green-heavy left, blue-heavy right), of a
    // frame past the first: the video played in the headset's frame loop.
    assert!(left[1] > 190 && left[2] < 70, "left eye shows {left:?}");
    assert!(right[1] < 70 && right[2] > 190, "right eye shows {right:?}");
    assert!(video_frame_of(left[0]) >= 4, "left eye shows {left:?}");
    assert_eq!(video_frame_of(left[0]), video_frame_of(right[0]));
}

#[cfg(feature = "video")]
#[test]
fn an_mp4_plays_as_the_panorama_with_its_stereo_from_st3d() {
    let Some(path) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&colour_video(dir.path()));
    let chromium = launch(path);
    let tab = open_viewer(&chromium, &format!("http://{}/", server.addr()), None);
    let info = js(&tab, "viewer.info");
    assert_eq!(info["kind"], "ods", "{info}");
    assert_eq!(info["video"], serde_json::json!({"frames": 24, "fps": 12}));
    let (w, h) = page_size(&tab);
    let centre = |tab: &Tab| {
        let p = screenshot(tab).get_pixel(w / 2, h / 2).0;
        [p[0], p[1], p[2]]
    };
    // H.264 keeps a flat colour within a few codes (measured: 2).
    let near = |got: [u8; 3], want: [u8; 3], what: &str| {
        let d = got
            .iter()
            .zip(want)
            .map(|(&a, b)| (i32::from(a) - i32::from(b)).abs())
            .max()
            .unwrap();
        eprintln!("{what}: got {got:?}, expected {want:?}");
        assert!(d <= 4, "{what}: got {got:?}, expected {want:?}");
    };

    // The first frame, left eye on top (st3d top-bottom); then the right eye.
    near(centre(&tab), video_colour(0, 0), "frame 0, left eye");
    js(&tab, "viewer.setMode('right')");
    near(centre(&tab), video_colour(0, 1), "frame 0, right eye");
    js(&tab, "viewer.setMode('mono')");

    // The slider seeks.
    js(&tab, "viewer.setFrame(10)");
    near(centre(&tab), video_colour(10, 0), "frame 10");
    assert_eq!(js(&tab, "document.getElementById('frame').value"), "10");
    assert_eq!(
        js(&tab, "document.getElementById('frame-label').textContent"),
        "11 / 24"
    );

    // Play advances the video, the slider and the picture; pause holds them.
    js(&tab, "viewer.setFrame(0)");
    js(&tab, "viewer.play()");
    let seen = js(
        &tab,
        "new Promise((resolve) => { const seen = []; const poll = () => { \
         const f = viewer.frame(); if (seen[seen.length - 1] !== f) seen.push(f); \
         if (seen.length >= 4) resolve(seen); else setTimeout(poll, 5); }; poll(); })",
    );
    let seen: Vec<i64> = serde_json::from_value(seen).unwrap();
    eprintln!("frames seen while playing: {seen:?}");
    // Forward, wrapping at most once (the video loops; a loaded machine may poll late).
    let wraps = seen.windows(2).filter(|p| p[1] < p[0]).count();
    assert!(wraps <= 1, "frames shown in order: {seen:?}");
    let playing = centre(&tab);
    let shown = video_frame_of(playing[0]);
    assert!(shown >= 1, "the picture advanced with play: {playing:?}");
    js(&tab, "viewer.pause()");
    let held = js(
        &tab,
        "new Promise((r) => setTimeout(r, 300)).then(() => [viewer.frame(), viewer.videoState().paused])",
    );
    let frame = held[0].as_u64().unwrap() as usize;
    assert_eq!(held[1], true);
    let shot = centre(&tab);
    near(shot, video_colour(frame, 0), "paused frame");
    let later = js(
        &tab,
        "new Promise((r) => setTimeout(r, 300)).then(() => viewer.frame())",
    );
    assert_eq!(held[0], later, "paused playback still advances");
}
