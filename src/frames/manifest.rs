//! `tour.json`, the manifest next to a tour's frames: its name, writing it, and reading what
//! a video or viewer needs from it.
//!
//! It is read leniently: `fps`, `stereo_layout` or `stereo` (`"top-bottom"`/`"ods"` or
//! `"mono"`) and `frames` (a list or a count), at the top level or under `settings` or
//! `render`, and the `stations` a survey's station run records. What it holds beyond that is
//! the tour's ([`crate::tour::TourManifest`]).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::FramesError;
use crate::output::{OutputError, StereoLayout, write_atomically};

/// The manifest's file name inside a tour's folder.
pub const MANIFEST_NAME: &str = "tour.json";

/// What a tour's `tour.json` says about its frames.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TourInfo {
    /// The `tour.json` file.
    pub path: PathBuf,
    /// Frames per second the tour was planned at.
    pub fps: Option<f64>,
    /// The stereo layout it was rendered in.
    pub stereo: Option<StereoLayout>,
    /// How many frames it has.
    pub frames: Option<usize>,
    /// The survey stations its frames stand at (empty for a tour along a path).
    pub stations: Vec<StationMark>,
}

/// One station of a survey and the frame rendered there, as `tour.json` lists them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StationMark {
    /// The frame shot at the station, from 0.
    pub frame: usize,
    /// The scan's index in its file, from 0.
    pub scan: usize,
    /// The scan's name, when it has one.
    #[serde(default)]
    pub name: Option<String>,
    /// The scanner's position, file coordinates.
    pub position: [f64; 3],
}

/// Writes `manifest` as pretty JSON to `dir/tour.json`, atomically; returns the path.
pub fn write_manifest(dir: &Path, manifest: &impl Serialize) -> Result<PathBuf, FramesError> {
    let path = dir.join(MANIFEST_NAME);
    let json = serde_json::to_vec_pretty(manifest).expect("a manifest serialises");
    write_atomically(&path, |w| {
        use std::io::Write;
        w.write_all(&json)
            .and_then(|_| w.write_all(b"\n"))
            .map_err(|source| OutputError::Io {
                path: path.clone(),
                action: "writing",
                source,
            })
    })?;
    Ok(path)
}

/// Reads `dir/tour.json` if there is one.
pub fn read_manifest(dir: &Path) -> Result<Option<TourInfo>, FramesError> {
    let path = dir.join(MANIFEST_NAME);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(FramesError::Io {
                path,
                action: "read",
                source,
            });
        }
    };
    parse_manifest(&path, &text).map(Some)
}

/// The fields a video or viewer needs, from the text of the manifest at `path`.
pub fn parse_manifest(path: &Path, text: &str) -> Result<TourInfo, FramesError> {
    let bad = |reason: String| FramesError::BadTour {
        path: path.to_path_buf(),
        reason,
    };
    let json: serde_json::Value =
        serde_json::from_str(text).map_err(|e| bad(format!("not valid JSON: {e}")))?;
    // A field at the top level, else in the render settings.
    let field = |name: &str| {
        json.get(name)
            .or_else(|| json.get("settings").and_then(|s| s.get(name)))
            .or_else(|| json.get("render").and_then(|s| s.get(name)))
    };
    let fps = match field("fps") {
        None => None,
        Some(v) => match v.as_f64() {
            Some(f) if f.is_finite() && f > 0.0 => Some(f),
            _ => return Err(bad(format!("fps is {v}: expected a positive number"))),
        },
    };
    let stereo = match field("stereo_layout").or_else(|| field("stereo")) {
        None | Some(serde_json::Value::Null) => None,
        Some(v) => match v.as_str().map(str::to_ascii_lowercase).as_deref() {
            Some("ods" | "top-bottom" | "topbottom" | "stereo") => Some(StereoLayout::TopBottom),
            Some("mono" | "none" | "off") => Some(StereoLayout::Mono),
            _ => {
                return Err(bad(format!(
                    "the stereo layout is {v}: expected \"ods\", \"top-bottom\" or \"mono\""
                )));
            }
        },
    };
    let frames = match json.get("frames") {
        None => None,
        Some(serde_json::Value::Array(list)) => Some(list.len()),
        Some(v) => match v.as_u64() {
            Some(n) => Some(n as usize),
            None => return Err(bad(format!("frames is {v}: expected a list or a count"))),
        },
    };
    let stations = match json.get("stations") {
        None | Some(serde_json::Value::Null) => Vec::new(),
        Some(v) => serde_json::from_value(v.clone()).map_err(|e| {
            bad(format!(
                "stations: {e}: expected a list of {{frame, scan, name, position}}"
            ))
        })?,
    };
    Ok(TourInfo {
        path: path.to_path_buf(),
        fps,
        stereo,
        frames,
        stations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_manifest_reads_back_its_rate_layout_and_frame_count() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_manifest(dir.path()).unwrap(), None);
        let manifest = serde_json::json!({
            "fps": 24.0, "stereo_layout": "top-bottom", "frames": [{}, {}, {}]
        });
        let path = write_manifest(dir.path(), &manifest).unwrap();
        assert_eq!(path, dir.path().join("tour.json"));
        let info = read_manifest(dir.path()).unwrap().unwrap();
        assert_eq!(
            (info.fps, info.stereo, info.frames),
            (Some(24.0), Some(StereoLayout::TopBottom), Some(3))
        );
        let e = parse_manifest(&path, r#"{"render": {"stereo": "sideways"}}"#)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tour.json: the stereo layout is \"sideways\""),
            "{e}"
        );
        assert!(info.stations.is_empty());
    }

    #[test]
    fn stations_read_back_and_bad_ones_are_named() {
        let path = Path::new("stations/tour.json");
        let info = parse_manifest(
            path,
            r#"{"frames": [{}, {}], "stations": [
                {"frame": 0, "scan": 0, "name": "North", "position": [10, 20, 1.5]},
                {"frame": 1, "scan": 1, "position": [-5, 3, 0.5]}]}"#,
        )
        .unwrap();
        assert_eq!(info.stations.len(), 2);
        assert_eq!(info.stations[0].name.as_deref(), Some("North"));
        assert_eq!(info.stations[1].name, None);
        assert_eq!(info.stations[1].position, [-5.0, 3.0, 0.5]);
        let e = parse_manifest(path, r#"{"stations": [{"frame": "x"}]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("tour.json: stations:"), "{e}");
    }
}
