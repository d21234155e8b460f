//! `omnicloud serve`'s live stream (`/api/live`) on the sample scan, driven by a Rust
//! WebSocket client as docs/LIVE.md describes the protocol: poses get frames carrying their
//! `seq` from the camera they asked for (the same picture `/api/render` gives there); a burst
//! of poses renders the newest, not a queue, then one still pair; malformed messages close
//! only their own connection with a reason; a client that stops reading is dropped while
//! another keeps receiving. Needs a GPU adapter (lavapipe will do): without one the tests skip
//! loudly, and fail under `OMNICLOUD_REQUIRE_GPU=1`.
#![cfg(all(feature = "web", feature = "gpu"))]

mod http_common;
mod serve_common;

use std::net::{SocketAddr, TcpStream};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use image::GenericImageView;
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::prepare::{PrepareOptions, prepare};
use omnicloud::web::Running;
use omnicloud::web::serve::StreamOptions;
use omnicloud::web::serve::live::{FrameHeader, LiveScale, split_frame};
use serve_common::{UNDER_TREES, sample, start_live_streaming};
use tungstenite::protocol::frame::coding::CloseCode;
use tungstenite::{Message, WebSocket};

/// Panorama width of the served frames.
const WIDTH: u32 = 256;

fn scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| {
        prepare(
            &sample(),
            &PrepareOptions::default(),
            &ProgressBar::hidden(),
        )
        .unwrap()
        .scene
    })
}

/// Every frame at the served width, as `--live-scale 1` serves them.
fn full_width() -> StreamOptions {
    StreamOptions {
        scale: LiveScale::Full,
        ..StreamOptions::default()
    }
}

fn start(stream: StreamOptions) -> Option<Running> {
    start_live_streaming(scene().clone(), WIDTH, stream)
}

type Client = WebSocket<TcpStream>;

/// Opens `/api/live` as a page of the server's own origin would.
fn connect(addr: SocketAddr) -> Client {
    let stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    let url = format!("ws://127.0.0.1:{}/api/live", addr.port());
    tungstenite::client(url.as_str(), stream).unwrap().0
}

fn pose(client: &mut Client, seq: u64, x: f64, y: f64, extra: &str) {
    let text = format!(r#"{{"seq": {seq}, "x": {x}, "y": {y}, "yaw": 90{extra}}}"#);
    client.send(Message::text(text)).unwrap();
}

/// The next frame (header and decoded RGB image); panics on anything else.
fn frame(client: &mut Client) -> (FrameHeader, image::RgbImage) {
    loop {
        match client.read().unwrap() {
            Message::Binary(bytes) => {
                let (header, jpeg) = split_frame(&bytes).unwrap();
                let image = image::load_from_memory(jpeg).unwrap().to_rgb8();
                return (header, image);
            }
            Message::Text(t) => panic!("a text message instead of a frame: {t}"),
            _ => {}
        }
    }
}

/// The server's start camera, file coordinates.
fn start_camera(addr: SocketAddr) -> [f64; 3] {
    let scan: serde_json::Value =
        serde_json::from_slice(&http_common::get(addr, "/api/scan").body).unwrap();
    serde_json::from_value(scan["camera"].clone()).unwrap()
}

/// Mean absolute difference per channel between a JPEG frame and a PNG render.
fn mean_difference(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&p, &q)| u64::from(p.abs_diff(q)))
        .sum();
    sum as f64 / a.as_raw().len() as f64
}

#[test]
fn poses_get_frames_of_their_camera_and_a_burst_renders_only_the_newest() {
    let Some(server) = start(full_width()) else {
        return;
    };
    let addr = server.addr();
    let [cx, cy, _] = start_camera(addr);
    let mut client = connect(addr);

    // Walking east in 3-foot steps, one pose per frame: each frame shows its pose's camera.
    for k in 1..=4u64 {
        let x = cx + 3.0 * k as f64;
        pose(&mut client, k, x, cy, "");
        let (h, image) = frame(&mut client);
        assert_eq!((h.seq, h.camera[0], h.camera[1]), (k, x, cy), "{h:?}");
        assert_eq!(
            (h.width, h.height, h.format.as_str()),
            (WIDTH, WIDTH, "jpeg")
        );
        assert_eq!((h.yaw, h.still, h.quality), (90.0, false, 80));
        assert_eq!(image.dimensions(), (WIDTH, WIDTH));
        assert!(h.render_ms > 0.0 && h.encode_ms > 0.0, "{h:?}");
        if k == 4 {
            // The same picture `/api/render` renders there (top-bottom, left eye on top), but
            // for JPEG's loss: measured 1.44 per channel at quality 80.
            let png = http_common::get(addr, &format!("/api/render?x={x}&y={cy}"));
            assert_eq!(png.status, 200);
            let png = image::load_from_memory(&png.body).unwrap().to_rgb8();
            let d = mean_difference(&image, &png);
            assert!(
                d < 2.5,
                "the frame differs from the render by {d} per channel"
            );
            // The eyes differ (the lower half is the right eye's, not a copy; identical halves
            // encode alike, 8-pixel blocks aligned): measured 1.91 per channel.
            let (top, bottom) = (
                image.view(0, 0, WIDTH, WIDTH / 2),
                image.view(0, WIDTH / 2, WIDTH, WIDTH / 2),
            );
            let eyes = mean_difference(&top.to_image(), &bottom.to_image());
            assert!(eyes > 1.0, "the eyes differ by only {eyes}");
        }
    }
    // At rest: one still pair of the last pose, at the highest quality.
    let (still, _) = frame(&mut client);
    assert_eq!((still.seq, still.still, still.quality), (4, true, 95));

    // A burst of 20 poses sent at once: the server renders the newest it has each time, so
    // far fewer than 20 frames arrive, in order, ending on the last pose.
    for k in 5..=24u64 {
        pose(&mut client, k, cx - 0.5 * k as f64, cy + 1.0, "");
    }
    let mut seqs = Vec::new();
    while seqs.last() != Some(&24) {
        let (h, _) = frame(&mut client);
        assert!(!h.still, "{h:?}");
        assert_eq!(h.camera[0], cx - 0.5 * h.seq as f64);
        seqs.push(h.seq);
    }
    assert!(seqs.windows(2).all(|w| w[0] < w[1]), "{seqs:?}");
    assert!(
        seqs.len() <= 4,
        "a queue of stale poses was rendered: {seqs:?}"
    );
    let (still, _) = frame(&mut client);
    assert_eq!((still.seq, still.still), (24, true));

    // A pose with its own height stands exactly there.
    pose(&mut client, 25, cx, cy, r#", "z": 500.5"#);
    let (h, _) = frame(&mut client);
    assert_eq!(h.camera, [cx, cy, 500.5]);
    // One with a height above the ground (metres; the sample counts feet) stands that high
    // instead of the served height (1.7 file units here, `LiveOptions`' default).
    let (x, y) = UNDER_TREES;
    pose(&mut client, 26, x, y, "");
    let low = frame(&mut client).0.camera[2];
    pose(&mut client, 27, x, y, r#", "height": 4.7"#);
    let high = frame(&mut client).0.camera[2];
    assert!(
        ((high - low) - (4.7 / 0.3048 - 1.7)).abs() < 1e-6,
        "{low} → {high}"
    );
}

/// Sends `message` on a fresh connection and returns the close frame's code and reason.
fn refused(addr: SocketAddr, message: Message) -> (CloseCode, String) {
    let mut client = connect(addr);
    client.send(message).unwrap();
    loop {
        match client.read() {
            Ok(Message::Close(Some(frame))) => return (frame.code, frame.reason.to_string()),
            Ok(Message::Close(None)) => panic!("closed without a reason"),
            Ok(_) => {}
            Err(e) => panic!("no close frame: {e}"),
        }
    }
}

#[test]
fn malformed_messages_close_only_their_connection_with_a_reason() {
    let Some(server) = start(full_width()) else {
        return;
    };
    let addr = server.addr();
    let [cx, cy, _] = start_camera(addr);
    let mut good = connect(addr);
    pose(&mut good, 1, cx, cy, "");
    assert_eq!(frame(&mut good).0.seq, 1);

    let text = |s: &str| Message::text(s.to_owned());
    let huge = format!(
        r#"{{"seq": 1, "x": {cx}, "y": {cy}, "yaw": 0, "pad": "{}"}}"#,
        "x".repeat(10_000)
    );
    let cases = [
        (
            text("{\"seq\": 1, \"x\":"),
            CloseCode::Invalid,
            "not a pose",
        ),
        (
            text(&format!(r#"{{"seq": 2, "x": NaN, "y": {cy}, "yaw": 0}}"#)),
            CloseCode::Invalid,
            "not a pose",
        ),
        (
            text(&format!(r#"{{"seq": 3, "x": {cx}, "y": 1e9, "yaw": 0}}"#)),
            CloseCode::Policy,
            "y=1000000000: the camera must stand within the scan's bounds",
        ),
        (text(&huge), CloseCode::Size, "a pose is at most 4096 bytes"),
        (
            Message::binary(vec![1u8, 2, 3]),
            CloseCode::Unsupported,
            "binary messages are not poses",
        ),
    ];
    for (k, (message, code, reason)) in cases.into_iter().enumerate() {
        let (got, why) = refused(addr, message);
        assert_eq!(got, code, "case {k}: {why}");
        assert!(why.contains(reason), "case {k}: {why}");
        // The other client is served on.
        let seq = 10 + k as u64;
        pose(&mut good, seq, cx + k as f64, cy, "");
        let h = loop {
            let (h, _) = frame(&mut good);
            if !h.still {
                break h;
            }
        };
        assert_eq!(h.seq, seq);
    }
}

#[test]
fn a_client_that_stops_reading_is_dropped_and_another_keeps_receiving() {
    let stream = StreamOptions {
        write_timeout: Duration::from_secs(1),
        ..full_width()
    };
    let Some(server) = start(stream) else {
        return;
    };
    let addr = server.addr();
    let [cx, cy, _] = start_camera(addr);

    // The stalled client walks but never reads: its frames fill the socket's buffers until
    // a send waits past the write timeout, and the server drops it.
    let stalled = std::thread::spawn(move || {
        let mut client = connect(addr);
        let started = Instant::now();
        for seq in 1.. {
            let text = format!(
                r#"{{"seq": {seq}, "x": {}, "y": {cy}, "yaw": 0}}"#,
                cx + (seq % 50) as f64
            );
            if client.send(Message::text(text)).is_err() {
                return Some((seq, started.elapsed()));
            }
            if started.elapsed() > Duration::from_secs(240) {
                return None;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        None
    });
    let mut reader = connect(addr);
    let mut received = 0u64;
    let mut after_drop = 0;
    for seq in 1.. {
        pose(&mut reader, seq, cx, cy - (seq % 40) as f64, "");
        let (h, _) = loop {
            let f = frame(&mut reader);
            if f.0.seq == seq {
                break f;
            }
        };
        assert_eq!(h.seq, seq);
        received += 1;
        if stalled.is_finished() {
            after_drop += 1;
            if after_drop == 3 {
                break;
            }
        }
    }
    let (poses, took) = stalled
        .join()
        .unwrap()
        .expect("the stalled client was never dropped");
    eprintln!(
        "the stalled client was dropped after {poses} poses, {took:?}; the reader got {received} frames"
    );
    assert!(received > 3);
}
