//! A tour's folder of frames, checked for a video: numbered 0 to n-1 without gaps (as many
//! as `tour.json` lists, when it says), all of one size, full equirect panoramas, in a
//! stereo layout read from `tour.json` or the frame shape, or given.

use std::path::{Path, PathBuf};

use super::{
    FramesError, MANIFEST_NAME, TourInfo, numbered_frames, one_size, read_manifest, sequence,
};
use crate::output::{StereoLayout, read_description};

/// The frame extensions read, lower case.
const EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];
/// The image kinds read, as an error names them.
const KINDS: &str = "PNG, JPEG or EXR";

/// The stereo layout asked for: read from `tour.json` or the frame shape, or given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StereoChoice {
    /// `tour.json`'s `stereo`, else 1:1 frames are top-bottom and 2:1 frames mono.
    #[default]
    Auto,
    /// The frames are mono panoramas.
    Mono,
    /// The frames are ODS pairs, left eye on top.
    TopBottom,
}

/// Where the stereo layout came from, for the summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StereoSource {
    /// Given by the caller.
    Given,
    /// `tour.json`.
    Tour,
    /// The frames' aspect ratio.
    Aspect,
}

/// The frames of a folder, checked: numbered 0 to n-1 without gaps, all of one even size.
#[derive(Debug, Clone)]
pub struct FrameFolder {
    /// The folder.
    pub dir: PathBuf,
    /// The frame files in order.
    pub frames: Vec<PathBuf>,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// How the frames hold the eyes.
    pub stereo: StereoLayout,
    /// Where `stereo` came from.
    pub stereo_source: StereoSource,
    /// The folder's `tour.json`, if it has one.
    pub tour: Option<TourInfo>,
}

impl FrameFolder {
    /// Lists and checks the frames of `dir` (reading only image headers).
    pub fn open(dir: &Path, stereo: StereoChoice) -> Result<Self, FramesError> {
        let tour = read_manifest(dir)?;
        let frames = sequence(dir, numbered_frames(dir, &EXTENSIONS)?, KINDS)?;
        if let Some(listed) = tour.as_ref().and_then(|t| t.frames) {
            let path = dir.join(MANIFEST_NAME);
            if listed > frames.len() {
                return Err(FramesError::IncompleteTour {
                    path,
                    listed,
                    found: frames.len(),
                });
            }
            if listed < frames.len() {
                return Err(FramesError::BadTour {
                    path,
                    reason: format!(
                        "lists {listed} frames but the folder holds {}: remove the frames \
                         from {} on (left from another tour?)",
                        frames.len(),
                        frames[listed].display()
                    ),
                });
            }
        }
        let (width, height) = one_size(&frames)?;
        let shape_error = |reason: &str| FramesError::Shape {
            path: frames[0].clone(),
            width,
            height,
            reason: reason.to_owned(),
        };
        // A render of another projection would be wrapped round the sphere.
        if let Some(d) = read_description(&frames[0])?.filter(|d| !d.is_panorama()) {
            return Err(shape_error(&format!(
                "it is a {} render; a 360° video holds full equirect panoramas \
                 (--projection equirect)",
                d.projection
            )));
        }
        let from_tour = tour.as_ref().and_then(|t| t.stereo);
        let (stereo, stereo_source) = match (stereo, from_tour) {
            (StereoChoice::Mono, _) => (StereoLayout::Mono, StereoSource::Given),
            (StereoChoice::TopBottom, _) => (StereoLayout::TopBottom, StereoSource::Given),
            (StereoChoice::Auto, Some(s)) => (s, StereoSource::Tour),
            (StereoChoice::Auto, None) if width == 2 * height => {
                (StereoLayout::Mono, StereoSource::Aspect)
            }
            (StereoChoice::Auto, None) if width == height => {
                (StereoLayout::TopBottom, StereoSource::Aspect)
            }
            (StereoChoice::Auto, None) => {
                return Err(shape_error(
                    "neither 2:1 (mono) nor 1:1 (ODS top-bottom); give --stereo mono or \
                     --stereo top-bottom",
                ));
            }
        };
        match stereo {
            StereoLayout::Mono if width != 2 * height => {
                return Err(shape_error(
                    "a mono equirectangular panorama is twice as wide as high",
                ));
            }
            StereoLayout::TopBottom if width != height => {
                return Err(shape_error(
                    "a top-bottom ODS pair of equirectangular eyes is as wide as high",
                ));
            }
            _ => {}
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            frames,
            width,
            height,
            stereo,
            stereo_source,
            tour,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(names: &[&str], size: (u32, u32)) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for name in names {
            image::RgbImage::new(size.0, size.1)
                .save(dir.path().join(name))
                .unwrap();
        }
        dir
    }

    #[test]
    fn frames_are_read_in_number_order_and_other_files_skipped() {
        let dir = folder(
            &[
                "frame_000002.png",
                "frame_000000.png",
                "frame_000001.jpg",
                "x.png",
            ],
            (16, 8),
        );
        let f = FrameFolder::open(dir.path(), StereoChoice::Auto).unwrap();
        let names: Vec<_> = f
            .frames
            .iter()
            .map(|p| p.file_name().unwrap().to_str().unwrap().to_owned())
            .collect();
        assert_eq!(
            names,
            ["frame_000000.png", "frame_000001.jpg", "frame_000002.png"]
        );
        assert_eq!((f.width, f.height, f.stereo), (16, 8, StereoLayout::Mono));
        assert_eq!(f.stereo_source, StereoSource::Aspect);
    }

    #[test]
    fn a_gap_names_the_missing_frame() {
        let dir = folder(&["frame_000000.png", "frame_000002.png"], (8, 8));
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("frame 1 is missing (frame_000001.png not found)"),
            "{e}"
        );
        let dir = folder(&["frame_000001.png"], (8, 8));
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("frame 0 is missing"), "{e}");
    }

    #[test]
    fn tour_json_gives_fps_stereo_and_the_frame_count() {
        let dir = folder(&["frame_000000.png", "frame_000001.png"], (16, 8));
        let tour = r#"{"settings": {"fps": 24, "stereo": "mono"}, "frames": [{}, {}, {}]}"#;
        std::fs::write(dir.path().join(MANIFEST_NAME), tour).unwrap();
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("lists 3 frames but the folder holds 2"), "{e}");
        let tour = r#"{"fps": 24, "stereo_layout": "top-bottom", "frames": 2}"#;
        std::fs::write(dir.path().join(MANIFEST_NAME), tour).unwrap();
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("is 16x8: a top-bottom ODS pair"), "{e}");
        std::fs::write(
            dir.path().join(MANIFEST_NAME),
            r#"{"fps": 24, "frames": 2}"#,
        )
        .unwrap();
        let f = FrameFolder::open(dir.path(), StereoChoice::Auto).unwrap();
        assert_eq!(f.tour.unwrap().fps, Some(24.0));
        std::fs::write(dir.path().join(MANIFEST_NAME), r#"{"fps": "fast"}"#).unwrap();
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("tour.json: fps is \"fast\""), "{e}");
    }

    #[test]
    fn odd_shapes_need_a_stereo_choice_that_fits() {
        let dir = folder(&["frame_000000.png"], (12, 8));
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("is 12x8: neither 2:1"), "{e}");
        let dir = folder(&["frame_000000.png"], (8, 8));
        let f = FrameFolder::open(dir.path(), StereoChoice::Auto).unwrap();
        assert_eq!(f.stereo, StereoLayout::TopBottom);
        assert!(FrameFolder::open(dir.path(), StereoChoice::Mono).is_err());
    }
}
