//! The query of `/api/render` (`x=&y=&ipd=&north=&south=&seq=&client=`), checked so that a
//! bad value gets a 400 naming its field before anything is queued.

use glam::DVec2;

use crate::projection::{PoleMerge, PoleMerging, Stereo};
use crate::value::finite;

use crate::web::query::pairs;

/// The names `/api/render` accepts.
pub const RENDER_KEYS: [&str; 7] = ["x", "y", "ipd", "north", "south", "seq", "client"];

/// Longest `client` name.
const MAX_CLIENT: usize = 64;

/// One render asked for: where the camera stands (file XY; its height comes from the ground
/// there) and the stereo settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderRequest {
    /// Camera position, file X and Y.
    pub xy: DVec2,
    /// Interocular distance, metres.
    pub ipd: f64,
    /// Pole merging at each pole.
    pub merging: PoleMerging,
    /// The client's number for this request, echoed in the reply (0 when not given): of a
    /// client's requests, only the newest renders.
    pub seq: u64,
    /// Who asks (a page names itself; empty when not given): each client has its own place
    /// in the render queue.
    pub client: String,
    /// Camera height, file Z; `None`: [`height`](Self::height) above the ground at `xy`.
    pub z: Option<f64>,
    /// Camera height above the ground, file units; `None`: the served height.
    pub height: Option<f64>,
}

/// The XY box a camera may stand in (the scan's bounds, file coordinates), and where it
/// stands when the request does not say.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraLimits {
    /// South-west corner.
    pub lo: DVec2,
    /// North-east corner.
    pub hi: DVec2,
    /// The default camera's XY.
    pub default: DVec2,
}

impl RenderRequest {
    /// What an empty query asks for: the default camera with the default IPD and pole
    /// merging.
    pub fn default_at(limits: &CameraLimits) -> Self {
        RenderRequest {
            xy: limits.default,
            ipd: Stereo::DEFAULT_IPD,
            merging: PoleMerging::both(PoleMerge::COMFORTABLE),
            seq: 0,
            client: String::new(),
            z: None,
            height: None,
        }
    }

    /// Reads a query string; the message names the field at fault and what it accepts.
    pub fn parse(query: &str, limits: &CameraLimits) -> Result<Self, String> {
        let mut request = Self::default_at(limits);
        for (key, value) in pairs(query, &RENDER_KEYS)? {
            let number = || finite(&value, &key).map_err(|e| format!("{key}={value:?}: {e}"));
            match key.as_str() {
                "x" => request.xy.x = within(&key, number()?, limits.lo.x, limits.hi.x)?,
                "y" => request.xy.y = within(&key, number()?, limits.lo.y, limits.hi.y)?,
                "ipd" => {
                    request.ipd =
                        Stereo::check_ipd(number()?).map_err(|e| format!("ipd={value:?}: {e}"))?;
                }
                "north" | "south" => {
                    let merge: PoleMerge = value
                        .parse()
                        .map_err(|e: String| format!("{key}={value:?}: {e}"))?;
                    if key == "north" {
                        request.merging.north = merge;
                    } else {
                        request.merging.south = merge;
                    }
                }
                "seq" => {
                    request.seq = value.parse().map_err(|_| {
                        format!(
                            "seq={value:?}: expected a whole number from 0 to {}",
                            u64::MAX
                        )
                    })?;
                }
                "client" => {
                    let ok = value.len() <= MAX_CLIENT
                        && value
                            .bytes()
                            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
                    if !ok {
                        return Err(format!(
                            "client={value:?}: expected up to {MAX_CLIENT} letters, digits, - or _"
                        ));
                    }
                    request.client = value;
                }
                _ => unreachable!("pairs() admits only RENDER_KEYS"),
            }
        }
        Ok(request)
    }
}

/// `v` when it lies in `lo..=hi`; else a message saying the camera must stand on the scan.
pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, String> {
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{key}={v}: the camera must stand within the scan's bounds, {key} from {lo:.3} to {hi:.3}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: CameraLimits = CameraLimits {
        lo: DVec2::new(100.0, 200.0),
        hi: DVec2::new(300.0, 400.0),
        default: DVec2::new(200.0, 300.0),
    };

    #[test]
    fn a_full_request_is_read_and_missing_fields_take_defaults() {
        let r = RenderRequest::parse(
            "x=150.5&y=399&ipd=0.07&north=marrinan:60,10,2&south=off&seq=42&client=tab-7",
            &LIMITS,
        )
        .unwrap();
        assert_eq!(r.xy, DVec2::new(150.5, 399.0));
        assert_eq!(r.ipd, 0.07);
        assert_eq!(
            r.merging.north,
            PoleMerge::Marrinan {
                start_deg: 60.0,
                end_deg: 10.0,
                exponent: 2.0
            }
        );
        assert_eq!(r.merging.south, PoleMerge::Off);
        assert_eq!((r.seq, r.client.as_str()), (42, "tab-7"));
        let d = RenderRequest::parse("", &LIMITS).unwrap();
        assert_eq!(d.xy, LIMITS.default);
        assert_eq!((d.ipd, d.seq), (Stereo::DEFAULT_IPD, 0));
        assert_eq!(d.merging, PoleMerging::both(PoleMerge::COMFORTABLE));
    }

    #[test]
    fn bad_values_name_their_field() {
        let cases = [
            ("x=NaN", "x=\"NaN\""),
            ("y=inf", "y=\"inf\": `inf` is not a finite number"),
            ("x=abc", "x=\"abc\": `abc` is not a number"),
            (
                "x=99.9",
                "x=99.9: the camera must stand within the scan's bounds",
            ),
            ("y=400.5", "y from 200.000 to 400.000"),
            (
                "ipd=-0.1",
                "ipd=\"-0.1\": the interocular distance must lie in",
            ),
            ("ipd=1e400", "ipd=\"1e400\""),
            (
                "north=marrinan:10,20,3",
                "north=\"marrinan:10,20,3\": marrinan angles",
            ),
            ("south=sideways", "south=\"sideways\": unknown pole merge"),
            ("north=marrinan:45,0,NaN", "north=\"marrinan:45,0,NaN\""),
            ("seq=-1", "seq=\"-1\""),
            ("client=a/b", "client=\"a/b\": expected up to 64 letters"),
            ("zoom=2", "unknown query parameter \"zoom\""),
            ("x=150&x=160", "given twice"),
        ];
        for (query, expected) in cases {
            let e = RenderRequest::parse(query, &LIMITS).unwrap_err();
            assert!(e.contains(expected), "{query}: {e}");
        }
    }
}
