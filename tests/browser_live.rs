//! `omnicloud serve`'s live walking in a real headless Chromium, over the live stream: holding
//! W walks forward along the heading (the frames shown come from increasing positions that
//! way, and the server's camera follows the keys); in VR (the stand-in WebXR runtime) pushing
//! the left thumbstick forward walks where the head looks. Chromium and its flags:
//! `browser_common`; without Chromium or a GPU adapter the tests skip with a notice, as
//! `browser_serve.rs` describes.
#![cfg(all(feature = "web", feature = "gpu"))]

mod browser_common;
mod serve_common;

use std::sync::Arc;
use std::time::Duration;

use browser_common::{Chromium, XR_STUB, chromium, js, launch, open_viewer};
use headless_chrome::Tab;
use headless_chrome::protocol::cdp::Input;
use indicatif::ProgressBar;
use omnicloud::prepare::{PrepareOptions, prepare};
use omnicloud::web::Running;
use omnicloud::web::serve::StreamOptions;
use omnicloud::web::serve::live::LiveScale;
use serve_common::{sample, start_live_streaming};

/// Panorama width of the streamed frames.
const WIDTH: u32 = 256;

fn set_up() -> Option<(Chromium, Running)> {
    let path = chromium()?;
    let scene = prepare(
        &sample(),
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap()
    .scene;
    let stream = StreamOptions {
        scale: LiveScale::Full,
        ..StreamOptions::default()
    };
    let server = start_live_streaming(scene, WIDTH, stream)?;
    Some((launch(path), server))
}

/// Opens the page (with `init` before its scripts) and waits until the stream is open.
fn open_walk(chromium: &Chromium, server: &Running, init: Option<&str>) -> Arc<Tab> {
    let tab = open_viewer(chromium, &format!("http://{}/", server.addr()), init);
    let ready = js(&tab, "walk.ready.then(() => 'ok', (e) => 'error: ' + e)");
    assert_eq!(
        ready,
        "ok",
        "the page did not start: {}",
        js(&tab, "walk.error")
    );
    // Every frame shown from now on, in order.
    js(
        &tab,
        "(() => { window.__shown = []; const show = viewer.showImage; \
              viewer.showImage = (image, kind) => { if (walk.last) __shown.push(walk.last); \
              return show(image, kind); }; })()",
    );
    tab
}

fn key(tab: &Tab, kind: Input::DispatchKeyEventTypeOption, name: &str, code: &str) {
    tab.call_method(Input::DispatchKeyEvent {
        Type: kind,
        modifiers: None,
        timestamp: None,
        text: None,
        unmodified_text: None,
        key_identifier: None,
        code: Some(code.into()),
        key: Some(name.into()),
        windows_virtual_key_code: None,
        native_virtual_key_code: None,
        auto_repeat: None,
        is_keypad: None,
        is_system_key: None,
        location: None,
        commands: None,
    })
    .unwrap();
}

/// Waits until a frame at least as new as the page's newest pose is on screen.
fn settled(tab: &Tab) -> serde_json::Value {
    let v = js(
        tab,
        "new Promise((resolve) => { const until = performance.now() + 60000; \
         const wait = () => walk.shownSeq >= walk.seq && walk.last && walk.last.still ? \
         resolve(walk.last) : performance.now() > until ? resolve({ timeout: true, \
         seq: walk.seq, shown: walk.shownSeq, error: walk.error }) : setTimeout(wait, 20); \
         wait(); })",
    );
    assert!(v.get("timeout").is_none(), "no frame arrived: {v}");
    v
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

#[test]
fn holding_w_walks_forward_along_the_heading() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let tab = open_walk(&chromium, &server, None);
    let scan = js(&tab, "live.scan");
    let (x0, y0) = (f(&scan["camera"][0]), f(&scan["camera"][1]));
    // Face east and let the still frame arrive.
    js(&tab, &format!("walk.standAt({x0}, {y0}, 90)"));
    let start = settled(&tab);
    assert_eq!(f(&start["camera"][0]), x0);
    js(&tab, "__shown.length = 0");

    key(
        &tab,
        Input::DispatchKeyEventTypeOption::KeyDown,
        "w",
        "KeyW",
    );
    std::thread::sleep(Duration::from_millis(2500));
    key(&tab, Input::DispatchKeyEventTypeOption::KeyUp, "w", "KeyW");
    let end = settled(&tab);
    let shown = js(&tab, "__shown");
    let moving: Vec<&serde_json::Value> = shown
        .as_array()
        .unwrap()
        .iter()
        .filter(|h| !h["still"].as_bool().unwrap())
        .collect();
    assert!(
        moving.len() >= 3,
        "only {} frames while walking: {shown}",
        moving.len()
    );
    // East: x grows frame after frame, y stays.
    let xs: Vec<f64> = moving.iter().map(|h| f(&h["camera"][0])).collect();
    assert!(xs.windows(2).all(|w| w[1] > w[0]), "{xs:?}");
    for h in &moving {
        assert!((f(&h["camera"][1]) - y0).abs() < 1e-6, "{h}");
        assert_eq!(f(&h["yaw"]), 90.0);
    }
    // 1.4 m/s for 2.5 s in feet, give or take the frames the page drew.
    let walked = f(&end["camera"][0]) - x0;
    let expected = 1.4 * 2.5 / 0.3048;
    assert!(
        walked > 0.5 * expected && walked < 1.5 * expected,
        "walked {walked} ft"
    );
    // The page's pose, the server's camera, the readout and the link agree.
    assert_eq!(f(&end["camera"][0]), f(&js(&tab, "walk.x")));
    let link = js(&tab, "document.getElementById('link').getAttribute('href')");
    assert!(
        link.as_str()
            .unwrap()
            .contains(&format!("x={:.2}", f(&end["camera"][0]))),
        "{link}"
    );
    assert!(link.as_str().unwrap().ends_with("yaw=90.0"), "{link}");
    let readout = js(&tab, "document.getElementById('walk').textContent");
    assert!(
        readout.as_str().unwrap().contains("heading 90°"),
        "{readout}"
    );

    // The link opens the same view in a new page.
    let url = format!("http://{}/{}", server.addr(), link.as_str().unwrap());
    let again = open_viewer(&chromium, &url, None);
    js(&again, "walk.ready");
    let reopened = settled(&again);
    assert!(
        (f(&reopened["camera"][0]) - f(&end["camera"][0])).abs() < 0.01,
        "{reopened}"
    );
    assert!((f(&js(&again, "viewer.view().yaw")) - 90.0).abs() < 1e-9);
}

#[test]
fn in_vr_the_left_thumbstick_walks_where_the_head_looks() {
    let Some((chromium, server)) = set_up() else {
        return;
    };
    let tab = open_walk(&chromium, &server, Some(XR_STUB));
    let scan = js(&tab, "live.scan");
    let (x0, y0) = (f(&scan["camera"][0]), f(&scan["camera"][1]));
    js(&tab, &format!("walk.standAt({x0}, {y0}, 0)"));
    settled(&tab);
    tab.find_element("#toggle-panel").unwrap().click().unwrap();
    tab.wait_for_element("#enter-vr:not([disabled])")
        .unwrap()
        .click()
        .unwrap();
    js(
        &tab,
        "new Promise((r) => { const w = () => window.__xr.frames >= 3 ? r(1) : setTimeout(w, 20); w(); })",
    );
    // Push the left stick forward (xr-standard: axis 3 negative) for two seconds.
    js(&tab, "window.__xr.left[3] = -1");
    std::thread::sleep(Duration::from_millis(2000));
    js(&tab, "window.__xr.left[3] = 0");
    let end = settled(&tab);
    // The stand-in's head looks 25° right of north: the walk goes that way.
    let (dx, dy) = (f(&end["camera"][0]) - x0, f(&end["camera"][1]) - y0);
    assert!(dx.hypot(dy) > 2.0, "moved only ({dx}, {dy})");
    let bearing = dx.atan2(dy).to_degrees();
    assert!((bearing - 25.0).abs() < 1.0, "walked towards {bearing}°");
    assert!(js(&tab, "window.__xr.frames").as_u64().unwrap() > 3);
}
