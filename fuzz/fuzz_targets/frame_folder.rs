//! A folder of frames as `view DIR` and `video DIR` read it: `tour.json`, the frame names
//! and each frame's image header (PNG, JPEG or EXR, with the description omnicloud writes).
//!
//! Input: sections split by a line `@@`; the first is `tour.json` (absent when empty), each
//! other is a file, its first line the name (letters, digits, `_`, `.`, `-`), the rest its
//! bytes.
#![no_main]

mod common;

use omnicloud::frames::{FrameFolder, StereoChoice};
use omnicloud::web::Panorama;

/// Files written per input.
const MAX_FILES: usize = 12;

fn safe_name(name: &str) -> bool {
    (1..=64).contains(&name.len())
        && name != "."
        && name != ".."
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"_.-".contains(&b))
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let dir = common::scratch_dir().join("frames");
    let _ = std::fs::remove_dir_all(&dir);
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    let mut sections = split(data, b"\n@@\n");
    if let Some(manifest) = sections.next()
        && !manifest.is_empty()
    {
        let _ = std::fs::write(dir.join("tour.json"), manifest);
    }
    for section in sections.take(MAX_FILES) {
        let (name, bytes) = match section.iter().position(|&b| b == b'\n') {
            Some(i) => (&section[..i], &section[i + 1..]),
            None => (section, &[][..]),
        };
        let Ok(name) = std::str::from_utf8(name) else {
            continue;
        };
        if safe_name(name) && name != "tour.json" {
            let _ = std::fs::write(dir.join(name), bytes);
        }
    }

    if let Ok(panorama) = Panorama::open(&dir) {
        assert!(!panorama.frames.is_empty());
        assert!(
            panorama
                .stations
                .iter()
                .all(|s| s.frame < panorama.frame_count())
        );
        let info = panorama.info();
        let _ = serde_json::to_string(&info).expect("the info serialises");
    }
    for stereo in [
        StereoChoice::Auto,
        StereoChoice::Mono,
        StereoChoice::TopBottom,
    ] {
        match FrameFolder::open(&dir, stereo) {
            Ok(folder) => {
                assert!(!folder.frames.is_empty() && folder.width > 0 && folder.height > 0);
                if let Some(n) = folder.tour.as_ref().and_then(|t| t.frames) {
                    assert_eq!(n, folder.frames.len());
                }
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
});

/// `data` split at each `sep`.
fn split<'a>(data: &'a [u8], sep: &'a [u8]) -> impl Iterator<Item = &'a [u8]> {
    let mut rest = Some(data);
    std::iter::from_fn(move || {
        let r = rest?;
        match r.windows(sep.len()).position(|w| w == sep) {
            Some(i) => {
                rest = Some(&r[i + sep.len()..]);
                Some(&r[..i])
            }
            None => {
                rest = None;
                Some(r)
            }
        }
    })
}
