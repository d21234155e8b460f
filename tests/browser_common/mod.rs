//! Headless Chromium for the browser tests of `view` and `serve` (Debian's `chromium`,
//! driven over the DevTools protocol by `headless_chrome`), and a stub WebXR runtime.
//!
//! Chromium runs with `--headless --no-sandbox --disable-gpu --no-first-run
//! --disable-background-networking --disable-component-update --disable-sync` and a fresh
//! `--user-data-dir`; WebGL2 comes from SwiftShader (`--use-angle=swiftshader
//! --enable-unsafe-swiftshader`). Without Chromium a test skips with a notice, and fails when
//! `OMNICLOUD_REQUIRE_BROWSER=1` (CI).
#![allow(dead_code)]

use std::ffi::OsStr;
use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use headless_chrome::protocol::cdp::Input;
use headless_chrome::protocol::cdp::Page;
use headless_chrome::{Browser, LaunchOptions, Tab};
use image::RgbaImage;

/// The browser window's size; the page gets what the window leaves of it (measured).
pub const WINDOW: (u32, u32) = (800, 600);

pub fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("OMNICLOUD_CHROMIUM")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/bin/chromium"));
    if path.exists() {
        return Some(path);
    }
    if std::env::var_os("OMNICLOUD_REQUIRE_BROWSER").is_some_and(|v| v == "1") {
        panic!(
            "OMNICLOUD_REQUIRE_BROWSER=1 but {} does not exist (apt-get install chromium)",
            path.display()
        );
    }
    let _ = writeln!(
        std::io::stderr().lock(),
        "SKIPPED: browser test needs Chromium at {} (apt-get install chromium, or set \
         OMNICLOUD_CHROMIUM); set OMNICLOUD_REQUIRE_BROWSER=1 to make this a failure",
        path.display()
    );
    None
}

/// A headless Chromium with its own empty profile (removed with it).
pub struct Chromium {
    pub browser: Browser,
    _profile: tempfile::TempDir,
}

pub fn launch(path: PathBuf) -> Chromium {
    let profile = tempfile::tempdir().unwrap();
    // Chromium's own WebXR is switched off so the stub runtime is the only one that answers.
    let features = "--disable-features=TranslateUI,BlinkGenPropertyTrees,WebXR";
    let options = LaunchOptions {
        path: Some(path),
        headless: true,
        sandbox: false,
        enable_gpu: false,
        window_size: Some(WINDOW),
        user_data_dir: Some(profile.path().to_path_buf()),
        idle_browser_timeout: Duration::from_secs(120),
        ignore_default_args: vec![OsStr::new(
            "--disable-features=TranslateUI,BlinkGenPropertyTrees",
        )],
        args: vec![
            OsStr::new("--disable-component-update"),
            OsStr::new("--disable-quic"),
            OsStr::new("--hide-scrollbars"),
            OsStr::new("--use-angle=swiftshader"),
            OsStr::new("--enable-unsafe-swiftshader"),
            OsStr::new(features),
        ],
        ..LaunchOptions::default()
    };
    let browser = Browser::new(options).expect("starting Chromium");
    Chromium {
        browser,
        _profile: profile,
    }
}

/// Evaluates `expr` (a value or a promise) in the page and returns it as JSON.
pub fn js(tab: &Tab, expr: &str) -> serde_json::Value {
    let wrapped =
        format!("Promise.resolve({expr}).then((v) => JSON.stringify(v === undefined ? null : v))");
    let result = tab.evaluate(&wrapped, true).expect("evaluate");
    match result.value {
        Some(serde_json::Value::String(s)) => serde_json::from_str(&s).unwrap(),
        _ => panic!("{expr} failed in the page: {:?}", result.description),
    }
}

/// Opens the viewer, optionally after installing `init` before any page script, and waits
/// until its first frame is drawn.
pub fn open_viewer(chromium: &Chromium, url: &str, init: Option<&str>) -> std::sync::Arc<Tab> {
    let tab = chromium.browser.new_tab().unwrap();
    tab.set_default_timeout(Duration::from_secs(60));
    if let Some(source) = init {
        tab.call_method(Page::AddScriptToEvaluateOnNewDocument {
            source: source.to_owned(),
            world_name: None,
            include_command_line_api: None,
            run_immediately: None,
        })
        .unwrap();
    }
    tab.navigate_to(url)
        .unwrap()
        .wait_until_navigated()
        .unwrap();
    let ready = tab
        .evaluate("viewer.ready.then(() => 'ok', (e) => 'error: ' + e)", true)
        .unwrap();
    assert_eq!(
        ready.value,
        Some(serde_json::json!("ok")),
        "the viewer did not start: {:?}",
        js(&tab, "viewer.error")
    );
    tab
}

pub fn screenshot(tab: &Tab) -> RgbaImage {
    let png = tab
        .capture_screenshot(Page::CaptureScreenshotFormatOption::Png, None, None, true)
        .unwrap();
    image::load_from_memory(&png).unwrap().to_rgba8()
}

/// The page's size in pixels; checks that a CSS pixel is a screenshot pixel.
pub fn page_size(tab: &Tab) -> (u32, u32) {
    let size = js(tab, "[innerWidth, innerHeight, devicePixelRatio]");
    assert_eq!(size[2], 1, "device pixel ratio");
    let (w, h) = (size[0].as_u64().unwrap(), size[1].as_u64().unwrap());
    assert!(w >= 400 && h >= 300, "page of {w}x{h}");
    (w as u32, h as u32)
}

/// A mouse event at (x, y); `held`: the left button is down during (or, for a press, after)
/// the event.
pub fn mouse(tab: &Tab, kind: Input::DispatchMouseEventTypeOption, x: f64, y: f64, held: bool) {
    use Input::DispatchMouseEventTypeOption as M;
    let button = match kind {
        M::MousePressed | M::MouseReleased => Input::MouseButton::Left,
        _ => Input::MouseButton::None,
    };
    tab.call_method(Input::DispatchMouseEvent {
        Type: kind,
        x,
        y,
        modifiers: None,
        timestamp: None,
        button: Some(button),
        buttons: Some(u32::from(held)),
        click_count: Some(1),
        force: None,
        tangential_pressure: None,
        tilt_x: None,
        tilt_y: None,
        twist: None,
        delta_x: None,
        delta_y: None,
        pointer_Type: None,
    })
    .unwrap();
}

/// A WebXR runtime stand-in: one `immersive-vr` session whose two views (left half, right half
/// of the canvas, 90° vertical field of view) look `HEAD_YAW` degrees right of the start, with
/// a left and a right controller whose thumbstick axes (xr-standard: 2 and 3) a test sets in
/// `window.__xr.left` and `window.__xr.right`; it records what the page asks of it in
/// `window.__xr`.
pub const XR_STUB: &str = r#"
(() => {
  const HEAD_YAW = 25;
  const log = { supported: [], requested: [], spaces: [], viewports: [], frames: 0, layers: 0,
    left: [0, 0, 0, 0], right: [0, 0, 0, 0] };
  window.__xr = log;
  const half = -HEAD_YAW * Math.PI / 360;
  const orientation = { x: 0, y: Math.sin(half), z: 0, w: Math.cos(half) };
  function perspective(fovY, aspect, near, far) {
    const f = 1 / Math.tan(fovY / 2);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0,
      0, 0, (far + near) / (near - far), -1, 0, 0, 2 * far * near / (near - far), 0]);
  }
  class XRWebGLLayer {
    constructor(session, gl) {
      log.layers += 1;
      this.framebuffer = null;
      this.framebufferWidth = gl.drawingBufferWidth;
      this.framebufferHeight = gl.drawingBufferHeight;
    }
    getViewport(view) {
      const w = this.framebufferWidth / 2;
      const vp = { x: view.eye === 'left' ? 0 : w, y: 0, width: w, height: this.framebufferHeight };
      log.viewports.push({ eye: view.eye, x: vp.x, y: vp.y, width: vp.width, height: vp.height });
      return vp;
    }
  }
  window.XRWebGLLayer = XRWebGLLayer;
  class Session extends EventTarget {
    constructor() {
      super(); this.renderState = {}; this.ended = false;
      this.inputSources = [{ handedness: 'left', gamepad: { axes: log.left } },
        { handedness: 'right', gamepad: { axes: log.right } }];
    }
    updateRenderState(state) { Object.assign(this.renderState, state); }
    async requestReferenceSpace(type) { log.spaces.push(type); return { type }; }
    requestAnimationFrame(callback) {
      return requestAnimationFrame((time) => {
        if (this.ended) return;
        log.frames += 1;
        const layer = this.renderState.baseLayer;
        const aspect = layer.framebufferWidth / 2 / layer.framebufferHeight;
        const view = (eye) => ({ eye, projectionMatrix: perspective(Math.PI / 2, aspect, 0.1, 1000),
          transform: { orientation } });
        const frame = { session: this, getViewerPose: () => ({ views: [view('left'), view('right')] }) };
        callback(time, frame);
      });
    }
    async end() { this.ended = true; this.dispatchEvent(new Event('end')); }
  }
  const xr = {
    async isSessionSupported(mode) { log.supported.push(mode); return mode === 'immersive-vr'; },
    async requestSession(mode) { log.requested.push(mode); return new Session(); },
  };
  Object.defineProperty(Navigator.prototype, 'xr', { get: () => xr, configurable: true });
  WebGL2RenderingContext.prototype.makeXRCompatible = async function () {};
})();
"#;
