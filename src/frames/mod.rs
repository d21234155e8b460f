//! A folder of frames as `omnicloud tour` writes it, with one owner for tours, videos and
//! the viewer: the frame files' names and numbering (`frame_000000.png`, ...), listing them
//! in order, checking that they share one size, the stereo layout they hold, and the folder's
//! manifest (`tour.json`: [`manifest`]).

mod error;
pub mod folder;
pub mod listing;
pub mod manifest;

use std::path::Path;

pub use error::FramesError;
pub use folder::{FrameFolder, StereoChoice, StereoSource};
pub use listing::{dimensions, numbered_frames, one_size, read_rgb, sequence};
pub use manifest::{MANIFEST_NAME, StationMark, TourInfo, read_manifest, write_manifest};

/// The file name of frame `index` with extension `ext`: `frame_000042.png`.
pub fn frame_file_name(index: usize, ext: &str) -> String {
    format!("frame_{index:06}.{ext}")
}

/// `N` of a file named `frame_N.ext` with `ext` (any case) one of `extensions` (lower case).
pub fn frame_number(path: &Path, extensions: &[&str]) -> Option<usize> {
    let name = path.file_name()?.to_str()?;
    let (stem, ext) = name.rsplit_once('.')?;
    if !extensions.contains(&ext.to_ascii_lowercase().as_str()) {
        return None;
    }
    let digits = stem.strip_prefix("frame_")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_round_trip_through_their_numbers() {
        assert_eq!(frame_file_name(42, "png"), "frame_000042.png");
        let png = ["png"];
        assert_eq!(
            frame_number(Path::new("d/frame_000042.png"), &png),
            Some(42)
        );
        assert_eq!(frame_number(Path::new("frame_7.PNG"), &png), Some(7));
        assert_eq!(frame_number(Path::new("frame_7.jpg"), &png), None);
        assert_eq!(frame_number(Path::new("frame_.png"), &png), None);
        assert_eq!(frame_number(Path::new("frame_-1.png"), &png), None);
        assert_eq!(frame_number(Path::new("shot_000001.png"), &png), None);
    }
}
