//! A folder of numbered frames (`frame_000000.png`, ... as `omnicloud tour` writes them):
//! which files, in which order, of which size and stereo layout, at which frame rate.
//!
//! A `tour.json` next to the frames (`omnicloud tour` writes one), when present, gives the
//! frame count (a folder with fewer frames is an unfinished tour), the frame rate and the
//! stereo layout; it is read leniently: `fps`, `stereo_layout` or `stereo` (`"top-bottom"`/
//! `"ods"` or `"mono"`) and `frames` (a list or a count), at the top level or under
//! `settings` or `render`.

use std::path::{Path, PathBuf};

use super::VideoError;
pub use crate::output::StereoLayout;
use crate::output::read_description;

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

/// What a tour's `tour.json` says about its video.
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

/// The name of the tour description next to the frames.
pub const TOUR_FILE: &str = "tour.json";

/// The frame extensions read, lower case.
const EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];

impl FrameFolder {
    /// Lists and checks the frames of `dir` (reading only image headers).
    pub fn open(dir: &Path, stereo: StereoChoice) -> Result<Self, VideoError> {
        let tour = read_tour(dir)?;
        let frames = numbered_frames(dir)?;
        if let Some(listed) = tour.as_ref().and_then(|t| t.frames) {
            let path = dir.join(TOUR_FILE);
            if listed > frames.len() {
                return Err(VideoError::IncompleteTour {
                    path,
                    listed,
                    found: frames.len(),
                });
            }
            if listed < frames.len() {
                return Err(VideoError::BadTour {
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
        let (width, height) = dimensions(&frames[0])?;
        for frame in &frames[1..] {
            let (w, h) = dimensions(frame)?;
            if (w, h) != (width, height) {
                return Err(VideoError::FrameSize {
                    path: frame.clone(),
                    width: w,
                    height: h,
                    first: frames[0].clone(),
                    first_width: width,
                    first_height: height,
                });
            }
        }
        let shape_error = |reason: &str| VideoError::Shape {
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

/// The `frame_N.ext` files of `dir` in number order; an error names the first gap.
fn numbered_frames(dir: &Path) -> Result<Vec<PathBuf>, VideoError> {
    let read = |source| VideoError::Io {
        path: dir.to_path_buf(),
        action: "read the folder",
        source,
    };
    let mut numbered: Vec<(usize, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read)? {
        let path = entry.map_err(read)?.path();
        if let Some(n) = frame_number(&path) {
            numbered.push((n, path));
        }
    }
    if numbered.is_empty() {
        return Err(VideoError::NoFrames {
            path: dir.to_path_buf(),
        });
    }
    numbered.sort();
    let last = numbered[numbered.len() - 1].0;
    for (i, (n, path)) in numbered.iter().enumerate() {
        if *n > i {
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy())
                .unwrap_or_default();
            return Err(VideoError::MissingFrame {
                dir: dir.to_path_buf(),
                missing: i,
                expected: format!("frame_{i:06}.{ext}"),
                last,
            });
        }
        if *n < i {
            return Err(VideoError::BadTour {
                path: path.clone(),
                reason: format!(
                    "frame {n} is also {}: keep one file per frame",
                    numbered[i - 1].1.display()
                ),
            });
        }
    }
    Ok(numbered.into_iter().map(|(_, p)| p).collect())
}

/// `N` of a file named `frame_N.png` (`.jpg`, `.jpeg`, `.exr`; any case).
fn frame_number(path: &Path) -> Option<usize> {
    let name = path.file_name()?.to_str()?;
    let (stem, ext) = name.rsplit_once('.')?;
    if !EXTENSIONS.contains(&ext.to_ascii_lowercase().as_str()) {
        return None;
    }
    let digits = stem.strip_prefix("frame_")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

fn dimensions(path: &Path) -> Result<(u32, u32), VideoError> {
    if is_exr(path) {
        let frame = read_rgb(path)?;
        return Ok((frame.width(), frame.height()));
    }
    let bad = |reason: String| VideoError::BadImage {
        path: path.to_path_buf(),
        reason,
    };
    image::ImageReader::open(path)
        .map_err(|e| bad(e.to_string()))?
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?
        .into_dimensions()
        .map_err(|e| bad(e.to_string()))
}

/// A frame as 8-bit sRGB, its coverage (alpha) composited over black as the viewer shows it.
pub fn read_rgb(path: &Path) -> Result<image::RgbImage, VideoError> {
    let rgba = if is_exr(path) {
        let linear = crate::output::read_image(path)?;
        let frame = linear.to_frame();
        let bytes = frame.color.iter().flatten().copied().collect();
        image::RgbaImage::from_raw(frame.width, frame.height, bytes).ok_or_else(|| {
            VideoError::BadImage {
                path: path.to_path_buf(),
                reason: "the pixel count does not match the size".into(),
            }
        })?
    } else {
        image::open(path)
            .map_err(|e| VideoError::BadImage {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })?
            .to_rgba8()
    };
    let (w, h) = rgba.dimensions();
    let over_black = |c: u8, a: u8| ((u32::from(c) * u32::from(a) + 127) / 255) as u8;
    Ok(image::RgbImage::from_fn(w, h, |x, y| {
        let [r, g, b, a] = rgba.get_pixel(x, y).0;
        image::Rgb([over_black(r, a), over_black(g, a), over_black(b, a)])
    }))
}

/// Reads `dir/tour.json` if there is one.
fn read_tour(dir: &Path) -> Result<Option<TourInfo>, VideoError> {
    let path = dir.join(TOUR_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(VideoError::Io {
                path,
                action: "read",
                source,
            });
        }
    };
    parse_tour(&path, &text).map(Some)
}

/// The tour fields a video needs, from `tour.json`'s text.
pub fn parse_tour(path: &Path, text: &str) -> Result<TourInfo, VideoError> {
    let bad = |reason: String| VideoError::BadTour {
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
    Ok(TourInfo {
        path: path.to_path_buf(),
        fps,
        stereo,
        frames,
    })
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
        std::fs::write(dir.path().join(TOUR_FILE), tour).unwrap();
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("lists 3 frames but the folder holds 2"), "{e}");
        let tour = r#"{"fps": 24, "stereo_layout": "top-bottom", "frames": 2}"#;
        std::fs::write(dir.path().join(TOUR_FILE), tour).unwrap();
        let e = FrameFolder::open(dir.path(), StereoChoice::Auto)
            .unwrap_err()
            .to_string();
        assert!(e.contains("is 16x8: a top-bottom ODS pair"), "{e}");
        std::fs::write(dir.path().join(TOUR_FILE), r#"{"fps": 24, "frames": 2}"#).unwrap();
        let f = FrameFolder::open(dir.path(), StereoChoice::Auto).unwrap();
        assert_eq!(f.tour.unwrap().fps, Some(24.0));
        std::fs::write(dir.path().join(TOUR_FILE), r#"{"fps": "fast"}"#).unwrap();
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

    #[test]
    fn coverage_is_composited_over_black() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 255, 128]))
            .save(&path)
            .unwrap();
        assert_eq!(read_rgb(&path).unwrap().get_pixel(0, 0).0, [100, 50, 128]);
    }
}
