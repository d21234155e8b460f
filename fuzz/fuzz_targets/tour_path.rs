//! A tour's path file (CSV keyframes or GeoJSON lines), chosen as `tour` chooses: text that
//! starts with `{` is GeoJSON. Accepted keyframes then go through the curve and the frame
//! poses as a tour plans them.
#![no_main]

use std::path::Path;

use glam::DVec3;
use omnicloud::tour::path::{parse_csv, parse_geojson};
use omnicloud::tour::poses::{self, Heading, Sampling};
use omnicloud::tour::spline::Spline;

/// Largest |coordinate| planned: a tour keeps keyframes inside the scan's bounds, which are
/// finite and far smaller than this.
const EXTENT: f64 = 1e7;
/// Keyframes planned per input: the curve's table is 512 steps a segment.
const MAX_PLANNED: usize = 64;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("path.csv");
    let parsed = if text.trim_start().starts_with('{') {
        parse_geojson(path, text)
    } else {
        parse_csv(path, text)
    };
    let keyframes = match parsed {
        Ok(k) => k,
        Err(e) => {
            assert!(e.to_string().starts_with("path.csv"), "{e}");
            return;
        }
    };
    for k in &keyframes {
        let ok = k.x.is_finite()
            && k.y.is_finite()
            && k.z.is_none_or(f64::is_finite)
            && k.yaw.is_none_or(f64::is_finite)
            && k.pitch.is_finite()
            && k.roll.is_finite();
        assert!(ok, "{k:?}");
        assert!(!k.at.is_empty());
    }
    plan(&keyframes);
});

/// The curve and poses `tour` makes of keyframes inside a scan.
fn plan(keyframes: &[omnicloud::tour::Keyframe]) {
    let mut points: Vec<DVec3> = keyframes
        .iter()
        .take(MAX_PLANNED)
        .map(|k| DVec3::new(k.x, k.y, k.z.unwrap_or(0.0)))
        .collect();
    if points.iter().any(|p| p.abs().max_element() > EXTENT) {
        return;
    }
    points.dedup();
    let Some(spline) = Spline::new(&points) else {
        return;
    };
    assert!(spline.length().is_finite() && spline.length() > 0.0);
    let yaws: Option<Vec<f64>> = keyframes.iter().take(points.len()).map(|k| k.yaw).collect();
    let heading = match yaws {
        Some(y) if y.len() == points.len() => Heading::Keyframes(y),
        _ => Heading::Tangent { window: 2.0 },
    };
    let mut poses = poses::sample(&spline, Sampling::Frames(33), &heading, 0.0);
    let pitches: Vec<f64> = keyframes
        .iter()
        .take(points.len())
        .map(|k| k.pitch)
        .collect();
    let rolls: Vec<f64> = keyframes
        .iter()
        .take(points.len())
        .map(|k| k.roll)
        .collect();
    let tilts = (pitches.len() == points.len()).then_some((&pitches[..], &rolls[..]));
    poses::tilt(&mut poses, &spline, tilts, 0.0, 0.0);
    for p in &poses {
        let ok = p.position.iter().all(|v| v.is_finite())
            && p.yaw.is_finite()
            && p.pitch.is_finite()
            && p.roll.is_finite()
            && p.arc_length.is_finite();
        assert!(ok, "{p:?}");
    }
}
