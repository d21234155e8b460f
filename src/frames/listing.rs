//! The frame files of a folder: listed in number order, checked for gaps, of one size, and
//! read as the viewer shows them.

use std::path::{Path, PathBuf};

use super::{FramesError, frame_file_name, frame_number};

/// The `frame_N.ext` files of `dir` with `ext` one of `extensions` (lower case), as (N, path)
/// in number order; gaps and repeated numbers are left for [`sequence`] to refuse.
pub fn numbered_frames(
    dir: &Path,
    extensions: &[&str],
) -> Result<Vec<(usize, PathBuf)>, FramesError> {
    let read = |source| FramesError::Io {
        path: dir.to_path_buf(),
        action: "read the folder",
        source,
    };
    let mut numbered: Vec<(usize, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read)? {
        let path = entry.map_err(read)?.path();
        if let Some(n) = frame_number(&path, extensions) {
            numbered.push((n, path));
        }
    }
    numbered.sort();
    Ok(numbered)
}

/// The frames of `dir` (listed by [`numbered_frames`]) when they run 0 to n-1, one file
/// each; an error names the first gap or repeat. `kinds` names the images looked for.
pub fn sequence(
    dir: &Path,
    numbered: Vec<(usize, PathBuf)>,
    kinds: &'static str,
) -> Result<Vec<PathBuf>, FramesError> {
    let Some(last) = numbered.last().map(|(n, _)| *n) else {
        return Err(FramesError::NoFrames {
            path: dir.to_path_buf(),
            kinds,
        });
    };
    for (i, (n, path)) in numbered.iter().enumerate() {
        if *n > i {
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy())
                .unwrap_or_default();
            return Err(FramesError::MissingFrame {
                dir: dir.to_path_buf(),
                missing: i,
                expected: frame_file_name(i, &ext),
                last,
            });
        }
        if *n < i {
            return Err(FramesError::BadTour {
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

/// The size every one of `frames` has (reading only image headers); an error names the first
/// frame of another size. `frames` must not be empty.
pub fn one_size(frames: &[PathBuf]) -> Result<(u32, u32), FramesError> {
    let (width, height) = dimensions(&frames[0])?;
    for frame in &frames[1..] {
        let (w, h) = dimensions(frame)?;
        if (w, h) != (width, height) {
            return Err(FramesError::FrameSize {
                path: frame.clone(),
                width: w,
                height: h,
                first: frames[0].clone(),
                first_width: width,
                first_height: height,
            });
        }
    }
    Ok((width, height))
}

fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// Width and height of the image at `path`, from its header (an EXR is read whole).
pub fn dimensions(path: &Path) -> Result<(u32, u32), FramesError> {
    if is_exr(path) {
        let frame = read_rgb(path)?;
        return Ok((frame.width(), frame.height()));
    }
    let read = |source| FramesError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    };
    let bad = |e: image::ImageError| FramesError::BadImage {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    image::ImageReader::open(path)
        .map_err(read)?
        .with_guessed_format()
        .map_err(read)?
        .into_dimensions()
        .map_err(bad)
}

/// A frame as 8-bit sRGB, its coverage (alpha) composited over black as the viewer shows it.
pub fn read_rgb(path: &Path) -> Result<image::RgbImage, FramesError> {
    let rgba = if is_exr(path) {
        let linear = crate::output::read_image(path)?;
        let frame = linear.to_frame();
        let bytes = frame.color.iter().flatten().copied().collect();
        image::RgbaImage::from_raw(frame.width, frame.height, bytes).ok_or_else(|| {
            FramesError::BadImage {
                path: path.to_path_buf(),
                reason: "the pixel count does not match the size".into(),
            }
        })?
    } else {
        image::open(path)
            .map_err(|e| FramesError::BadImage {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_is_composited_over_black() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 255, 128]))
            .save(&path)
            .unwrap();
        assert_eq!(read_rgb(&path).unwrap().get_pixel(0, 0).0, [100, 50, 128]);
    }

    #[test]
    fn a_repeated_number_names_both_files() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["frame_000000.png", "frame_000001.png", "frame_1.png"] {
            image::RgbImage::new(4, 2)
                .save(dir.path().join(name))
                .unwrap();
        }
        let numbered = numbered_frames(dir.path(), &["png"]).unwrap();
        assert_eq!(numbered.len(), 3);
        let e = sequence(dir.path(), numbered, "PNG")
            .unwrap_err()
            .to_string();
        assert!(e.contains("frame 1 is also"), "{e}");
        assert!(e.contains("keep one file per frame"), "{e}");
    }
}
