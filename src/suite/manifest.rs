//! `suite.json`: what each suite scene is, where its file is, and how to view it.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::projection::{Camera, Equirect, OdsOffset, PoleMerge, PoleMerging, Stereo};
use crate::render::{ColorMode, RenderSettings};

use super::SuiteError;
use super::ply::ply_bytes;
use super::scenes::{SuiteScene, SuiteStereo, all_scenes};

/// File name of the manifest inside a suite folder.
pub const MANIFEST_FILE: &str = "suite.json";

/// The manifest: one entry per view of a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Manifest format version (1).
    pub version: u32,
    /// The views, in the order the suite renders them.
    pub scenes: Vec<ManifestEntry>,
}

/// One view of one scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestEntry {
    /// Unique name.
    pub name: String,
    /// Scene file, relative to the manifest's folder.
    pub file: String,
    /// What the view exercises.
    pub description: String,
    /// Number of points in the file.
    pub points: usize,
    /// Camera centre `[X, Y, Z]` in file coordinates.
    pub camera: [f64; 3],
    /// Camera heading, degrees.
    pub yaw_deg: f64,
    /// `mono` or `ods`.
    pub stereo: SuiteStereo,
    /// Interocular distance, metres (ignored for mono).
    pub ipd: f64,
    /// North pole merge in the CLI's syntax (`off`, `comfortable`, `cycles:60,75`, ...).
    pub pole_merge_north: String,
    /// South pole merge in the CLI's syntax.
    pub pole_merge_south: String,
    /// Image width per eye.
    pub width: u32,
    /// What fails here: `pole`, `seam`, `near`, `enclosing`, `culled`, `utm`, `dense`, `huge`.
    pub tags: Vec<String>,
}

impl ManifestEntry {
    /// Camera centre in file coordinates.
    pub fn camera_world(&self) -> DVec3 {
        DVec3::from_array(self.camera)
    }

    /// Mono or ODS settings for this view, parsed like the CLI parses them.
    pub fn stereo(&self) -> Result<Stereo, SuiteError> {
        let bad = |reason: String| SuiteError::BadEntry {
            name: self.name.clone(),
            reason,
        };
        Ok(match self.stereo {
            SuiteStereo::Mono => Stereo::Mono,
            SuiteStereo::Ods => Stereo::Ods {
                ipd: Stereo::check_ipd(self.ipd).map_err(bad)?,
                merging: PoleMerging {
                    north: PoleMerge::from_str(&self.pole_merge_north).map_err(bad)?,
                    south: PoleMerge::from_str(&self.pole_merge_south).map_err(bad)?,
                },
                offset: OdsOffset::Exact,
            },
        })
    }

    /// The accuracy setup for this view (unlit file colours, DESIGN §5) for a scene whose
    /// local frame starts at `scene_origin` (file coordinates).
    pub fn settings(&self, scene_origin: DVec3) -> Result<RenderSettings, SuiteError> {
        Equirect::check_width(self.width).map_err(|reason| SuiteError::BadEntry {
            name: self.name.clone(),
            reason,
        })?;
        let camera = Camera::new(self.camera_world() - scene_origin, self.yaw_deg);
        let mut s = RenderSettings::new(self.width, camera);
        s.stereo = self.stereo()?;
        s.color = ColorMode::Rgb;
        Ok(s)
    }
}

/// The manifest entries of the generated scenes.
pub fn manifest_of(scenes: &[SuiteScene]) -> Manifest {
    let scenes = scenes
        .iter()
        .flat_map(|s| {
            s.views.iter().map(move |v| ManifestEntry {
                name: v.name.clone(),
                file: format!("{}.ply", s.name),
                description: v.description.clone(),
                points: s.points.len(),
                camera: s.camera.to_array(),
                yaw_deg: s.yaw_deg,
                stereo: v.stereo,
                ipd: v.ipd,
                pole_merge_north: v.pole_merge_north.clone(),
                pole_merge_south: v.pole_merge_south.clone(),
                width: v.width,
                tags: v.tags.clone(),
            })
        })
        .collect();
    Manifest { version: 1, scenes }
}

/// Every file of the suite folder as (file name, bytes): one PLY per scene and the manifest.
pub fn suite_files() -> Result<Vec<(String, Vec<u8>)>, SuiteError> {
    let scenes = all_scenes();
    let mut files = Vec::new();
    for s in &scenes {
        let name = format!("{}.ply", s.name);
        let comment = format!(
            "omnicloud stability suite scene '{}' (tools/gen_scenes.rs)",
            s.name
        );
        let bytes = ply_bytes(&s.points, &comment).map_err(|source| SuiteError::Write {
            path: PathBuf::from(&name),
            source,
        })?;
        files.push((name, bytes));
    }
    let mut json =
        serde_json::to_vec_pretty(&manifest_of(&scenes)).map_err(|source| SuiteError::Json {
            path: PathBuf::from(MANIFEST_FILE),
            source,
        })?;
    json.push(b'\n');
    files.push((MANIFEST_FILE.to_string(), json));
    Ok(files)
}

/// Writes the suite's scene files and manifest into `dir` (created if missing); returns the
/// paths written.
pub fn write_suite(dir: &Path) -> Result<Vec<PathBuf>, SuiteError> {
    std::fs::create_dir_all(dir).map_err(|source| SuiteError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut written = Vec::new();
    for (name, bytes) in suite_files()? {
        let path = dir.join(name);
        std::fs::write(&path, bytes).map_err(|source| SuiteError::Write {
            path: path.clone(),
            source,
        })?;
        written.push(path);
    }
    Ok(written)
}

/// Reads `dir/suite.json`.
pub fn load_manifest(dir: &Path) -> Result<Manifest, SuiteError> {
    let path = dir.join(MANIFEST_FILE);
    let text = std::fs::read_to_string(&path).map_err(|source| SuiteError::Read {
        path: path.clone(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| SuiteError::Json { path, source })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_round_trips_and_every_entry_parses() {
        let m = manifest_of(&all_scenes());
        let text = serde_json::to_string(&m).unwrap();
        let back: Manifest = serde_json::from_str(&text).unwrap();
        assert_eq!(back, m);
        for e in &m.scenes {
            let s = e.settings(e.camera_world()).unwrap();
            assert_eq!(s.camera.center, DVec3::ZERO);
            assert_eq!(s.image.height * 2, s.image.width);
        }
    }

    #[test]
    fn a_bad_pole_merge_names_the_entry() {
        let mut e = manifest_of(&all_scenes()).scenes.remove(1);
        e.pole_merge_north = "sideways".into();
        let err = e.stereo().unwrap_err().to_string();
        assert!(err.contains(&e.name), "{err}");
    }
}
