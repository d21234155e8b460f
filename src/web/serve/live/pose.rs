//! A pose message: the JSON text a client sends, read and checked against the scan so that
//! a bad one closes its connection with a reason naming the field.

use glam::DVec2;
use serde::Deserialize;

use crate::output::xmp::heading_from_yaw;
use crate::projection::Stereo;

use super::super::request::{CameraLimits, RenderRequest, within};

/// Longest pose message accepted, bytes; a longer one closes the connection.
pub const MAX_POSE_BYTES: usize = 4096;

/// A pose as sent: file coordinates, degrees, metres.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseMessage {
    seq: u64,
    x: f64,
    y: f64,
    z: Option<f64>,
    yaw: f64,
    pitch: Option<f64>,
    ipd: Option<f64>,
    height: Option<f64>,
}

/// Where a pose may place the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseLimits {
    /// The XY box (the scan's bounds).
    pub xy: CameraLimits,
    /// Lowest and highest camera Z, file units.
    pub z: (f64, f64),
    /// File units per metre (`height` and `ipd` come in metres).
    pub per_metre: f64,
}

/// A pose read from a client, ready to render.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// The render it asks for (client name left empty).
    pub request: RenderRequest,
    /// Heading, degrees clockwise from north (file +Y), in `[0, 360)`.
    pub yaw: f64,
    /// Look up (+) or down, degrees.
    pub pitch: f64,
}

/// Why a message was refused: the WebSocket close code that says so, and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// Not JSON, or not a pose (a missing or unknown field, a wrong type, a number JSON
    /// cannot hold such as NaN): close code 1007.
    #[error("not a pose: {0}")]
    Malformed(String),
    /// A value out of its range (a non-finite number, a pitch beyond ±90°): 1007.
    #[error("{0}")]
    Invalid(String),
    /// A position outside the scan: 1008.
    #[error("{0}")]
    Outside(String),
}

impl PoseError {
    /// The WebSocket close code for this refusal.
    pub fn close_code(&self) -> u16 {
        match self {
            PoseError::Malformed(_) | PoseError::Invalid(_) => 1007,
            PoseError::Outside(_) => 1008,
        }
    }
}

/// Reads and checks one pose message.
pub fn parse_pose(text: &str, limits: &PoseLimits) -> Result<Pose, PoseError> {
    let m: PoseMessage =
        serde_json::from_str(text).map_err(|e| PoseError::Malformed(e.to_string()))?;
    let finite = |key: &str, v: f64| {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(PoseError::Invalid(format!(
                "{key}={v}: not a finite number"
            )))
        }
    };
    let outside = PoseError::Outside;
    let x = within("x", finite("x", m.x)?, limits.xy.lo.x, limits.xy.hi.x).map_err(outside)?;
    let y = within("y", finite("y", m.y)?, limits.xy.lo.y, limits.xy.hi.y).map_err(outside)?;
    let z = match m.z {
        Some(z) => Some(within("z", finite("z", z)?, limits.z.0, limits.z.1).map_err(outside)?),
        None => None,
    };
    let yaw = heading_from_yaw(finite("yaw", m.yaw)?);
    let pitch = finite("pitch", m.pitch.unwrap_or(0.0))?;
    if pitch.abs() > 90.0 {
        return Err(PoseError::Invalid(format!(
            "pitch={pitch}: expected -90 to 90 degrees"
        )));
    }
    let mut request = RenderRequest::default_at(&limits.xy);
    request.xy = DVec2::new(x, y);
    request.z = z;
    request.seq = m.seq;
    if let Some(ipd) = m.ipd {
        request.ipd = Stereo::check_ipd(finite("ipd", ipd)?)
            .map_err(|e| PoseError::Invalid(format!("ipd={ipd}: {e}")))?;
    }
    if let Some(h) = m.height {
        let h = finite("height", h)?;
        if !(0.0..=1000.0).contains(&h) {
            return Err(PoseError::Invalid(format!(
                "height={h}: expected 0 to 1000 metres above the ground"
            )));
        }
        request.height = Some(h * limits.per_metre);
    }
    Ok(Pose {
        request,
        yaw,
        pitch,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: PoseLimits = PoseLimits {
        xy: CameraLimits {
            lo: DVec2::new(100.0, 200.0),
            hi: DVec2::new(300.0, 400.0),
            default: DVec2::new(200.0, 300.0),
        },
        z: (-50.0, 250.0),
        per_metre: 1.0 / 0.3048,
    };

    #[test]
    fn a_full_pose_is_read_and_the_optional_fields_default() {
        let p = parse_pose(
            r#"{"seq": 9, "x": 150.5, "y": 399, "z": 12.5, "yaw": -90, "pitch": 10,
                "ipd": 0.07, "height": 3.048}"#,
            &LIMITS,
        )
        .unwrap();
        assert_eq!(p.request.xy, DVec2::new(150.5, 399.0));
        assert_eq!(
            (p.request.z, p.request.seq, p.request.ipd),
            (Some(12.5), 9, 0.07)
        );
        assert!(
            (p.request.height.unwrap() - 10.0).abs() < 1e-9,
            "3.048 m in feet"
        );
        assert_eq!((p.yaw, p.pitch), (270.0, 10.0));
        let tiny = parse_pose(r#"{"seq": 2, "x": 200, "y": 300, "yaw": -1e-20}"#, &LIMITS);
        assert_eq!(tiny.unwrap().yaw, 0.0, "yaw stays in [0, 360)");
        let d = parse_pose(r#"{"seq": 1, "x": 200, "y": 300, "yaw": 0}"#, &LIMITS).unwrap();
        assert_eq!((d.request.z, d.request.height), (None, None));
        assert_eq!((d.request.ipd, d.pitch), (Stereo::DEFAULT_IPD, 0.0));
    }

    #[test]
    fn bad_poses_are_refused_with_their_close_code_and_field() {
        let cases = [
            ("{", 1007, "EOF while parsing"),
            (
                r#"{"seq": 1, "x": NaN, "y": 300, "yaw": 0}"#,
                1007,
                "not a pose",
            ),
            (
                r#"{"seq": 1, "x": 1e400, "y": 300, "yaw": 0}"#,
                1007,
                "not a pose",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300}"#,
                1007,
                "missing field `yaw`",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300, "yaw": 0, "zoom": 2}"#,
                1007,
                "unknown field `zoom`",
            ),
            (
                r#"{"seq": -1, "x": 200, "y": 300, "yaw": 0}"#,
                1007,
                "not a pose",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300, "yaw": 0, "pitch": 91}"#,
                1007,
                "pitch=91",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300, "yaw": 0, "ipd": -1}"#,
                1007,
                "ipd=-1",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300, "yaw": 0, "height": -2}"#,
                1007,
                "height=-2",
            ),
            (
                r#"{"seq": 1, "x": 99, "y": 300, "yaw": 0}"#,
                1008,
                "x=99: the camera must stand",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 401, "yaw": 0}"#,
                1008,
                "y from 200.000",
            ),
            (
                r#"{"seq": 1, "x": 200, "y": 300, "z": 251, "yaw": 0}"#,
                1008,
                "z=251",
            ),
        ];
        for (text, code, expected) in cases {
            let e = parse_pose(text, &LIMITS).unwrap_err();
            assert_eq!(e.close_code(), code, "{text}: {e}");
            assert!(e.to_string().contains(expected), "{text}: {e}");
        }
    }
}
