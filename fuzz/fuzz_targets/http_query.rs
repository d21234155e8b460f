//! HTTP requests as `view` and `serve` answer them: the method, the request target (path,
//! percent-escapes and query) and a `Range` header. The first byte picks the method and the
//! panorama `view` serves; the rest is the target, and a second line the `Range` header.
//! A file is only ever served from the panorama's own frames.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use glam::{DVec3, Vec3};
use omnicloud::Scene;
use omnicloud::web::panorama::{FrameFile, ImageType, VideoTrack};
use omnicloud::web::routes::{Body, route};
use omnicloud::web::serve::{LiveOptions, LiveScan, RenderFailure, RenderRequest};
use omnicloud::web::{FileRange, Panorama, PanoramaKind, byte_range};

const METHODS: [&str; 4] = ["GET", "HEAD", "POST", "get"];

fn frames(n: usize, ext: &str, image_type: ImageType) -> Vec<FrameFile> {
    (0..n)
        .map(|i| FrameFile {
            path: PathBuf::from(format!("/pano/frame_{i:06}.{ext}")),
            image_type,
        })
        .collect()
}

/// The panoramas `view` serves: one image, a folder of ODS frames with stations, a video.
fn panoramas() -> &'static [Panorama; 3] {
    static PANORAMAS: OnceLock<[Panorama; 3]> = OnceLock::new();
    PANORAMAS.get_or_init(|| {
        let tour: omnicloud::frames::TourInfo = omnicloud::frames::manifest::parse_manifest(
            std::path::Path::new("tour.json"),
            r#"{"frames": 12, "stations": [{"frame": 3, "scan": 1, "name": "hall", "position": [1, 2, 3]}]}"#,
        )
        .expect("the fixed manifest reads");
        [
            Panorama {
                kind: PanoramaKind::Mono,
                width: 64,
                height: 32,
                frames: frames(1, "png", ImageType::Png),
                video: None,
                stations: Vec::new(),
            },
            Panorama {
                kind: PanoramaKind::Ods,
                width: 64,
                height: 64,
                frames: frames(12, "jpg", ImageType::Jpeg),
                video: None,
                stations: tour.stations,
            },
            Panorama {
                kind: PanoramaKind::Mono,
                width: 64,
                height: 32,
                frames: frames(1, "mp4", ImageType::Mp4),
                video: Some(VideoTrack {
                    frames: 90,
                    fps: 30.0,
                }),
                stations: Vec::new(),
            },
        ]
    })
}

/// A small scan for `serve`'s routes (its map drawn once).
fn scan() -> &'static LiveScan {
    static SCAN: OnceLock<LiveScan> = OnceLock::new();
    SCAN.get_or_init(|| {
        let positions = (0..64)
            .map(|i| Vec3::new((i % 8) as f32, (i / 8) as f32, 0.0))
            .collect();
        let scene = Scene::new(DVec3::new(500.0, 800.0, 10.0), positions, 0.05);
        let options = LiveOptions {
            map_size: 64,
            ..LiveOptions::default()
        };
        LiveScan::new(std::path::Path::new("scan.laz"), scene, options).expect("a scan")
    })
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let method = METHODS[usize::from(pick & 3)];
    let panorama = &panoramas()[usize::from(pick >> 2) % 3];
    let text = String::from_utf8_lossy(rest);
    let (url, range) = text.split_once('\n').unwrap_or((&text, ""));

    let reply = route(method, url, panorama);
    assert!(
        matches!(reply.status, 200 | 400 | 403 | 404 | 405),
        "{}",
        reply.status
    );
    if let Body::File(path) = &reply.body {
        assert!(
            panorama.frames.iter().any(|f| f.path == *path),
            "{url:?} served {}",
            path.display()
        );
    }

    let scan = scan();
    let limits = scan.limits;
    let render = |request: RenderRequest| {
        let inside = (limits.lo.x..=limits.hi.x).contains(&request.xy.x)
            && (limits.lo.y..=limits.hi.y).contains(&request.xy.y);
        assert!(inside && request.ipd.is_finite(), "{request:?}");
        assert!(request.client.len() <= 64, "{request:?}");
        Err(RenderFailure::Superseded)
    };
    let reply = omnicloud::web::serve::routes::route(method, url, scan, &render);
    assert!(
        matches!(
            reply.status,
            200 | 400 | 403 | 404 | 405 | 409 | 422 | 500 | 503
        ),
        "{}",
        reply.status
    );
    let query = url.split_once('?').map_or("", |(_, q)| q);
    if let Ok(request) = RenderRequest::parse(query, &limits) {
        assert!(request.merging.north.factor(0.5).is_finite());
    }

    for len in [0, 1, 1000, u64::MAX] {
        match byte_range(range, len) {
            FileRange::Whole(n) | FileRange::Unsatisfiable(n) => assert_eq!(n, len),
            FileRange::Part { start, end, len: n } => {
                assert_eq!(n, len);
                assert!(
                    start <= end && end < len,
                    "{range:?} of {len}: {start}..={end}"
                );
            }
        }
    }
});
