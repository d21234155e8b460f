//! `omnicloud view tour.mp4`: the viewer opens an MP4 as mono or top-bottom from its `st3d`
//! box, and serves it at `/video` in the byte ranges a video element asks for.
#![cfg(all(feature = "video", feature = "web"))]

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::time::Duration;

use indicatif::ProgressBar;
use omnicloud::frames::StereoChoice;
use omnicloud::video::{VideoOptions, encode_folder};
use omnicloud::web::{Panorama, PanoramaKind, ViewServer};

/// Encodes four `width` x `height` frames into `dir/v.mp4` with `stereo`.
fn video(dir: &Path, width: u32, height: u32, stereo: StereoChoice) -> std::path::PathBuf {
    for k in 0..4u8 {
        image::RgbImage::from_pixel(width, height, image::Rgb([60 * k, 100, 50]))
            .save(dir.join(format!("frame_{k:06}.png")))
            .unwrap();
    }
    let out = dir.join("v.mp4");
    let options = VideoOptions {
        stereo,
        ..VideoOptions::default()
    };
    encode_folder(dir, &out, &options, &ProgressBar::hidden()).unwrap();
    out
}

/// One raw request; returns (status, head, body).
fn get(addr: SocketAddr, target: &str, extra: &str) -> (u16, String, Vec<u8>) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let host = format!("127.0.0.1:{}", addr.port());
    write!(
        stream,
        "GET {target} HTTP/1.1\r\nHost: {host}\r\n{extra}Connection: close\r\n\r\n"
    )
    .unwrap();
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap();
    let split = bytes.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&bytes[..split]).into_owned();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, head, bytes[split + 4..].to_vec())
}

#[test]
fn the_stereo_layout_comes_from_st3d_not_the_shape() {
    let dir = tempfile::tempdir().unwrap();
    let ods = Panorama::open(&video(dir.path(), 64, 64, StereoChoice::Auto)).unwrap();
    assert_eq!(
        (ods.kind, ods.width, ods.height),
        (PanoramaKind::Ods, 64, 64)
    );
    assert_eq!(ods.frame_count(), 4);
    assert_eq!(ods.video.unwrap().fps, 30.0);

    let dir = tempfile::tempdir().unwrap();
    let mono = Panorama::open(&video(dir.path(), 64, 32, StereoChoice::Mono)).unwrap();
    assert_eq!(mono.kind, PanoramaKind::Mono);

    let fake = dir.path().join("fake.mp4");
    std::fs::write(&fake, b"\0\0\0\x10ftypisom\0\0\0\0").unwrap();
    let e = Panorama::open(&fake).unwrap_err().to_string();
    assert!(
        e.contains("cannot show") && e.contains("fake.mp4") && e.contains("no moov box"),
        "{e}"
    );
}

#[test]
fn the_video_is_served_whole_and_in_byte_ranges() {
    let dir = tempfile::tempdir().unwrap();
    let file = video(dir.path(), 64, 64, StereoChoice::Auto);
    let bytes = std::fs::read(&file).unwrap();
    let server = ViewServer::bind("127.0.0.1", 0, Panorama::open(&file).unwrap())
        .unwrap()
        .spawn();
    let addr = server.addr();

    let (status, head, body) = get(addr, "/video", "");
    assert_eq!(status, 200, "{head}");
    assert!(head.contains("Content-Type: video/mp4"), "{head}");
    assert!(head.contains("Accept-Ranges: bytes"), "{head}");
    assert_eq!(body, bytes);

    let (status, head, body) = get(addr, "/video", "Range: bytes=8-107\r\n");
    assert_eq!(status, 206, "{head}");
    assert!(
        head.contains(&format!("Content-Range: bytes 8-107/{}", bytes.len())),
        "{head}"
    );
    assert_eq!(body, &bytes[8..108]);

    let (status, _, body) = get(addr, "/video", "Range: bytes=-10\r\n");
    assert_eq!(status, 206);
    assert_eq!(body, &bytes[bytes.len() - 10..]);

    let past = format!("Range: bytes={}-\r\n", bytes.len());
    let (status, head, _) = get(addr, "/video", &past);
    assert_eq!(status, 416, "{head}");
    assert!(
        head.contains(&format!("Content-Range: bytes */{}", bytes.len())),
        "{head}"
    );

    // The server keeps serving; the info names the video.
    let (status, _, body) = get(addr, "/api/info", "");
    assert_eq!(status, 200);
    assert_eq!(
        String::from_utf8_lossy(&body),
        r#"{"kind":"ods","width":64,"height":64,"frames":4,"video":{"frames":4,"fps":30.0}}"#
    );
    assert_eq!(get(addr, "/frames/0", "").0, 404);
}
