//! `omnicloud serve`'s page on the sample scan in a real headless Chromium: clicking the map
//! renders from the clicked spot; moving a pole-merge slider (fast, as a drag does) ends on a
//! render of its last value that differs from the previous one near the pole and not at the
//! horizon; a busy answer (503, Retry-After) to the newest request is asked again and its
//! render shown; with a stub WebXR runtime, "Enter VR" asks for `immersive-vr` and draws both
//! eyes. Chromium and its flags: `browser_common`. Without Chromium the tests skip with a
//! notice (and fail under `OMNICLOUD_REQUIRE_BROWSER=1`); without a GPU adapter they follow
//! the GPU rule (`OMNICLOUD_REQUIRE_GPU=1`).
#![cfg(all(feature = "web", feature = "gpu"))]

mod browser_common;
mod http_common;
mod serve_common;

use std::net::SocketAddr;
use std::sync::Arc;

use browser_common::{Chromium, XR_STUB, chromium, js, launch, mouse, open_viewer, screenshot};
use headless_chrome::Tab;
use headless_chrome::protocol::cdp::Input::DispatchMouseEventTypeOption as M;
use image::RgbaImage;
use indicatif::ProgressBar;
use omnicloud::prepare::{PrepareOptions, prepare};
use omnicloud::web::Running;
use serve_common::{UNDER_TREES, sample, start_live};

/// Panorama width of the served renders.
const WIDTH: u32 = 256;

/// A live server of the sample; `None` (after the GPU rule's notice) without an adapter.
fn start() -> Option<Running> {
    let scene = prepare(
        &sample(),
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap()
    .scene;
    start_live(scene, WIDTH)
}

/// Chromium, and the server, or `None` when either is missing (after its notice).
fn set_up() -> Option<(Chromium, Running)> {
    let path = chromium()?;
    let server = start()?;
    Some((launch(path), server))
}

/// Opens the page and waits for its first render to be on screen.
fn open_page(chromium: &Chromium, addr: SocketAddr, init: Option<&str>) -> Arc<Tab> {
    let tab = open_viewer(chromium, &format!("http://{addr}/"), init);
    let ready = js(&tab, "live.ready.then(() => 'ok', (e) => 'error: ' + e)");
    assert_eq!(
        ready,
        "ok",
        "the page did not start: {}",
        js(&tab, "live.error")
    );
    tab
}

/// Waits until the page shows a render at least as new as its newest request; fails with
/// the page's state after a minute.
fn settled(tab: &Tab) -> serde_json::Value {
    let v = js(
        tab,
        "Promise.race([live.settled(), new Promise((resolve) => setTimeout(() => resolve({ \
         timeout: true, seq: live.seq, shown: live.shownSeq, error: live.error, \
         status: document.getElementById('status').textContent }), 60000))])",
    );
    assert!(v.get("timeout").is_none(), "no render arrived: {v}");
    v
}

/// The render the page shows, fetched again from the server (renders are deterministic).
fn fetch_shown(tab: &Tab, addr: SocketAddr) -> RgbaImage {
    let url = js(tab, "live.lastRender.url");
    let r = http_common::get(addr, url.as_str().unwrap());
    assert_eq!(r.status, 200, "{}", r.text());
    image::load_from_memory(&r.body).unwrap().to_rgba8()
}

#[test]
fn clicking_the_map_renders_from_the_clicked_spot() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let addr = server.addr();
    let tab = open_page(&chromium, addr, None);
    let scan = js(&tab, "live.scan");
    let first = js(&tab, "live.lastRender");
    for k in 0..2 {
        let (a, b) = (first["camera"][k].as_f64(), scan["camera"][k].as_f64());
        assert!((a.unwrap() - b.unwrap()).abs() < 1e-6, "{first} vs {scan}");
    }

    // Click where the map shows the spot under the trees.
    let map = &scan["map"];
    let f = |key: &str| map[key].as_f64().unwrap();
    let rect = js(
        &tab,
        "(() => { const r = document.getElementById('map').getBoundingClientRect(); \
         return [r.left, r.top, r.width, r.height]; })()",
    );
    let r = |k: usize| rect[k].as_f64().unwrap();
    let (x, y) = UNDER_TREES;
    let cx = r(0) + (x - f("x0")) / f("pixel") / f("width") * r(2);
    let cy = r(1) + (f("y1") - y) / f("pixel") / f("height") * r(3);
    let before = js(&tab, "live.seq").as_u64().unwrap();
    mouse(&tab, M::MouseMoved, cx, cy, false);
    mouse(&tab, M::MousePressed, cx, cy, true);
    mouse(&tab, M::MouseReleased, cx, cy, false);
    let seq = js(
        &tab,
        &format!(
            "new Promise((resolve) => {{ const wait = () => live.seq > {before} ? \
             resolve(live.seq) : setTimeout(wait, 10); wait(); }})"
        ),
    );
    let shown = settled(&tab);
    assert_eq!(shown["seq"], seq, "the click's render is on screen");
    // The page clicks at whole CSS pixels: within one of them, and so within a map pixel.
    let tolerance = f("pixel") * f("width") / r(2);
    let camera = &shown["camera"];
    let (got_x, got_y) = (camera[0].as_f64().unwrap(), camera[1].as_f64().unwrap());
    assert!(
        (got_x - x).abs() <= tolerance && (got_y - y).abs() <= tolerance,
        "clicked ({x}, {y}), the render stands at ({got_x}, {got_y}); tolerance {tolerance} m"
    );
    assert!(
        tolerance <= f("pixel"),
        "a CSS pixel is at most a map pixel"
    );
    // The camera stands above the ground under the trees, lower than at the scan's centre.
    let z = camera[2].as_f64().unwrap();
    assert!((415.0..430.0).contains(&z), "camera height {z}");
    // The marker sits on the clicked spot, and the readout names the camera.
    let marker = js(
        &tab,
        "(() => { const r = document.getElementById('marker').getBoundingClientRect(); \
         return [r.left + r.width / 2, r.top + r.height / 2]; })()",
    );
    assert!((marker[0].as_f64().unwrap() - cx).abs() < 2.0, "{marker:?}");
    assert!((marker[1].as_f64().unwrap() - cy).abs() < 2.0, "{marker:?}");
    let readout = js(&tab, "document.getElementById('camera').textContent");
    assert!(
        readout.as_str().unwrap().starts_with("camera 6362"),
        "{readout}"
    );
    assert!(
        js(&tab, "document.getElementById('timing').textContent")
            .as_str()
            .unwrap()
            .starts_with("rendered in")
    );
}

#[test]
fn a_busy_answer_to_the_newest_request_is_asked_again_and_its_render_shown() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let addr = server.addr();
    let tab = open_page(&chromium, addr, None);
    // The server's answer when more renders wait than it lets wait (`RenderFailure::Busy`),
    // given here to the page's next render request.
    js(
        &tab,
        "(() => { const real = window.fetch; let busy = 1; \
         window.fetch = (url, options) => String(url).startsWith('/api/render') && busy-- > 0 \
           ? Promise.resolve(new Response('too many renders asked for at once; try again later', \
               { status: 503, headers: { 'Retry-After': '1' } })) \
           : real(url, options); })()",
    );
    let before = js(&tab, "live.seq").as_u64().unwrap();
    let (x, y) = UNDER_TREES;
    let started = std::time::Instant::now();
    js(&tab, &format!("live.standAt({x}, {y})"));
    let shown = settled(&tab);
    let waited = started.elapsed();
    assert_eq!(
        shown["seq"].as_u64(),
        Some(before + 2),
        "the busy request is asked again once and that render shown: {shown}"
    );
    assert_eq!(js(&tab, "live.error"), serde_json::Value::Null);
    assert!(
        shown["url"]
            .as_str()
            .unwrap()
            .contains(&format!("seq={}", before + 2)),
        "{shown}"
    );
    // It waited the pause the server named (1 s) before asking again.
    assert!(waited.as_secs_f64() >= 1.0, "asked again after {waited:?}");
    let camera = &shown["camera"];
    assert!((camera[0].as_f64().unwrap() - x).abs() < 0.5, "{shown}");
    assert!((camera[1].as_f64().unwrap() - y).abs() < 0.5, "{shown}");
}

/// Rows of one eye of a top-bottom pair whose latitude lies in `lat` (degrees).
fn rows(eye: u32, lat: std::ops::Range<f64>) -> impl Iterator<Item = u32> {
    let h = WIDTH / 2;
    (0..h)
        .filter(move |j| lat.contains(&(90.0 - (f64::from(*j) + 0.5) / f64::from(h) * 180.0)))
        .map(move |j| j + eye * h)
}

fn differing(a: &RgbaImage, b: &RgbaImage, rows: impl Iterator<Item = u32>) -> usize {
    rows.map(|j| {
        (0..a.width())
            .filter(|&i| a.get_pixel(i, j) != b.get_pixel(i, j))
            .count()
    })
    .sum()
}

#[test]
fn a_fast_pole_merge_slider_ends_on_its_last_value_and_changes_only_the_pole_rows() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let addr = server.addr();
    let tab = open_page(&chromium, addr, None);
    // A wide IPD (the slider's end) makes merging visible at 256 pixels across.
    let (x, y) = UNDER_TREES;
    js(
        &tab,
        "(() => { const s = document.getElementById('ipd'); s.value = '0.2'; \
         s.dispatchEvent(new Event('input')); })()",
    );
    js(&tab, &format!("live.standAt({x}, {y})"));
    let before = fetch_shown(&tab, addr);
    let url = js(&tab, "live.lastRender.url");
    assert!(
        url.as_str()
            .unwrap()
            .contains("ipd=0.2&north=marrinan%3A45%2C0%2C3"),
        "{url}"
    );

    // Drag the north start from 45° from the pole down to 0° (merging off), one input event
    // per degree and no waiting: the server answers replaced requests with 409 and the page
    // ignores late answers, so the render shown is the last value's.
    js(
        &tab,
        "(() => { const s = document.getElementById('north-start'); \
         for (let v = 44; v >= 0; v--) { s.value = String(v); \
         s.dispatchEvent(new Event('input')); } })()",
    );
    let shown = settled(&tab);
    assert_eq!(
        shown["seq"],
        js(&tab, "live.seq"),
        "the last request's render is shown (shown {shown}, error {})",
        js(&tab, "live.error")
    );
    let url = shown["url"].as_str().unwrap();
    assert!(url.contains("north=marrinan%3A0%2C0%2C3"), "{url}");
    assert!(url.contains("south=marrinan%3A45%2C0%2C3"), "{url}");
    assert_eq!(
        js(
            &tab,
            "document.getElementById('north-start-value').textContent"
        ),
        "0"
    );
    let after = fetch_shown(&tab, addr);

    // Merging covered latitudes above 45° and now none: the rows up to 30° (the horizon and
    // the whole southern half) keep every pixel, the rows above 45° change (measured: 401
    // and 402 of their 8192 pixels).
    for eye in 0..2 {
        assert_eq!(
            differing(&before, &after, rows(eye, -90.0..30.0)),
            0,
            "eye {eye}"
        );
        let top = differing(&before, &after, rows(eye, 45.0..90.0));
        assert!(top > 200, "eye {eye}: only {top} pixels above 45° changed");
    }
}

#[test]
fn enter_vr_asks_for_immersive_vr_and_draws_both_eyes_of_the_live_render() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let tab = open_page(&chromium, server.addr(), Some(XR_STUB));
    tab.find_element("#toggle-panel").unwrap().click().unwrap();
    let button = tab.wait_for_element("#enter-vr:not([disabled])").unwrap();
    button.click().unwrap();
    let wait_frames = |n: u64| {
        js(
            &tab,
            &format!(
                "new Promise((resolve) => {{ const wait = () => window.__xr.frames >= {n} ? \
                 resolve(window.__xr.frames) : setTimeout(wait, 20); wait(); }})"
            ),
        )
        .as_u64()
        .unwrap()
    };
    let frames = wait_frames(3);
    let log = js(&tab, "window.__xr");
    assert_eq!(log["requested"], serde_json::json!(["immersive-vr"]));
    let views = js(&tab, "viewer.xrViews");
    assert_eq!(views[0]["eye"], "left");
    assert_eq!(views[1]["eye"], "right");
    assert_eq!(views.as_array().unwrap().len(), 2);

    // A new render while in VR reaches the headset's views.
    js(
        &tab,
        "(() => { const s = document.getElementById('ipd'); s.value = '0.2'; \
         s.dispatchEvent(new Event('input')); })()",
    );
    let shown = settled(&tab);
    assert!(
        shown["url"].as_str().unwrap().contains("ipd=0.2"),
        "{shown}"
    );
    wait_frames(frames + 2);
    // Both eyes' viewports show the scan (the stub draws them side by side on the page).
    let shot = screenshot(&tab);
    let (w, h) = shot.dimensions();
    for (eye, x0) in [("left", 0), ("right", w / 2)] {
        let lit = (x0..x0 + w / 2)
            .flat_map(|i| (h / 2..h * 3 / 4).map(move |j| (i, j)))
            .filter(|&(i, j)| shot.get_pixel(i, j).0[..3].iter().any(|&c| c > 40))
            .count();
        // Measured: 31659 and 32150 of 45600.
        assert!(lit > 20_000, "the {eye} eye shows {lit} lit pixels");
    }
    // Each eye samples its own half of the pair: at 0.2 m IPD the near ground differs.
    let differ = (0..w / 2)
        .flat_map(|i| (h / 2..h * 3 / 4).map(move |j| (i, j)))
        .filter(|&(i, j)| shot.get_pixel(i, j) != shot.get_pixel(i + w / 2, j))
        .count();
    // Measured: 21677 of 45600 (the same half for both would differ in none).
    assert!(differ > 5000, "the eyes differ in {differ} pixels");
}
