//! The viewer's HTTP server, in process on a free port: pages, info and frames are served;
//! traversal attempts, bad queries, foreign Host headers and broken requests get errors and
//! no file; the server keeps serving after each.
#![cfg(feature = "web")]

mod http_common;

use std::io::Write;
use std::net::{SocketAddr, TcpStream};
use std::path::Path;

use http_common::{get, send};
use omnicloud::web::{Panorama, Running, ViewServer};

/// Frames of 64x32 pixels, one flat colour each, `frame_000000.png`... in `dir`.
fn write_frames(dir: &Path, count: u8) {
    for k in 0..count {
        let img = image::RgbImage::from_pixel(64, 32, image::Rgb([k * 40, 100, 200]));
        img.save(dir.join(format!("frame_{k:06}.png"))).unwrap();
    }
}

fn serve(path: &Path) -> Running {
    ViewServer::bind("127.0.0.1", 0, Panorama::open(path).unwrap())
        .unwrap()
        .spawn()
}

fn assert_still_serving(addr: SocketAddr) {
    let r = get(addr, "/api/info");
    assert_eq!(r.status, 200, "{}", r.text());
}

#[test]
fn the_page_its_script_the_info_and_each_frame_are_served() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 3);
    let server = serve(dir.path());
    let addr = server.addr();

    let page = get(addr, "/");
    assert_eq!(page.status, 200);
    assert!(
        page.header("content-type")
            .unwrap()
            .starts_with("text/html")
    );
    assert!(page.text().contains(r#"<script src="/viewer.js">"#));
    let script = get(addr, "/viewer.js");
    assert_eq!(script.status, 200);
    assert!(
        script
            .header("content-type")
            .unwrap()
            .starts_with("text/javascript")
    );
    assert!(script.text().contains("immersive-vr"));

    let info = get(addr, "/api/info");
    assert_eq!(info.header("content-type").unwrap(), "application/json");
    let json: serde_json::Value = serde_json::from_slice(&info.body).unwrap();
    assert_eq!(
        json,
        serde_json::json!({"kind": "mono", "width": 64, "height": 32, "frames": 3})
    );

    for k in 0..3 {
        let frame = get(addr, &format!("/frames/{k}"));
        assert_eq!(frame.status, 200);
        assert_eq!(frame.header("content-type").unwrap(), "image/png");
        let on_disk = std::fs::read(dir.path().join(format!("frame_{k:06}.png"))).unwrap();
        assert_eq!(frame.body, on_disk, "frame {k}");
    }
    let past_end = get(addr, "/frames/3");
    assert_eq!(past_end.status, 404);
    assert!(
        past_end.text().contains("numbered 0 to 2"),
        "{}",
        past_end.text()
    );

    let head = send(
        addr,
        b"HEAD /frames/0 HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n",
    );
    assert_eq!(head.status, 200);
    assert!(head.body.is_empty());
}

#[test]
fn a_square_image_is_an_ods_pair_and_a_view_link_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("pair.png");
    image::RgbImage::new(64, 64).save(&file).unwrap();
    let server = serve(&file);
    let json: serde_json::Value =
        serde_json::from_slice(&get(server.addr(), "/api/info").body).unwrap();
    assert_eq!(json["kind"], "ods");
    assert_eq!(json["frames"], 1);
    let linked = get(
        server.addr(),
        "/?yaw=30&pitch=-10&fov=75&mode=anaglyph&frame=0",
    );
    assert_eq!(linked.status, 200, "{}", linked.text());
}

#[test]
fn traversal_attempts_get_403_or_404_and_never_a_file() {
    let root = tempfile::tempdir().unwrap();
    let secret = root.path().join("secret.txt");
    std::fs::write(&secret, "SECRET-CONTENT-7f3a").unwrap();
    let tour = root.path().join("tour");
    std::fs::create_dir(&tour).unwrap();
    write_frames(&tour, 2);
    let server = serve(&tour);
    let addr = server.addr();

    let abs = secret.to_str().unwrap().to_owned();
    let frame0 = tour.join("frame_000000.png");
    let targets = [
        "/../../etc/passwd".to_owned(),
        "/../secret.txt".to_owned(),
        "/frames/../../secret.txt".to_owned(),
        "/frames/../../../../etc/passwd".to_owned(),
        "/%2e%2e/%2e%2e/etc/passwd".to_owned(),
        "/%2E%2E/secret.txt".to_owned(),
        "/..%2fsecret.txt".to_owned(),
        "/frames/..%2f..%2fsecret.txt".to_owned(),
        "/frames/%2e%2e%2f%2e%2e%2fsecret.txt".to_owned(),
        "/frames/..%5c..%5csecret.txt".to_owned(),
        "/%252e%252e/secret.txt".to_owned(),
        "/etc/passwd".to_owned(),
        abs.clone(),
        format!("/{abs}"),
        format!("file://{abs}"),
        frame0.to_str().unwrap().to_owned(),
        "/frame_000000.png".to_owned(),
        "/frames/0/../../secret.txt".to_owned(),
        "/frames/0%00".to_owned(),
    ];
    for target in &targets {
        let r = get(addr, target);
        assert!(
            r.status == 403 || r.status == 404,
            "{target}: status {}",
            r.status
        );
        assert!(
            !r.text().contains("SECRET-CONTENT"),
            "{target} leaked the file"
        );
        assert!(!r.body.starts_with(b"\x89PNG"), "{target} served a frame");
        assert!(!r.text().contains("root:"), "{target} served /etc/passwd");
    }
    assert_eq!(get(addr, "/../secret.txt").status, 403);
    assert_eq!(get(addr, "/%2e%2e/secret.txt").status, 403);
    assert_eq!(get(addr, "/etc/passwd").status, 404);
    assert_still_serving(addr);
}

#[test]
fn bad_queries_get_400_with_a_message_and_serving_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 2);
    let server = serve(dir.path());
    let addr = server.addr();
    let cases = [
        ("/?yaw=east", "yaw=\"east\""),
        ("/?pitch=120", "pitch=\"120\""),
        ("/?fov=0", "fov=\"0\""),
        ("/?frame=2", "from 0 to 1"),
        ("/?mode=anaglyph", "this panorama is mono"),
        ("/?zoom=3", "unknown query parameter \"zoom\""),
        ("/api/info?verbose=1", "takes none"),
        ("/frames/0?size=small", "takes none"),
    ];
    for (target, message) in cases {
        let r = get(addr, target);
        assert_eq!(r.status, 400, "{target}");
        assert!(r.text().contains(message), "{target}: {}", r.text());
        assert_still_serving(addr);
    }
}

#[test]
fn broken_requests_other_methods_and_foreign_hosts_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 1);
    let server = serve(dir.path());
    let addr = server.addr();

    let post = send(
        addr,
        b"POST /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
    );
    assert_eq!(post.status, 405);

    // A page elsewhere that rebinds its name to 127.0.0.1 sends that name as Host.
    let foreign = send(
        addr,
        b"GET /frames/0 HTTP/1.1\r\nHost: evil.example:8360\r\nConnection: close\r\n\r\n",
    );
    assert_eq!(foreign.status, 403);
    assert!(!foreign.body.starts_with(b"\x89PNG"));

    // Garbage, and a connection that closes mid-request: no reply needed, no harm done.
    let mut garbage = TcpStream::connect(addr).unwrap();
    garbage
        .write_all(b"\x00\x01NOT HTTP AT ALL\r\n\r\n")
        .unwrap();
    drop(garbage);
    let mut half = TcpStream::connect(addr).unwrap();
    half.write_all(b"GET /api/in").unwrap();
    drop(half);
    assert_still_serving(addr);
}

#[test]
fn a_frame_deleted_while_serving_gets_500_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 2);
    let server = serve(dir.path());
    std::fs::remove_file(dir.path().join("frame_000001.png")).unwrap();
    let r = get(server.addr(), "/frames/1");
    assert_eq!(r.status, 500);
    assert!(r.text().contains("frame_000001.png"), "{}", r.text());
    assert_eq!(get(server.addr(), "/frames/0").status, 200);
}

#[test]
fn a_busy_port_and_a_missing_file_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 1);
    let server = serve(dir.path());
    let taken = server.addr().port();
    let e = ViewServer::bind("127.0.0.1", taken, Panorama::open(dir.path()).unwrap())
        .err()
        .expect("the port is taken")
        .to_string();
    assert!(
        e.contains(&format!("cannot listen on 127.0.0.1:{taken}")),
        "{e}"
    );
    let e = Panorama::open(&dir.path().join("nope.png"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nope.png"), "{e}");
}

/// `omnicloud view` itself: prints the address (and, bound to every interface, the warning),
/// serves it, and stops on Ctrl-C (SIGINT).
#[cfg(all(unix, feature = "cli"))]
#[test]
fn the_command_prints_its_address_serves_and_stops_on_ctrl_c() {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 2);
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    command
        .args(["view", "--host", "0.0.0.0", "--port", "0"])
        .arg(dir.path());
    let server = http_common::ServerProcess::start(command);
    let (lines, addr) = (&server.before, server.addr);
    assert!(lines[0].contains("mono 64x32, 2 frame(s)"), "{lines:?}");
    assert!(addr.ip().is_loopback(), "{addr}");
    let json: serde_json::Value = serde_json::from_slice(&get(addr, "/api/info").body).unwrap();
    assert_eq!(json["frames"], 2);

    let out = server.interrupt();
    let rest = String::from_utf8_lossy(&out.stdout);
    assert!(rest.contains("omnicloud view: stopped"), "{rest}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning: listening on 0.0.0.0:")
            && stderr.contains("everyone on the network can see the served files"),
        "{stderr}"
    );
}
