//! A tour folder's `tour.json`: the fields `video` and `view` read from it, and the whole
//! manifest as `tour` writes it.
#![no_main]

use std::path::Path;

use omnicloud::frames::manifest::parse_manifest;
use omnicloud::tour::TourManifest;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("tour.json");
    match parse_manifest(path, text) {
        Ok(info) => {
            assert!(
                info.fps.is_none_or(|f| f.is_finite() && f > 0.0),
                "{info:?}"
            );
            for s in &info.stations {
                let _ = (s.frame, s.scan, s.name.as_deref());
            }
        }
        Err(e) => assert!(e.to_string().contains("tour.json"), "{e}"),
    }
    if let Ok(manifest) = serde_json::from_str::<TourManifest>(text) {
        // What was read is written back the same way.
        let again = serde_json::to_string(&manifest).expect("a manifest serialises");
        let reread: TourManifest = serde_json::from_str(&again).expect("its own JSON reads");
        assert_eq!(reread.frames.len(), manifest.frames.len());
    }
});
