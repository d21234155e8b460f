//! `serve`'s addresses: the page and its scripts, the scan's description and map, and live
//! renders. Paths are checked as `view` checks them (no part of a URL names a file).

use crate::web::assets;
use crate::web::query::pairs;
use crate::web::routes::{Body, Reply, checked_path};

use super::render_thread::{LiveFrame, RenderFailure};
use super::request::RenderRequest;
use super::scan::LiveScan;

/// Answers one request; `render` renders a checked request (the render thread, or a
/// stand-in in tests).
pub fn route(
    method: &str,
    url: &str,
    scan: &LiveScan,
    render: &dyn Fn(RenderRequest) -> Result<LiveFrame, RenderFailure>,
) -> Reply {
    let (path, query) = match checked_path(method, url) {
        Ok(checked) => checked,
        Err(reply) => return reply,
    };
    let no_query = |reply: Reply| match pairs(&query, &[]) {
        Ok(_) => reply,
        Err(e) => Reply::error(400, e),
    };
    let script = |text| Reply::ok("text/javascript; charset=utf-8", Body::Static(text));
    match path.as_str() {
        // The page takes the view a link reproduces (live.js reads it).
        "/" | "/index.html" => match pairs(&query, &["x", "y", "yaw"]) {
            Ok(_) => Reply::ok("text/html; charset=utf-8", Body::Static(assets::SERVE_HTML)),
            Err(e) => Reply::error(400, e),
        },
        "/viewer.js" => no_query(script(assets::VIEWER_JS)),
        "/serve.js" => no_query(script(assets::SERVE_JS)),
        "/live.js" => no_query(script(assets::LIVE_JS)),
        "/api/scan" => no_query(Reply::json(&scan.info)),
        "/map.png" => no_query(Reply::ok("image/png", Body::Bytes(scan.map_png.clone()))),
        "/api/render" => match RenderRequest::parse(&query, &scan.limits) {
            Ok(request) => frame_reply(render(request)),
            Err(e) => Reply::error(400, e),
        },
        _ => Reply::error(404, format!("no such page: {path}")),
    }
}

/// The PNG with the camera, sequence number and render time in headers; a failure's status
/// says whose fault it was.
fn frame_reply(result: Result<LiveFrame, RenderFailure>) -> Reply {
    match result {
        Ok(frame) => {
            let c = frame.camera;
            let mut reply = Reply::ok("image/png", Body::Bytes(frame.png));
            reply.headers = vec![
                (CAMERA_HEADER, format!("{},{},{}", c.x, c.y, c.z)),
                (SEQ_HEADER, frame.seq.to_string()),
                (
                    TIME_HEADER,
                    format!("{:.1}", frame.elapsed.as_secs_f64() * 1e3),
                ),
            ];
            reply
        }
        Err(e) => {
            let status = match e {
                RenderFailure::Superseded => 409,
                RenderFailure::NoGround { .. } => 400,
                RenderFailure::Failed(_) => 500,
                RenderFailure::Busy | RenderFailure::Stopped => 503,
            };
            let mut reply = Reply::error(status, e.to_string());
            if e == RenderFailure::Busy {
                reply.headers = vec![("Retry-After", "1".to_owned())];
            }
            reply
        }
    }
}

/// The camera a render was made from, file coordinates: `X,Y,Z`.
pub const CAMERA_HEADER: &str = "X-Omnicloud-Camera";
/// The request's `seq`, echoed.
pub const SEQ_HEADER: &str = "X-Omnicloud-Seq";
/// Milliseconds the render took (upload, render, PNG encoding).
pub const TIME_HEADER: &str = "X-Omnicloud-Render-Ms";

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use crate::web::serve::scan::LiveOptions;
    use glam::{DVec3, Vec3};
    use std::path::Path;
    use std::time::Duration;

    fn scan() -> LiveScan {
        let pts = (0..100)
            .map(|k| Vec3::new((k % 10) as f32 - 5.0, (k / 10) as f32 - 5.0, -1.7))
            .collect();
        let scene = Scene::new(DVec3::new(100.0, 200.0, 10.0), pts, 0.5);
        let options = LiveOptions {
            map_size: 20,
            ..LiveOptions::default()
        };
        LiveScan::new(Path::new("grid.laz"), scene, options).unwrap()
    }

    /// Renders nothing: answers with the request's position as the camera.
    fn echo(request: RenderRequest) -> Result<LiveFrame, RenderFailure> {
        if request.ipd == 0.1 {
            return Err(RenderFailure::Failed("the GPU is on fire".into()));
        }
        Ok(LiveFrame {
            png: b"\x89PNG".to_vec(),
            camera: request.xy.extend(8.3),
            seq: request.seq,
            elapsed: Duration::from_millis(12),
        })
    }

    #[test]
    fn the_page_scripts_scan_and_map_are_served() {
        let scan = scan();
        let page = route("GET", "/", &scan, &echo);
        assert_eq!(page.body, Body::Static(assets::SERVE_HTML));
        let link = route("GET", "/?x=101.5&y=202&yaw=90.0", &scan, &echo);
        assert_eq!(link.body, Body::Static(assets::SERVE_HTML));
        assert_eq!(route("GET", "/?zoom=2", &scan, &echo).status, 400);
        for path in [
            "/viewer.js",
            "/serve.js",
            "/live.js",
            "/api/scan",
            "/map.png",
        ] {
            assert_eq!(route("GET", path, &scan, &echo).status, 200, "{path}");
        }
        let Body::Text(json) = route("GET", "/api/scan", &scan, &echo).body else {
            panic!("not text")
        };
        let json: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(json["file"], "grid.laz");
        assert_eq!(json["points"], 100);
        // The grid's ground lies 1.7 m below the prepared camera, where LiveOptions stands it.
        assert_eq!(json["camera"][0], 100.0);
        assert!(
            (json["camera"][2].as_f64().unwrap() - 10.0).abs() < 1e-5,
            "{json}"
        );
    }

    #[test]
    fn a_render_carries_its_camera_seq_and_time_and_failures_their_status() {
        let scan = scan();
        let ok = route("GET", "/api/render?x=101&y=202.5&seq=7", &scan, &echo);
        assert_eq!((ok.status, ok.content_type), (200, "image/png"));
        assert_eq!(
            ok.headers,
            vec![
                (CAMERA_HEADER, "101,202.5,8.3".to_owned()),
                (SEQ_HEADER, "7".to_owned()),
                (TIME_HEADER, "12.0".to_owned()),
            ]
        );
        let failed = route("GET", "/api/render?ipd=0.1", &scan, &echo);
        assert_eq!(failed.status, 500);
        assert_eq!(
            failed.body,
            Body::Text("the render failed: the GPU is on fire\n".into())
        );
        let bad = route("GET", "/api/render?x=NaN", &scan, &echo);
        assert_eq!(bad.status, 400);
        assert_eq!(route("GET", "/api/render?y=500", &scan, &echo).status, 400);
        assert_eq!(route("GET", "/../etc/passwd", &scan, &echo).status, 403);
        assert_eq!(route("GET", "/frames/0", &scan, &echo).status, 404);
        assert_eq!(route("GET", "/map.png?x=1", &scan, &echo).status, 400);
        assert_eq!(route("POST", "/api/render", &scan, &echo).status, 405);
        assert_eq!(frame_reply(Err(RenderFailure::Superseded)).status, 409);
        let busy = frame_reply(Err(RenderFailure::Busy));
        assert_eq!(busy.status, 503);
        assert_eq!(busy.headers, vec![("Retry-After", "1".to_owned())]);
    }
}
