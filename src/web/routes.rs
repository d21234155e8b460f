//! From a request line to a reply, without sockets: which address serves what.
//!
//! Addresses are a fixed set (`/`, `/viewer.js`, `/api/info`, `/frames/N`, `/video` for an
//! MP4, which the server sends in byte ranges as video elements ask); no part of a URL
//! is ever joined to a file path, so only the files the viewer was given can be served.
//! Paths that try to climb (`..`, also percent-encoded) get 403, everything else unknown 404.

use std::path::PathBuf;

use percent_encoding::percent_decode_str;

use super::assets;
use super::panorama::{ImageType, Panorama};
use super::query;

/// The body of a reply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Body {
    /// Text built into the binary.
    Static(&'static str),
    /// Text made for this request (JSON, error messages).
    Text(String),
    /// A served image or video file, read when the reply is sent (in the byte range the
    /// request asks for, if any).
    File(PathBuf),
    /// Bytes made for this request (a rendered image).
    Bytes(Vec<u8>),
}

/// A reply: status, media type and body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reply {
    /// HTTP status code.
    pub status: u16,
    /// `Content-Type`.
    pub content_type: &'static str,
    /// What to send.
    pub body: Body,
    /// Headers beyond the ones every reply has (name, ASCII value).
    pub headers: Vec<(&'static str, String)>,
}

impl Reply {
    /// A 200 reply.
    pub fn ok(content_type: &'static str, body: Body) -> Self {
        Self {
            status: 200,
            content_type,
            body,
            headers: Vec::new(),
        }
    }

    /// A plain-text error reply.
    pub fn error(status: u16, message: impl Into<String>) -> Self {
        let mut text = message.into();
        text.push('\n');
        Self {
            status,
            content_type: "text/plain; charset=utf-8",
            body: Body::Text(text),
            headers: Vec::new(),
        }
    }

    /// A JSON reply of `value`; 500 if it cannot be written.
    pub fn json(value: &impl serde::Serialize) -> Self {
        match serde_json::to_string(value) {
            Ok(json) => Reply::ok("application/json", Body::Text(json)),
            Err(e) => Reply::error(500, format!("cannot write the JSON reply: {e}")),
        }
    }
}

/// A GET (or HEAD) request's decoded path and raw query; the error reply for another method,
/// a path that is not UTF-8, or one that tries to climb out of the address set (403).
pub fn checked_path(method: &str, url: &str) -> Result<(String, String), Reply> {
    if method != "GET" && method != "HEAD" {
        return Err(Reply::error(
            405,
            format!("method {method} not allowed: use GET"),
        ));
    }
    let (raw_path, query) = url.split_once('?').unwrap_or((url, ""));
    let path = match percent_decode_str(raw_path).decode_utf8() {
        Ok(p) => p,
        Err(_) => return Err(Reply::error(400, "the path is not UTF-8 once decoded")),
    };
    if climbs(&path) {
        return Err(Reply::error(
            403,
            "this server serves only its own fixed addresses",
        ));
    }
    Ok((path.into_owned(), query.to_owned()))
}

/// Answers one request: `method` as sent, `url` the request target (path and query).
pub fn route(method: &str, url: &str, panorama: &Panorama) -> Reply {
    let (path, query) = match checked_path(method, url) {
        Ok(checked) => checked,
        Err(reply) => return reply,
    };
    let query = query.as_str();
    let no_query = |reply: Reply| match query::pairs(query, &[]) {
        Ok(_) => reply,
        Err(e) => Reply::error(400, e),
    };
    match path.as_str() {
        "/" | "/index.html" => match query::check_view(query, panorama) {
            Ok(()) => Reply::ok("text/html; charset=utf-8", Body::Static(assets::INDEX_HTML)),
            Err(e) => Reply::error(400, e),
        },
        "/viewer.js" => no_query(Reply::ok(
            "text/javascript; charset=utf-8",
            Body::Static(assets::VIEWER_JS),
        )),
        "/api/info" => no_query(Reply::json(&panorama.info())),
        "/video" => no_query(match panorama.video {
            Some(_) => Reply::ok(
                ImageType::Mp4.mime(),
                Body::File(panorama.frames[0].path.clone()),
            ),
            None => Reply::error(
                404,
                "this panorama is not a video: its frames are at /frames/N",
            ),
        }),
        p => match p.strip_prefix("/frames/") {
            Some(_) if panorama.video.is_some() => {
                Reply::error(404, "this panorama is a video: it is served at /video")
            }
            Some(index) => no_query(frame(index, panorama)),
            None => Reply::error(404, format!("no such page: {path}")),
        },
    }
}

/// Frame `index` (decimal digits only, below the frame count).
fn frame(index: &str, panorama: &Panorama) -> Reply {
    let count = panorama.frames.len();
    let found = index
        .bytes()
        .all(|b| b.is_ascii_digit())
        .then(|| index.parse::<usize>().ok())
        .flatten()
        .and_then(|n| panorama.frames.get(n));
    match found {
        Some(f) => Reply::ok(f.image_type.mime(), Body::File(f.path.clone())),
        None => Reply::error(
            404,
            format!("no frame {index:?}: frames are numbered 0 to {}", count - 1),
        ),
    }
}

/// Whether a decoded path tries to leave the fixed address set: parent segments, backslashes
/// (a parent segment to some servers), NUL bytes, or no leading slash (absolute URLs).
fn climbs(path: &str) -> bool {
    !path.starts_with('/')
        || path.contains('\\')
        || path.contains('\0')
        || path.split('/').any(|segment| segment == "..")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::web::panorama::{FrameFile, ImageType, PanoramaKind};

    fn panorama() -> Panorama {
        let frame = |n: u32| FrameFile {
            path: format!("/data/frame_{n}.png").into(),
            image_type: ImageType::Png,
        };
        Panorama {
            kind: PanoramaKind::Ods,
            width: 8,
            height: 8,
            frames: vec![frame(0), frame(1)],
            video: None,
            stations: Vec::new(),
        }
    }

    fn video() -> Panorama {
        Panorama {
            kind: PanoramaKind::Mono,
            width: 16,
            height: 8,
            frames: vec![FrameFile {
                path: "/data/tour.mp4".into(),
                image_type: ImageType::Mp4,
            }],
            video: Some(crate::web::panorama::VideoTrack {
                frames: 12,
                fps: 24.0,
            }),
            stations: Vec::new(),
        }
    }

    #[test]
    fn a_video_is_served_at_its_own_address_only() {
        let v = video();
        let r = route("GET", "/video", &v);
        assert_eq!(r.body, Body::File("/data/tour.mp4".into()));
        assert_eq!(r.content_type, "video/mp4");
        assert_eq!(route("GET", "/frames/0", &v).status, 404);
        assert_eq!(route("GET", "/video?x=1", &v).status, 400);
        assert_eq!(route("GET", "/video", &panorama()).status, 404);
        assert_eq!(
            route("GET", "/api/info", &v).body,
            Body::Text(
                r#"{"kind":"mono","width":16,"height":8,"frames":12,"video":{"frames":12,"fps":24.0}}"#
                    .into()
            )
        );
        assert_eq!(route("GET", "/?frame=11", &v).status, 200);
        assert_eq!(route("GET", "/?frame=12", &v).status, 400);
    }

    #[test]
    fn pages_info_and_frames_are_served() {
        let p = panorama();
        assert_eq!(route("GET", "/", &p).body, Body::Static(assets::INDEX_HTML));
        assert_eq!(route("GET", "/viewer.js", &p).status, 200);
        let info = route("GET", "/api/info", &p);
        assert_eq!(
            info.body,
            Body::Text(r#"{"kind":"ods","width":8,"height":8,"frames":2}"#.into())
        );
        let f = route("GET", "/frames/1", &p);
        assert_eq!(f.body, Body::File("/data/frame_1.png".into()));
        assert_eq!(f.content_type, "image/png");
        assert_eq!(route("HEAD", "/frames/0", &p).status, 200);
    }

    #[test]
    fn climbing_paths_are_forbidden_and_unknown_ones_not_found() {
        let p = panorama();
        for url in [
            "/../../etc/passwd",
            "/%2e%2e/%2e%2e/etc/passwd",
            "/frames/..%2f..%2fetc%2fpasswd",
            "/frames/%2E%2E",
            "/..%5c..%5cetc%5cpasswd",
            "http://example.com/etc/passwd",
            "/frames/0%00.png",
        ] {
            assert_eq!(route("GET", url, &p).status, 403, "{url}");
        }
        for url in [
            "/etc/passwd",
            "//etc/passwd",
            "/frames/2",
            "/frames/-1",
            "/frames/+1",
            "/frames/1.0",
            "/frames/99999999999999999999999",
            "/frame_0.png",
            "/data/frame_0.png",
        ] {
            let r = route("GET", url, &p);
            assert_eq!(r.status, 404, "{url}");
            assert!(!matches!(r.body, Body::File(_)), "{url}");
        }
    }

    #[test]
    fn bad_queries_get_400_and_other_methods_405() {
        let p = panorama();
        assert_eq!(route("GET", "/?yaw=east", &p).status, 400);
        assert_eq!(route("GET", "/api/info?x=1", &p).status, 400);
        assert_eq!(route("GET", "/frames/0?size=big", &p).status, 400);
        assert_eq!(route("POST", "/api/info", &p).status, 405);
    }
}
