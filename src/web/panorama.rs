//! The panoramas a viewer serves: one image, the frames of a tour folder, all of one shape,
//! or an MP4 video (mono or top-bottom as its `st3d` box says).

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::WebError;
use crate::frames::{FramesError, StationMark, numbered_frames, one_size, read_manifest};
use crate::output::{StoredEyes, read_description};

/// Mono equirect (2:1) or an ODS pair, left eye on top (1:1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PanoramaKind {
    /// One 2:1 equirectangular image.
    Mono,
    /// Two 2:1 equirectangular images stacked, left eye on top.
    Ods,
}

impl PanoramaKind {
    /// The kind an image of this size holds, by aspect ratio; `None` for other shapes.
    pub fn from_size(width: u32, height: u32) -> Option<Self> {
        let (w, h) = (u64::from(width), u64::from(height));
        match () {
            _ if h > 0 && w == 2 * h => Some(Self::Mono),
            _ if h > 0 && w == h && h % 2 == 0 => Some(Self::Ods),
            _ => None,
        }
    }
}

/// A PNG or JPEG file, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageType {
    /// `.png`
    Png,
    /// `.jpg` or `.jpeg`
    Jpeg,
    /// `.mp4`, an H.264 video
    Mp4,
}

impl ImageType {
    /// The type a file's extension names (case-insensitive), if any.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(Self::Png),
            "jpg" | "jpeg" => Some(Self::Jpeg),
            "mp4" => Some(Self::Mp4),
            _ => None,
        }
    }

    /// The HTTP media type.
    pub fn mime(self) -> &'static str {
        match self {
            Self::Png => "image/png",
            Self::Jpeg => "image/jpeg",
            Self::Mp4 => "video/mp4",
        }
    }
}

/// One served image file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameFile {
    /// Where it lies.
    pub path: PathBuf,
    /// PNG or JPEG.
    pub image_type: ImageType,
}

/// What `omnicloud view` shows: the frames (one for a single image) and their common shape.
#[derive(Debug, Clone)]
pub struct Panorama {
    /// Mono or ODS.
    pub kind: PanoramaKind,
    /// Width of every frame in pixels.
    pub width: u32,
    /// Height of every frame in pixels.
    pub height: u32,
    /// The frames, in playing order; never empty. A video has one entry: the MP4 file.
    pub frames: Vec<FrameFile>,
    /// For an MP4: its frame count and rate.
    pub video: Option<VideoTrack>,
    /// For a folder of a survey's stations (its `tour.json` lists them): each station and
    /// its frame.
    pub stations: Vec<StationMark>,
}

/// What the page needs to know of an MP4 to step through it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VideoTrack {
    /// Number of frames.
    pub frames: usize,
    /// Frames per second.
    pub fps: f64,
}

/// The JSON of `/api/info`.
#[derive(Debug, Clone, Serialize)]
pub struct PanoramaInfo {
    /// `mono` or `ods`.
    pub kind: PanoramaKind,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Number of frames (1 for a single image).
    pub frames: usize,
    /// For an MP4 (served at `/video`): its frame count and rate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub video: Option<VideoTrack>,
    /// For a folder of a survey's stations: each station's frame, scan, name and position.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stations: Vec<StationMark>,
}

impl Panorama {
    /// Opens a PNG/JPEG panorama, or a folder of frames: its `frame_*` images when it has
    /// any, else all its PNG/JPEG files, sorted by name. Reads only the image headers.
    pub fn open(path: &Path) -> Result<Self, WebError> {
        let read = |source| WebError::Read {
            path: path.to_path_buf(),
            source,
        };
        if std::fs::metadata(path).map_err(read)?.is_dir() {
            let mut panorama = Self::from_frames(path, folder_frames(path)?)?;
            let count = panorama.frames.len();
            panorama.stations = read_manifest(path)?
                .map(|tour| tour.stations)
                .unwrap_or_default()
                .into_iter()
                .filter(|s| s.frame < count)
                .collect();
            Ok(panorama)
        } else {
            let Some(image_type) = ImageType::of(path) else {
                return Err(WebError::NotAnImage {
                    path: path.to_path_buf(),
                    reason: "the name does not end in .png, .jpg, .jpeg or .mp4".into(),
                });
            };
            if image_type == ImageType::Mp4 {
                return Self::from_video(path);
            }
            let frame = FrameFile {
                path: path.to_path_buf(),
                image_type,
            };
            Self::from_frames(path, vec![frame])
        }
    }

    fn from_frames(origin: &Path, frames: Vec<FrameFile>) -> Result<Self, WebError> {
        let Some(first) = frames.first() else {
            return Err(FramesError::NoFrames {
                path: origin.to_path_buf(),
                kinds: "PNG or JPEG",
            }
            .into());
        };
        let paths: Vec<PathBuf> = frames.iter().map(|f| f.path.clone()).collect();
        let (width, height) = one_size(&paths)?;
        let kind = frame_kind(&first.path, width, height)?;
        Ok(Self {
            kind,
            width,
            height,
            frames,
            video: None,
            stations: Vec::new(),
        })
    }

    /// An MP4 video: size, frame count and rate from its index; mono or top-bottom from its
    /// `st3d` box, or, without one, from its shape as for images.
    #[cfg(feature = "video")]
    fn from_video(path: &Path) -> Result<Self, WebError> {
        use crate::output::StereoLayout;
        let not_video = |reason: String| WebError::NotAVideo {
            path: path.to_path_buf(),
            reason,
        };
        let info = crate::video::read_video_info(path).map_err(|e| not_video(e.to_string()))?;
        let (width, height) = (info.width, info.height);
        let kind = match (info.stereo_mode, info.stereo()) {
            (None, _) => PanoramaKind::from_size(width, height).ok_or_else(|| WebError::Shape {
                path: path.to_path_buf(),
                width,
                height,
            })?,
            (Some(_), Some(StereoLayout::Mono)) => PanoramaKind::Mono,
            (Some(_), Some(StereoLayout::TopBottom)) => PanoramaKind::Ods,
            (Some(mode), None) => {
                return Err(not_video(format!(
                    "its st3d box says stereo mode {mode}; the viewer shows mono (0) and \
                     top-bottom (1) videos"
                )));
            }
        };
        if info.frames == 0 || !(info.fps.is_finite() && info.fps > 0.0) {
            return Err(not_video("the video has no frames".into()));
        }
        Ok(Self {
            kind,
            width,
            height,
            frames: vec![FrameFile {
                path: path.to_path_buf(),
                image_type: ImageType::Mp4,
            }],
            video: Some(VideoTrack {
                frames: info.frames,
                fps: info.fps,
            }),
            stations: Vec::new(),
        })
    }

    #[cfg(not(feature = "video"))]
    fn from_video(path: &Path) -> Result<Self, WebError> {
        Err(WebError::NotAVideo {
            path: path.to_path_buf(),
            reason: "this omnicloud was built without the `video` feature".into(),
        })
    }

    /// How many frames the page can show: the video's, else the images'.
    pub fn frame_count(&self) -> usize {
        self.video.map_or(self.frames.len(), |v| v.frames)
    }

    /// What `/api/info` answers.
    pub fn info(&self) -> PanoramaInfo {
        PanoramaInfo {
            kind: self.kind,
            width: self.width,
            height: self.height,
            frames: self.frame_count(),
            video: self.video,
            stations: self.stations.clone(),
        }
    }
}

/// The image files of a folder: its numbered frames (`frame_000000.png`, ...) in number
/// order if it has any, else all its PNG and JPEG files in name order.
fn folder_frames(dir: &Path) -> Result<Vec<FrameFile>, WebError> {
    let numbered = numbered_frames(dir, &["png", "jpg", "jpeg"])?;
    let framed =
        |path: PathBuf| ImageType::of(&path).map(|image_type| FrameFile { path, image_type });
    if !numbered.is_empty() {
        return Ok(numbered
            .into_iter()
            .filter_map(|(_, p)| framed(p))
            .collect());
    }
    let read = |source| WebError::Read {
        path: dir.to_path_buf(),
        source,
    };
    let mut images = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read)? {
        let entry = entry.map_err(read)?;
        let path = entry.path();
        if let Some(image_type) = ImageType::of(&path)
            && image_type != ImageType::Mp4
            && entry.file_type().map_err(read)?.is_file()
        {
            images.push(FrameFile { path, image_type });
        }
    }
    images.sort_by(|a, b| a.path.file_name().cmp(&b.path.file_name()));
    Ok(images)
}

/// The kind of the `width x height` image at `path`: as its description says (a render of
/// another projection is refused), else by its shape.
fn frame_kind(path: &Path, width: u32, height: u32) -> Result<PanoramaKind, WebError> {
    let by_shape = PanoramaKind::from_size(width, height);
    let shape = || WebError::Shape {
        path: path.to_path_buf(),
        width,
        height,
    };
    let Some(d) = read_description(path)? else {
        return by_shape.ok_or_else(shape);
    };
    if !d.is_panorama() {
        return Err(WebError::NotPanorama {
            path: path.to_path_buf(),
            projection: d.projection.to_string(),
        });
    }
    let kind = match d.eyes {
        StoredEyes::TopBottom => PanoramaKind::Ods,
        StoredEyes::Mono | StoredEyes::Left | StoredEyes::Right => PanoramaKind::Mono,
    };
    (by_shape == Some(kind)).then_some(kind).ok_or_else(shape)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_aspect_ratio_tells_mono_from_ods() {
        assert_eq!(
            PanoramaKind::from_size(4096, 2048),
            Some(PanoramaKind::Mono)
        );
        assert_eq!(PanoramaKind::from_size(2048, 2048), Some(PanoramaKind::Ods));
        assert_eq!(PanoramaKind::from_size(2047, 2047), None);
        assert_eq!(PanoramaKind::from_size(4096, 2000), None);
        assert_eq!(PanoramaKind::from_size(0, 0), None);
    }

    #[test]
    fn a_folder_serves_its_frames_in_name_order_and_skips_other_files() {
        let dir = tempfile::tempdir().unwrap();
        let img = image::RgbImage::new(8, 4);
        for name in [
            "frame_000002.png",
            "frame_000000.png",
            "frame_000001.png",
            "z.png",
        ] {
            img.save(dir.path().join(name)).unwrap();
        }
        std::fs::write(dir.path().join("notes.txt"), "x").unwrap();
        let p = Panorama::open(dir.path()).unwrap();
        let names: Vec<_> = p
            .frames
            .iter()
            .map(|f| f.path.file_name().unwrap().to_str().unwrap().to_owned())
            .collect();
        assert_eq!(
            names,
            ["frame_000000.png", "frame_000001.png", "frame_000002.png"]
        );
        assert_eq!((p.kind, p.width, p.height), (PanoramaKind::Mono, 8, 4));
    }

    #[test]
    fn a_station_folder_lists_its_stations_in_the_info() {
        let dir = tempfile::tempdir().unwrap();
        for k in 0..2 {
            image::RgbImage::new(8, 4)
                .save(dir.path().join(format!("frame_{k:06}.png")))
                .unwrap();
        }
        let plain = Panorama::open(dir.path()).unwrap();
        assert!(plain.stations.is_empty());
        let json = serde_json::to_string(&plain.info()).unwrap();
        assert!(!json.contains("stations"), "{json}");
        std::fs::write(
            dir.path().join("tour.json"),
            r#"{"frames": [{}, {}], "stations": [
                {"frame": 0, "scan": 0, "name": "North", "position": [10, 20, 1.5]},
                {"frame": 1, "scan": 1, "name": "South", "position": [-5, 3, 0.5]},
                {"frame": 2, "scan": 2, "name": "Gone", "position": [0, 0, 0]}]}"#,
        )
        .unwrap();
        let p = Panorama::open(dir.path()).unwrap();
        let names: Vec<_> = p.stations.iter().map(|s| s.name.as_deref()).collect();
        assert_eq!(names, [Some("North"), Some("South")]);
        let json = serde_json::to_string(&p.info()).unwrap();
        assert!(
            json.contains(
                r#""stations":[{"frame":0,"scan":0,"name":"North","position":[10.0,20.0,1.5]}"#
            ),
            "{json}"
        );
    }

    #[test]
    fn a_jpeg_panorama_is_served_as_jpeg() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("pano.JPG");
        image::RgbImage::new(16, 8).save(&file).unwrap();
        let p = Panorama::open(&file).unwrap();
        assert_eq!((p.kind, p.width, p.height), (PanoramaKind::Mono, 16, 8));
        assert_eq!(p.frames[0].image_type.mime(), "image/jpeg");
    }

    #[test]
    fn frames_of_different_sizes_are_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        image::RgbImage::new(8, 4)
            .save(dir.path().join("frame_0.png"))
            .unwrap();
        image::RgbImage::new(16, 8)
            .save(dir.path().join("frame_1.png"))
            .unwrap();
        let e = Panorama::open(dir.path()).unwrap_err().to_string();
        assert!(e.contains("frame_1.png is 16x8"), "{e}");
    }

    #[test]
    fn odd_shapes_and_non_images_are_refused_with_the_file_named() {
        let dir = tempfile::tempdir().unwrap();
        let wide = dir.path().join("wide.png");
        image::RgbImage::new(9, 4).save(&wide).unwrap();
        let e = Panorama::open(&wide).unwrap_err().to_string();
        assert!(e.contains("wide.png is 9x4"), "{e}");
        let fake = dir.path().join("fake.png");
        std::fs::write(&fake, "not a png").unwrap();
        let e = Panorama::open(&fake).unwrap_err().to_string();
        assert!(e.contains("fake.png is not a readable PNG or JPEG"), "{e}");
        let empty = dir.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        let e = Panorama::open(&empty).unwrap_err().to_string();
        assert!(e.contains("holds no PNG or JPEG frames"), "{e}");
    }
}
