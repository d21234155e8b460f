//! The page's query string (`/?yaw=30&pitch=10&fov=90&mode=anaglyph&frame=3`): a view to open
//! at, checked by the server so a bad link gets a 400 that says what is wrong.

use super::panorama::{Panorama, PanoramaKind};

/// The names `/` accepts.
const VIEW_KEYS: [&str; 5] = ["yaw", "pitch", "fov", "mode", "frame"];

/// How an ODS pair is shown on a flat screen.
pub const MODES: [&str; 4] = ["mono", "anaglyph", "left", "right"];

/// Checks a query string against the keys a route accepts: each at most once.
pub fn pairs(query: &str, allowed: &[&str]) -> Result<Vec<(String, String)>, String> {
    let mut seen: Vec<(String, String)> = Vec::new();
    for (key, value) in form_urlencoded::parse(query.as_bytes()) {
        if !allowed.contains(&key.as_ref()) {
            return Err(if allowed.is_empty() {
                format!("unknown query parameter {key:?}: this address takes none")
            } else {
                format!(
                    "unknown query parameter {key:?}: expected one of {}",
                    allowed.join(", ")
                )
            });
        }
        if seen.iter().any(|(k, _)| *k == key) {
            return Err(format!("query parameter {key:?} given twice"));
        }
        seen.push((key.into_owned(), value.into_owned()));
    }
    Ok(seen)
}

/// Checks the page's view parameters against the panorama; the message says which is wrong.
pub fn check_view(query: &str, panorama: &Panorama) -> Result<(), String> {
    for (key, value) in pairs(query, &VIEW_KEYS)? {
        match key.as_str() {
            "yaw" => number(&key, &value, -360.0, 360.0)?,
            "pitch" => number(&key, &value, -90.0, 90.0)?,
            "fov" => number(&key, &value, 10.0, 120.0)?,
            "mode" => {
                if !MODES.contains(&value.as_str()) {
                    return Err(format!(
                        "mode={value:?}: expected one of {}",
                        MODES.join(", ")
                    ));
                }
                if panorama.kind == PanoramaKind::Mono && value != "mono" {
                    return Err(format!(
                        "mode={value}: this panorama is mono; the eye modes need an ODS pair"
                    ));
                }
            }
            "frame" => {
                let count = panorama.frame_count();
                match value.parse::<usize>() {
                    Ok(n) if n < count => {}
                    _ => {
                        return Err(format!(
                            "frame={value:?}: expected a whole number from 0 to {}",
                            count - 1
                        ));
                    }
                }
            }
            _ => unreachable!("pairs() admits only VIEW_KEYS"),
        }
    }
    Ok(())
}

fn number(key: &str, value: &str, lo: f64, hi: f64) -> Result<(), String> {
    match value.parse::<f64>() {
        Ok(x) if (lo..=hi).contains(&x) => Ok(()),
        _ => Err(format!(
            "{key}={value:?}: expected a number of degrees from {lo} to {hi}"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::web::panorama::{FrameFile, ImageType};

    fn panorama(kind: PanoramaKind, frames: usize) -> Panorama {
        let frame = FrameFile {
            path: "p.png".into(),
            image_type: ImageType::Png,
        };
        Panorama {
            kind,
            width: 8,
            height: 4,
            frames: vec![frame; frames],
            video: None,
            stations: Vec::new(),
        }
    }

    #[test]
    fn good_views_pass() {
        let ods = panorama(PanoramaKind::Ods, 3);
        check_view("", &ods).unwrap();
        check_view("yaw=-30.5&pitch=90&fov=10&mode=anaglyph&frame=2", &ods).unwrap();
        check_view("mode=mono", &panorama(PanoramaKind::Mono, 1)).unwrap();
    }

    #[test]
    fn bad_views_say_what_is_wrong() {
        let mono = panorama(PanoramaKind::Mono, 3);
        let cases = [
            ("yaw=abc", "yaw=\"abc\": expected a number"),
            ("pitch=91", "pitch=\"91\""),
            ("fov=NaN", "fov=\"NaN\""),
            ("frame=3", "from 0 to 2"),
            ("frame=-1", "frame=\"-1\""),
            ("mode=left", "this panorama is mono"),
            ("mode=sideways", "expected one of mono, anaglyph"),
            ("zoom=2", "unknown query parameter \"zoom\""),
            ("yaw=1&yaw=2", "given twice"),
        ];
        for (query, expected) in cases {
            let e = check_view(query, &mono).unwrap_err();
            assert!(e.contains(expected), "{query}: {e}");
        }
    }

    #[test]
    fn routes_without_parameters_refuse_any() {
        assert!(pairs("", &[]).unwrap().is_empty());
        let e = pairs("x=1", &[]).unwrap_err();
        assert!(e.contains("takes none"), "{e}");
    }
}
