//! `view`'s and `serve`'s servers under load and abuse, in process on loopback, each check in
//! seconds: a slowloris client holds up no one and is cut off; long request lines and large
//! heads are refused 414/431; connections past the limit get 503; a client that disconnects
//! mid-response costs nothing; a storm of render requests is shed (409/503) and leaves no
//! backlog; 20 clients at once get every static answer, quickly. The long versions are
//! `tools/server_load.sh` (docs/RELIABILITY.md).
#![cfg(feature = "web")]

mod http_common;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use http_common::{Reply, get, send};
use omnicloud::web::door::{HEAD_TIME, MAX_CONNECTIONS, MAX_HEADERS, MAX_REQUEST_LINE};
use omnicloud::web::{Panorama, Running, ViewServer};

/// `count` frames of `side` x `side`/2 pixels of noise (PNG barely compresses it) in `dir`.
fn write_frames(dir: &Path, count: u32, side: u32) {
    let mut state = 0x9e37_79b9_u32;
    for k in 0..count {
        let img = image::RgbImage::from_fn(side, side / 2, |_, _| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            image::Rgb([state as u8, (state >> 8) as u8, (state >> 16) as u8])
        });
        img.save(dir.join(format!("frame_{k:06}.png"))).unwrap();
    }
}

/// `view` of a folder of three small frames, and the folder.
fn view() -> (Running, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    write_frames(dir.path(), 3, 64);
    let server = ViewServer::bind("127.0.0.1", 0, Panorama::open(dir.path()).unwrap())
        .unwrap()
        .spawn();
    (server, dir)
}

/// A GET's reply and how long it took.
fn timed_get(addr: SocketAddr, target: &str) -> (Reply, Duration) {
    let started = Instant::now();
    let reply = get(addr, target);
    (reply, started.elapsed())
}

/// The `q`-quantile of `times` (sorted in place).
fn quantile(times: &mut [Duration], q: f64) -> Duration {
    times.sort_unstable();
    times[((times.len() - 1) as f64 * q).round() as usize]
}

/// A raw request head with `headers` (whole lines) and `Host`.
fn head(addr: SocketAddr, target: &str, headers: &str) -> Vec<u8> {
    format!(
        "GET {target} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n{headers}Connection: close\r\n\r\n",
        addr.port()
    )
    .into_bytes()
}

#[test]
fn a_slowloris_client_holds_up_no_one_and_is_cut_off_in_time() {
    let (server, _dir) = view();
    let addr = server.addr();
    // More slow clients than the server has workers, one byte a second each.
    let started = Instant::now();
    let slow: Vec<TcpStream> = (0..8).map(|_| TcpStream::connect(addr).unwrap()).collect();
    let stop = AtomicBool::new(false);
    let mut times = std::thread::scope(|scope| {
        let dripping = scope.spawn(|| {
            let line = head(addr, "/api/info", "");
            for byte in line.iter().take(4) {
                for mut s in &slow {
                    s.write_all(&[*byte]).unwrap();
                }
                for _ in 0..10 {
                    if stop.load(Ordering::SeqCst) {
                        return;
                    }
                    std::thread::sleep(Duration::from_millis(100));
                }
            }
        });
        // Meanwhile the others are answered at once.
        let mut times = Vec::new();
        while started.elapsed() < Duration::from_secs(3) {
            let (reply, took) = timed_get(addr, "/api/info");
            assert_eq!(reply.status, 200, "{}", reply.text());
            times.push(took);
        }
        stop.store(true, Ordering::SeqCst);
        dripping.join().unwrap();
        times
    });
    let worst = quantile(&mut times, 1.0);
    println!(
        "{} answers beside 8 slow clients, median {:?}, worst {worst:?}",
        times.len(),
        quantile(&mut times, 0.5)
    );
    // Measured: median 5 ms, worst 18 to 44 ms, on 2 cores shared with other builds.
    assert!(times.len() > 20, "{} answers in 3 s", times.len());
    assert!(worst < Duration::from_millis(500), "{worst:?}");
    // Each slow client gets 408 once its head is HEAD_TIME late, and its connection closes.
    for mut s in slow {
        s.set_read_timeout(Some(HEAD_TIME + Duration::from_secs(5)))
            .unwrap();
        let mut answer = String::new();
        s.read_to_string(&mut answer).unwrap();
        assert!(answer.starts_with("HTTP/1.1 408 "), "{answer:?}");
    }
    let cut_off = started.elapsed();
    assert!(
        cut_off >= HEAD_TIME && cut_off < HEAD_TIME + Duration::from_secs(2),
        "{cut_off:?}"
    );
}

#[test]
fn long_request_lines_get_414_and_large_heads_431_without_reading_on() {
    let (server, _dir) = view();
    let addr = server.addr();
    // The longest line allowed reaches the routes (a long query of unknown names: 400).
    let query = "a".repeat(MAX_REQUEST_LINE - "GET /api/info? HTTP/1.1".len());
    let longest = send(addr, &head(addr, &format!("/api/info?{query}"), ""));
    assert_eq!(longest.status, 400, "{}", longest.text());
    let too_long = send(addr, &head(addr, &format!("/api/info?{query}a"), ""));
    assert_eq!(too_long.status, 414, "{}", too_long.text());

    let pad = format!("X-Pad: {}\r\n", "b".repeat(1000));
    let large = send(addr, &head(addr, "/api/info", &pad.repeat(17)));
    assert_eq!(large.status, 431, "{}", large.text());
    let many = |n: usize| send(addr, &head(addr, "/api/info", &"X-A: b\r\n".repeat(n)));
    // `head` adds Host and Connection.
    assert_eq!(many(MAX_HEADERS - 2).status, 200);
    assert_eq!(many(MAX_HEADERS - 1).status, 431);

    // A line that never ends: refused once it passes the limit, not read to its end.
    let mut endless = TcpStream::connect(addr).unwrap();
    endless
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    endless
        .set_write_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let chunk = vec![b'a'; 64 * 1024];
    endless.write_all(b"GET /").unwrap();
    let mut sent = 0usize;
    // The server stops reading: writes block once the socket buffers are full.
    while sent < 64 << 20 && endless.write_all(&chunk).is_ok() {
        sent += chunk.len();
    }
    assert!(sent < 64 << 20, "the server read 64 MiB of one line");
    let mut answer = Vec::new();
    let _ = endless.read_to_end(&mut answer);
    assert!(
        answer.starts_with(b"HTTP/1.1 414 "),
        "{:?}",
        String::from_utf8_lossy(&answer)
    );
    assert_eq!(get(addr, "/api/info").status, 200);
}

#[test]
fn connections_past_the_limit_get_503_until_one_closes() {
    let (server, _dir) = view();
    let addr = server.addr();
    let idle: Vec<TcpStream> = (0..MAX_CONNECTIONS)
        .map(|_| TcpStream::connect(addr).unwrap())
        .collect();
    // The accept loop has taken them all once one more is turned away.
    let deadline = Instant::now() + Duration::from_secs(5);
    let turned_away = loop {
        let r = get(addr, "/api/info");
        if r.status == 503 || Instant::now() > deadline {
            break r;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(turned_away.status, 503, "{}", turned_away.text());
    assert_eq!(turned_away.header("retry-after").as_deref(), Some("1"));
    drop(idle);
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let r = get(addr, "/api/info");
        if r.status == 200 {
            break;
        }
        assert!(Instant::now() < deadline, "still {}", r.status);
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_client_that_disconnects_mid_response_costs_nothing() {
    let dir = tempfile::tempdir().unwrap();
    // 1024 x 512 of noise: about 1.5 MB, more than the socket buffers hold.
    write_frames(dir.path(), 1, 1024);
    let frame = std::fs::read(dir.path().join("frame_000000.png")).unwrap();
    let server = ViewServer::bind("127.0.0.1", 0, Panorama::open(dir.path()).unwrap())
        .unwrap()
        .spawn();
    let addr = server.addr();
    // More than the server has workers, each leaving after a few kilobytes.
    for _ in 0..12 {
        let mut s = TcpStream::connect(addr).unwrap();
        s.write_all(&head(addr, "/frames/0", "")).unwrap();
        let mut some = [0u8; 4096];
        s.read_exact(&mut some).unwrap();
        assert!(some.starts_with(b"HTTP/1.1 200 "));
    }
    let (info, took) = timed_get(addr, "/api/info");
    assert_eq!(info.status, 200);
    assert!(took < Duration::from_millis(500), "{took:?}");
    let whole = get(addr, "/frames/0");
    assert_eq!(whole.status, 200);
    assert!(
        whole.body == frame,
        "the frame differs after the disconnects"
    );
}

#[test]
fn twenty_clients_at_once_get_every_static_answer_quickly() {
    let (server, _dir) = view();
    let addr = server.addr();
    let targets = ["/", "/viewer.js", "/api/info", "/frames/0", "/frames/2"];
    let started = Instant::now();
    let mut times: Vec<Duration> = std::thread::scope(|scope| {
        let clients: Vec<_> = (0..20)
            .map(|c| {
                scope.spawn(move || {
                    let mut times = Vec::new();
                    let mut k = c;
                    while started.elapsed() < Duration::from_secs(2) {
                        let target = targets[k % targets.len()];
                        let (reply, took) = timed_get(addr, target);
                        assert_eq!(reply.status, 200, "{target}: {}", reply.text());
                        times.push(took);
                        k += 1;
                    }
                    times
                })
            })
            .collect();
        clients
            .into_iter()
            .flat_map(|c| c.join().unwrap())
            .collect()
    });
    let p99 = quantile(&mut times, 0.99);
    println!(
        "{} answers to 20 clients in 2 s: median {:?}, p99 {p99:?}",
        times.len(),
        quantile(&mut times, 0.5)
    );
    // Measured: about 7500 answers, p99 7 to 10 ms, on 2 cores shared with other builds.
    assert!(times.len() > 1000, "only {} answers", times.len());
    assert!(p99 < Duration::from_millis(100), "p99 {p99:?}");
}

/// `serve` with the ray tracer (no GPU needed) on a small courtyard: a floor and a wall.
#[cfg(feature = "gpu")]
mod serve {
    use super::*;

    use glam::{DVec3, Vec3};
    use omnicloud::Scene;
    use omnicloud::render::{ColorMode, RendererKind};
    use omnicloud::web::serve::{LiveOptions, LiveScan, LiveServer};

    /// `serve` of a 20 m courtyard at panorama `width`, rendering on the CPU.
    fn courtyard(width: u32) -> Running {
        let mut pts = Vec::new();
        for i in 0..=80 {
            let x = i as f32 * 0.25 - 10.0;
            for j in 0..=80 {
                pts.push(Vec3::new(x, j as f32 * 0.25 - 10.0, -1.7));
            }
            for k in 0..=8 {
                pts.push(Vec3::new(x, 10.0, k as f32 * 0.25 - 1.7));
            }
        }
        let scene = Scene::new(DVec3::new(300.0, 700.0, 20.0), pts, 0.15);
        let options = LiveOptions {
            width,
            color: ColorMode::Elevation,
            map_size: 40,
            ..LiveOptions::default()
        };
        let scan = LiveScan::new(Path::new("courtyard.laz"), scene, options).unwrap();
        LiveServer::bind_renderer("127.0.0.1", 0, scan, RendererKind::Raytrace)
            .unwrap()
            .spawn()
    }

    /// `n` render requests at once (`client(k)` names the k-th one's client), their replies
    /// and times.
    fn storm(addr: SocketAddr, n: usize, client: fn(usize) -> String) -> Vec<(Reply, Duration)> {
        std::thread::scope(|scope| {
            let asks: Vec<_> = (0..n)
                .map(|k| {
                    scope.spawn(move || {
                        let target = format!("/api/render?seq={}&client={}", k + 1, client(k));
                        timed_get(addr, &target)
                    })
                })
                .collect();
            asks.into_iter().map(|a| a.join().unwrap()).collect()
        })
    }

    #[test]
    fn a_storm_of_renders_is_shed_and_leaves_no_backlog() {
        let server = courtyard(768);
        let addr = server.addr();
        let (one, alone) = timed_get(addr, "/api/render");
        assert_eq!(one.status, 200, "{}", one.text());
        println!("one render alone: {alone:?}");

        // Forty clients at once, each its own: a few wait, the rest are told to come back.
        let many = storm(addr, 40, |k| format!("storm{k}"));
        let count = |status| many.iter().filter(|(r, _)| r.status == status).count();
        let (ok, busy) = (count(200), count(503));
        println!("40 clients: {ok} rendered, {busy} shed");
        assert_eq!(ok + busy, 40, "only 200 and 503 expected");
        assert!(busy >= 40 - 2 * 4, "{busy} of 40 shed");
        for (reply, took) in many.iter().filter(|(r, _)| r.status == 503) {
            assert_eq!(reply.header("retry-after").as_deref(), Some("1"));
            assert!(*took < alone * 3 + Duration::from_millis(500), "{took:?}");
        }

        // One client forty times at once: its newest request replaces its waiting one.
        let one_client = storm(addr, 40, |_| "page".into());
        let superseded = one_client.iter().filter(|(r, _)| r.status == 409).count();
        assert!(
            one_client
                .iter()
                .all(|(r, _)| matches!(r.status, 200 | 409 | 503)),
            "{:?}",
            one_client.iter().map(|(r, _)| r.status).collect::<Vec<_>>()
        );
        let rendered = one_client.iter().filter(|(r, _)| r.status == 200).count();
        println!("one client 40 times: {rendered} rendered, {superseded} superseded");
        // Some of the forty may be shed (503) rather than superseded, by how the threads
        // interleave; what matters is that few render and many replace each other.
        assert!(rendered <= 2 * 4, "{rendered} of 40 rendered");
        assert!(superseded >= 3, "{superseded} of 40 superseded");

        // Nothing queued stays behind: the next render takes about as long as one alone, and
        // the page is answered at once.
        let (scan, took) = timed_get(addr, "/api/scan");
        assert_eq!(scan.status, 200);
        assert!(took < Duration::from_millis(500), "{took:?}");
        let (after, took) = timed_get(addr, "/api/render?client=after");
        assert_eq!(after.status, 200, "{}", after.text());
        assert!(
            took < alone * 3 + Duration::from_millis(500),
            "{took:?} after the storms"
        );
    }

    #[test]
    fn the_page_is_answered_during_a_storm_and_a_gone_client_costs_nothing() {
        let server = courtyard(768);
        let addr = server.addr();
        let (_, alone) = timed_get(addr, "/api/render");
        // Clients that ask for a render and leave before it is done.
        for k in 0..12 {
            let mut s = TcpStream::connect(addr).unwrap();
            s.write_all(&head(addr, &format!("/api/render?client=gone{k}"), ""))
                .unwrap();
        }
        let stop = AtomicBool::new(false);
        let mut times = std::thread::scope(|scope| {
            for k in 0..6 {
                let stop = &stop;
                scope.spawn(move || {
                    let mut seq = 0;
                    while !stop.load(Ordering::SeqCst) {
                        seq += 1;
                        let r = get(addr, &format!("/api/render?client=busy{k}&seq={seq}"));
                        assert!(matches!(r.status, 200 | 409 | 503), "{}", r.status);
                    }
                });
            }
            let mut times = Vec::new();
            for target in ["/", "/viewer.js", "/serve.js", "/api/scan", "/map.png"].repeat(10) {
                let (reply, took) = timed_get(addr, target);
                assert_eq!(reply.status, 200, "{target}");
                times.push(took);
            }
            stop.store(true, Ordering::SeqCst);
            times
        });
        let worst = quantile(&mut times, 1.0);
        println!("static answers during a render storm: worst {worst:?} (a render: {alone:?})");
        assert!(worst < Duration::from_millis(500), "{worst:?}");
        let (after, took) = timed_get(addr, "/api/render?client=after");
        assert_eq!(after.status, 200, "{}", after.text());
        assert!(took < alone * 3 + Duration::from_millis(500), "{took:?}");
    }
}
