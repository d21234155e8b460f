//! A prepared scan made ready to serve: its map, the box a camera may stand in, and the
//! camera height above the ground at any XY.

use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3};
use serde::Serialize;

use crate::frame::Frame;
use crate::io::Up;
use crate::output::png::encode_png;
use crate::prepare::lod::NodeRadii;
use crate::prepare::placement::{EYE_HEIGHT, ground_camera_position};
use crate::projection::{PoleMerge, Stereo};
use crate::render::{ColorMode, Shading};
use crate::scene::Scene;

use super::ServeError;
use super::map::{MapGrid, render_map};
use super::request::CameraLimits;

/// How a scan is served; fixed when the server starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiveOptions {
    /// Panorama width per eye, pixels (the height is half of it).
    pub width: u32,
    /// Camera height above the local ground where the map is clicked, file units.
    pub height: f64,
    /// File units per metre across: the IPD a page sends, in metres, times this is the
    /// rig's in the scan.
    pub per_metre: f64,
    /// Metres per file unit, when the scan declares a unit of length.
    pub metres_per_unit: Option<f64>,
    /// Point colour.
    pub color: ColorMode,
    /// Shading.
    pub shading: Shading,
    /// The map's longer side, pixels.
    pub map_size: u32,
}

impl Default for LiveOptions {
    fn default() -> Self {
        LiveOptions {
            width: 2048,
            height: EYE_HEIGHT,
            per_metre: 1.0,
            metres_per_unit: None,
            color: ColorMode::Auto,
            shading: Shading::Unlit,
            map_size: 1024,
        }
    }
}

/// A COPC scan drawn through its level of detail: each render reads the octree nodes its
/// camera needs into a node cache on the GPU kept across requests
/// ([`NodeStream`](crate::renderer::NodeStream)), rather than holding every point there.
#[derive(Debug, Clone, PartialEq)]
pub struct ServedLod {
    /// The COPC file.
    pub path: PathBuf,
    /// Up axis it was read with.
    pub up: Up,
    /// How the nodes' spheres are sized.
    pub radii: NodeRadii,
    /// A node is fine enough when its spacing spans less than this many pixels (0 reads
    /// every node).
    pub pixels: f64,
    /// Points a render reads at least, where the file holds them.
    pub floor: u64,
    /// Bytes of nodes kept on the GPU between renders.
    pub budget: u64,
}

/// A scan in memory, in the local frame preparation gave it, with its map.
pub struct LiveScan {
    /// The scene; its origin is the camera preparation placed (DESIGN §1).
    pub scene: Scene,
    /// The options it is served with.
    pub options: LiveOptions,
    /// Where a camera may stand, and the default camera.
    pub limits: CameraLimits,
    /// Pixel ↔ file XY of the map.
    pub grid: MapGrid,
    /// The map as PNG.
    pub map_png: Vec<u8>,
    /// What `/api/scan` answers.
    pub info: ScanInfo,
    /// Renders through the level of detail (rasterizer only); `None`: every point resident.
    pub lod: Option<ServedLod>,
    /// Width of the scan's XY bounds (the ground search's largest radius), metres.
    extent: f32,
}

/// The JSON of `/api/scan`. Coordinates are file coordinates (metres).
#[derive(Debug, Clone, Serialize)]
pub struct ScanInfo {
    /// The scan's file name.
    pub file: String,
    /// Points in the scan.
    pub points: usize,
    /// Lowest corner of the points' bounds.
    pub min: [f64; 3],
    /// Highest corner of the points' bounds.
    pub max: [f64; 3],
    /// The map's pixel grid: pixel centre `(i + 0.5, j + 0.5)` is file
    /// `(x0 + (i + 0.5) * pixel, y1 - (j + 0.5) * pixel)`.
    pub map: MapGrid,
    /// The camera the page starts at: [`LiveOptions::height`] above the ground at the XY
    /// preparation placed the camera at.
    pub camera: [f64; 3],
    /// Camera height above the ground where the map is clicked, file units.
    pub height: f64,
    /// Metres per file unit (0.3048 for a scan in feet); `null` when the scan declares no
    /// unit of length.
    pub metres_per_unit: Option<f64>,
    /// Panorama width per eye, pixels.
    pub width: u32,
    /// Default interocular distance, metres (as `/api/render`'s `ipd` takes it).
    pub ipd: f64,
    /// Default pole merging, as `/api/render`'s `north` and `south` spell it.
    pub pole_merge: String,
}

impl LiveScan {
    /// Draws the map and measures the bounds of a prepared scan's scene (`path` names it);
    /// the camera preparation placed, the scene's origin, is the default camera.
    ///
    /// # Errors
    /// The scan holds no point, the colour mode needs an attribute it lacks, or the map
    /// cannot be encoded.
    pub fn new(path: &Path, scene: Scene, options: LiveOptions) -> Result<Self, ServeError> {
        let Some((lo, hi)) = scene.bounds() else {
            return Err(ServeError::Empty {
                path: path.to_path_buf(),
            });
        };
        let (lo, hi) = (scene.origin + lo.as_dvec3(), scene.origin + hi.as_dvec3());
        let grid = MapGrid::over(lo.truncate(), hi.truncate(), options.map_size);
        let map = render_map(&scene, &grid, options.color)?;
        let map_png = png_bytes(&map)?;
        let default = scene.origin;
        let limits = CameraLimits {
            lo: lo.truncate(),
            hi: hi.truncate(),
            default: default.truncate(),
        };
        let info = ScanInfo {
            file: path.file_name().map_or_else(
                || path.display().to_string(),
                |n| n.to_string_lossy().into(),
            ),
            points: scene.len(),
            min: lo.to_array(),
            max: hi.to_array(),
            map: grid,
            camera: default.to_array(),
            height: options.height,
            metres_per_unit: options.metres_per_unit,
            width: options.width,
            ipd: Stereo::DEFAULT_IPD,
            pole_merge: PoleMerge::COMFORTABLE.to_string(),
        };
        Ok(LiveScan {
            extent: (hi - lo).truncate().max_element() as f32,
            scene,
            options,
            limits,
            grid,
            map_png,
            info,
            lod: None,
        })
    }

    /// This scan read from the coarse levels of a file of `points` points (its map, ground
    /// and bounds come from them; views are drawn through [`with_lod`](Self::with_lod), and
    /// a ray tracer would trace only the points held).
    #[must_use]
    pub fn surveyed_from(mut self, points: u64) -> Self {
        self.info.points = usize::try_from(points).unwrap_or(usize::MAX);
        self
    }

    /// This scan rendered through its level of detail as `lod` says (by the rasterizer;
    /// the ray tracer keeps every point).
    #[must_use]
    pub fn with_lod(mut self, lod: ServedLod) -> Self {
        self.lod = Some(lod);
        self
    }

    /// The camera (file coordinates) [`LiveOptions::height`] above the ground at file `xy`:
    /// the ground as automatic placement estimates it
    /// ([`ground_camera_position`]); `None` when no point lies near enough to stand on. At
    /// the default camera's XY, the camera preparation placed (where `render` stands).
    pub fn camera_at(&self, xy: DVec2) -> Option<DVec3> {
        self.camera_at_height(xy, None)
    }

    /// [`camera_at`](Self::camera_at) `height` (file units) above the ground when given, the
    /// served height when not.
    pub fn camera_at_height(&self, xy: DVec2, height: Option<f64>) -> Option<DVec3> {
        if xy == self.limits.default && height.is_none() {
            return Some(DVec3::from_array(self.info.camera));
        }
        let centre = (xy - self.scene.origin.truncate()).as_vec2();
        let eye = ground_camera_position(&self.scene, centre, self.extent)?;
        let ground = self.scene.origin.z + eye.z - EYE_HEIGHT;
        Some(xy.extend(ground + height.unwrap_or(self.options.height)))
    }
}

/// A frame as PNG bytes.
pub(super) fn png_bytes(frame: &Frame) -> Result<Vec<u8>, ServeError> {
    let mut bytes = Vec::new();
    encode_png(frame, None, None, &mut bytes, Path::new("(served image)"))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A 40 m x 20 m ground sloping up 0.1 m per metre eastwards, camera prepared at its
    /// middle (file (1000, 2000)).
    fn slope() -> Scene {
        let mut pts = Vec::new();
        for i in 0..=200 {
            for j in 0..=100 {
                let (x, y) = (i as f32 * 0.2 - 20.0, j as f32 * 0.2 - 10.0);
                pts.push(Vec3::new(x, y, 0.1 * x - 1.7));
            }
        }
        Scene::new(DVec3::new(1000.0, 2000.0, 50.0), pts, 0.1)
    }

    #[test]
    fn the_camera_stands_its_height_above_the_ground_where_asked() {
        let options = LiveOptions {
            width: 256,
            height: 3.0,
            color: ColorMode::Elevation,
            map_size: 80,
            ..LiveOptions::default()
        };
        let scan = LiveScan::new(Path::new("/data/slope.laz"), slope(), options).unwrap();
        assert_eq!(scan.info.file, "slope.laz");
        assert_eq!(scan.limits.lo, DVec2::new(980.0, 1990.0));
        assert_eq!(scan.limits.hi, DVec2::new(1020.0, 2010.0));
        assert_eq!((scan.grid.width, scan.grid.height), (80, 40));
        // Ground at file x: 50 - 1.7 + 0.1 (x - 1000).
        for x in [990.0, 1000.0, 1012.5] {
            let c = scan.camera_at(DVec2::new(x, 2003.0)).unwrap();
            let ground = 48.3 + 0.1 * (x - 1000.0);
            assert_eq!(c.truncate(), DVec2::new(x, 2003.0));
            assert!((c.z - (ground + 3.0)).abs() < 0.05, "at {x}: {c}");
        }
        let png = image::load_from_memory(&scan.map_png).unwrap();
        assert_eq!((png.width(), png.height()), (80, 40));
        let json = serde_json::to_value(&scan.info).unwrap();
        assert_eq!(json["pole_merge"], "marrinan:45,0,3");
        assert_eq!(json["map"]["width"], 80);
        // The page starts where preparation placed the camera.
        let camera: Vec<f64> = serde_json::from_value(json["camera"].clone()).unwrap();
        assert_eq!(camera, [1000.0, 2000.0, 50.0]);
    }
}
