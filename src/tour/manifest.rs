//! What a tour records in its `tour.json` ([`crate::frames::manifest`] names, writes and
//! reads the file): every frame's pose and file, the render settings, the `omnicloud render`
//! command line that reproduces each frame, and what an encoder needs (frame rate, size,
//! stereo layout, frame files in order).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::poses::Pose;
use crate::frames::{FramesError, StationMark, write_manifest};
pub use crate::output::StereoLayout;

/// Version of the manifest's layout.
pub const MANIFEST_VERSION: u32 = 1;

/// One frame of the tour.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    /// Frame number from 0.
    pub index: usize,
    /// File name inside the tour's folder.
    pub file: String,
    /// The camera.
    #[serde(flatten)]
    pub pose: Pose,
    /// The `omnicloud render` command that writes this frame's file again, byte for byte.
    pub command: String,
}

/// The whole manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TourManifest {
    /// [`MANIFEST_VERSION`].
    pub version: u32,
    /// The scan, as given.
    pub scan: String,
    /// The path file, as given.
    pub path: String,
    /// Frames per second of playback.
    pub fps: f64,
    /// File units per second when frames are spaced by speed (`--speed`, given in metres
    /// per second, converted); `None` with a frame count.
    pub speed: Option<f64>,
    /// Length of the curve, file units.
    pub length: f64,
    /// Metres per file unit: the scale of `speed`, `length`, the positions and the rig's IPD;
    /// `None` when the scan declares no unit of length.
    #[serde(default)]
    pub metres_per_unit: Option<f64>,
    /// Frame file width, pixels.
    pub width: u32,
    /// Frame file height, pixels (both eyes for [`StereoLayout::TopBottom`]).
    pub height: u32,
    /// `mono` or `top-bottom` (left eye on top).
    pub stereo_layout: StereoLayout,
    /// `png`, `jpg` or `exr`.
    pub format: String,
    /// Zero of the renderers' local frame, file coordinates; every frame's command passes it
    /// as `--origin`.
    pub origin: [f64; 3],
    /// Render settings, as `omnicloud render` options (without the per-frame `--camera`,
    /// `--yaw` and `-o`).
    pub render_options: Vec<String>,
    /// Every frame, in order.
    pub frames: Vec<FrameRecord>,
    /// For a tour of a survey's stations: each station's scan, name, position and frame
    /// (absent, so empty, for a tour along a path).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stations: Vec<StationMark>,
}

impl TourManifest {
    /// Writes the manifest to `dir/tour.json`, atomically.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, FramesError> {
        write_manifest(dir, self)
    }
}

/// `args` as one POSIX shell command line: arguments made only of safe characters stay as
/// they are, others are single-quoted.
pub fn shell_line(args: &[String]) -> String {
    args.iter()
        .map(|a| {
            let safe = !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./,:=+@%".contains(c));
            if safe {
                a.clone()
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_lines_quote_what_needs_it() {
        let args: Vec<String> = ["omnicloud", "a b.laz", "--camera", "1.5,-2,3", "it's"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(
            shell_line(&args),
            r"omnicloud 'a b.laz' --camera 1.5,-2,3 'it'\''s'"
        );
    }

    #[test]
    fn the_manifest_round_trips_through_json() {
        let m = TourManifest {
            version: MANIFEST_VERSION,
            scan: "s.laz".into(),
            path: "p.csv".into(),
            fps: 30.0,
            speed: Some(1.4),
            length: 10.0,
            metres_per_unit: Some(0.3048),
            width: 256,
            height: 256,
            stereo_layout: StereoLayout::TopBottom,
            format: "png".into(),
            origin: [1.0, 2.0, 3.0],
            render_options: vec!["--width".into(), "256".into()],
            frames: vec![FrameRecord {
                index: 0,
                file: "frame_000000.png".into(),
                pose: Pose {
                    position: [1.0, 2.0, 3.5],
                    yaw: 90.0,
                    pitch: 0.0,
                    roll: 0.0,
                    arc_length: 0.0,
                },
                command: "omnicloud render".into(),
            }],
            stations: Vec::new(),
        };
        let json = serde_json::to_string(&m).unwrap();
        assert!(json.contains("\"stereo_layout\":\"top-bottom\""), "{json}");
        assert!(json.contains("\"yaw\":90.0"), "{json}");
        assert_eq!(serde_json::from_str::<TourManifest>(&json).unwrap(), m);
        assert!(!json.contains("stations"), "{json}");
        let stations = TourManifest {
            stations: vec![StationMark {
                frame: 0,
                scan: 1,
                name: Some("South".into()),
                position: [1.0, 2.0, 3.5],
            }],
            ..m
        };
        let json = serde_json::to_string(&stations).unwrap();
        assert_eq!(
            serde_json::from_str::<TourManifest>(&json).unwrap(),
            stations
        );
    }
}
