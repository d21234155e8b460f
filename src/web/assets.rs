//! The viewer page, embedded in the binary: plain HTML and JavaScript, no build step.

/// The page: canvas, controls, and the script tag.
pub const INDEX_HTML: &str = include_str!("assets/index.html");

/// WebGL2 rendering, mouse and keyboard controls, frame playback and WebXR.
pub const VIEWER_JS: &str = include_str!("assets/viewer.js");

/// `serve`'s page: the viewer's canvas and controls, the map and the live sliders.
#[cfg(feature = "gpu")]
pub const SERVE_HTML: &str = include_str!("assets/serve.html");

/// `serve`'s page logic: map clicks and sliders to render requests, renders to the viewer.
#[cfg(feature = "gpu")]
pub const SERVE_JS: &str = include_str!("assets/serve.js");

/// `serve`'s live walking: poses to `/api/live`, streamed pairs to the viewer.
#[cfg(feature = "gpu")]
pub const LIVE_JS: &str = include_str!("assets/live.js");
