//! The viewer page, embedded in the binary: plain HTML and JavaScript, no build step.

/// The page: canvas, controls, and the script tag.
pub const INDEX_HTML: &str = include_str!("assets/index.html");

/// WebGL2 rendering, mouse and keyboard controls, frame playback and WebXR.
pub const VIEWER_JS: &str = include_str!("assets/viewer.js");
