//! Load on a running `omnicloud view` or `omnicloud serve`: many clients at once for a while,
//! each request on a fresh connection, plus a few slowloris clients that send a byte a
//! second; reports requests, statuses, errors and latency quantiles per class of route, and
//! the server's resident memory (VmRSS) at the start, middle and end.
//!
//! ```sh
//! cargo run --example server_load -- frames DIR            # noise frames for `view DIR`
//! cargo run --example server_load -- view 127.0.0.1:8360 --pid PID --clients 50 --seconds 60
//! cargo run --example server_load -- serve 127.0.0.1:8360 --pid PID --render-every 10
//! ```
//! `tools/server_load.sh` starts the server, runs this and stops the server.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Args, Parser, Subcommand};

#[derive(Parser)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Writes `--count` frames of noise (`--width` x width/2) for `omnicloud view DIR`.
    Frames {
        dir: PathBuf,
        #[arg(long, default_value_t = 4)]
        count: u32,
        #[arg(long, default_value_t = 1024)]
        width: u32,
    },
    /// Loads `omnicloud view`: the page, its script, the info and the frames.
    View(Load),
    /// Loads `omnicloud serve`: the page, scripts, scan, map and renders.
    Serve(Load),
}

#[derive(Args)]
struct Load {
    /// The server's address.
    addr: SocketAddr,
    /// The server's process id, for its resident memory.
    #[arg(long)]
    pid: Option<u32>,
    /// Clients asking at once, each its next request as soon as the last is answered.
    #[arg(long, default_value_t = 50)]
    clients: usize,
    /// How long, seconds.
    #[arg(long, default_value_t = 60)]
    seconds: u64,
    /// Slowloris clients, each sending its head a byte a second (and again once cut off).
    #[arg(long, default_value_t = 4)]
    slowloris: usize,
    /// `view`: the frames the folder holds.
    #[arg(long, default_value_t = 4)]
    frames: usize,
    /// `serve`: every Nth request of a client is a render (0: none).
    #[arg(long, default_value_t = 10)]
    render_every: usize,
}

/// One answered (or failed) request.
struct Sample {
    class: &'static str,
    status: Option<u16>,
    took: Duration,
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Frames { dir, count, width } => write_frames(&dir, count, width),
        Command::View(load) => run(&load, false),
        Command::Serve(load) => run(&load, true),
    }
}

fn write_frames(dir: &std::path::Path, count: u32, width: u32) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut state = 0x2545_f491_u32;
    for k in 0..count {
        let img = image::RgbImage::from_fn(width, width / 2, |_, _| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            image::Rgb([state as u8, (state >> 8) as u8, (state >> 16) as u8])
        });
        img.save(dir.join(format!("frame_{k:06}.png")))?;
    }
    Ok(())
}

/// The `n`-th request of client `c`: its class and target.
fn request(load: &Load, serve: bool, c: usize, n: usize) -> (&'static str, String) {
    if serve {
        if load.render_every > 0 && n % load.render_every == load.render_every - 1 {
            return (
                "render",
                format!("/api/render?client=load{c}&seq={}", n + 1),
            );
        }
        let pages = ["/", "/viewer.js", "/serve.js", "/live.js", "/api/scan"];
        match (c + n) % (pages.len() + 1) {
            k if k < pages.len() => ("static", pages[k].to_owned()),
            _ => ("map", "/map.png".to_owned()),
        }
    } else {
        let pages = ["/", "/viewer.js", "/api/info"];
        match (c + n) % (pages.len() + 1) {
            k if k < pages.len() => ("static", pages[k].to_owned()),
            _ => ("frame", format!("/frames/{}", (c + n) % load.frames.max(1))),
        }
    }
}

/// GETs `target` on a fresh connection and reads the reply whole: its status.
fn get(addr: SocketAddr, target: &str) -> std::io::Result<u16> {
    let mut s = TcpStream::connect(addr)?;
    s.set_read_timeout(Some(Duration::from_secs(30)))?;
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nConnection: close\r\n\r\n",
        addr.port()
    )?;
    let mut reply = Vec::new();
    s.read_to_end(&mut reply)?;
    let status = reply
        .split(|&b| b == b' ')
        .nth(1)
        .and_then(|w| std::str::from_utf8(w).ok()?.parse().ok());
    status.ok_or_else(|| std::io::Error::other("no status line"))
}

/// The server's resident memory, KiB.
fn rss_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// One slowloris client: a head a byte a second, again each time the server cuts it off;
/// returns the statuses it was cut off with.
fn slowloris(addr: SocketAddr, stop: &AtomicBool) -> Vec<String> {
    let head = format!(
        "GET /api/scan HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Slow: {}\r\n\r\n",
        addr.port(),
        "s".repeat(200)
    );
    let mut endings = Vec::new();
    while !stop.load(Ordering::SeqCst) {
        let Ok(mut s) = TcpStream::connect(addr) else {
            endings.push("no connection".into());
            std::thread::sleep(Duration::from_secs(1));
            continue;
        };
        for byte in head.bytes() {
            if stop.load(Ordering::SeqCst) || s.write_all(&[byte]).is_err() {
                break;
            }
            std::thread::sleep(Duration::from_secs(1));
        }
        let _ = s.set_read_timeout(Some(Duration::from_secs(1)));
        let mut answer = String::new();
        let _ = s.read_to_string(&mut answer);
        if !stop.load(Ordering::SeqCst) {
            endings.push(answer.lines().next().unwrap_or("closed").to_owned());
        }
    }
    endings
}

fn run(load: &Load, serve: bool) -> anyhow::Result<()> {
    let started = Instant::now();
    let until = started + Duration::from_secs(load.seconds);
    let samples = Mutex::new(Vec::<Sample>::new());
    let rss = Mutex::new(Vec::<(f64, u64)>::new());
    let stop = AtomicBool::new(false);
    let sample_rss = |rss: &Mutex<Vec<(f64, u64)>>| {
        if let Some(kib) = load.pid.and_then(rss_kib) {
            rss.lock()
                .unwrap()
                .push((started.elapsed().as_secs_f64(), kib));
        }
    };
    sample_rss(&rss);
    let endings = std::thread::scope(|scope| {
        let slow: Vec<_> = (0..load.slowloris)
            .map(|_| scope.spawn(|| slowloris(load.addr, &stop)))
            .collect();
        scope.spawn(|| {
            while Instant::now() < until {
                std::thread::sleep(Duration::from_secs(1));
                sample_rss(&rss);
            }
        });
        for c in 0..load.clients {
            let samples = &samples;
            scope.spawn(move || {
                let mut mine = Vec::new();
                let mut n = 0;
                while Instant::now() < until {
                    let (class, target) = request(load, serve, c, n);
                    let asked = Instant::now();
                    let status = get(load.addr, &target).ok();
                    mine.push(Sample {
                        class,
                        status,
                        took: asked.elapsed(),
                    });
                    n += 1;
                }
                samples.lock().unwrap().extend(mine);
            });
        }
        std::thread::sleep(until.saturating_duration_since(Instant::now()));
        stop.store(true, Ordering::SeqCst);
        slow.into_iter()
            .flat_map(|s| s.join().unwrap())
            .collect::<Vec<_>>()
    });
    sample_rss(&rss);
    report(
        load,
        serve,
        &samples.into_inner().unwrap(),
        &rss.into_inner().unwrap(),
        &endings,
    );
    Ok(())
}

fn report(load: &Load, serve: bool, samples: &[Sample], rss: &[(f64, u64)], endings: &[String]) {
    println!(
        "{} at {}: {} clients for {} s, {} slowloris",
        if serve { "serve" } else { "view" },
        load.addr,
        load.clients,
        load.seconds,
        load.slowloris
    );
    println!("| class | requests | statuses | errors | p50 ms | p95 ms | p99 ms | max ms |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut classes: BTreeMap<&str, Vec<&Sample>> = BTreeMap::new();
    for s in samples {
        classes.entry(s.class).or_default().push(s);
    }
    for (class, list) in &classes {
        let mut statuses: BTreeMap<u16, usize> = BTreeMap::new();
        let mut errors = 0;
        for s in list {
            match s.status {
                Some(code) => *statuses.entry(code).or_default() += 1,
                None => errors += 1,
            }
        }
        // A render may be shed (409 superseded, 503 busy); anything else but 200 is an error.
        let shed_ok = |code: u16| code == 200 || (*class == "render" && matches!(code, 409 | 503));
        errors += statuses
            .iter()
            .filter(|(code, _)| !shed_ok(**code))
            .map(|(_, n)| n)
            .sum::<usize>();
        let mut times: Vec<Duration> = list.iter().map(|s| s.took).collect();
        times.sort_unstable();
        let q = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize].as_secs_f64() * 1e3;
        let statuses: Vec<String> = statuses.iter().map(|(c, n)| format!("{c}: {n}")).collect();
        println!(
            "| {class} | {} | {} | {errors} | {:.1} | {:.1} | {:.1} | {:.1} |",
            list.len(),
            statuses.join(", "),
            q(0.5),
            q(0.95),
            q(0.99),
            q(1.0)
        );
    }
    if let (Some(first), Some(last)) = (rss.first(), rss.last()) {
        let middle = rss[rss.len() / 2];
        let most = rss.iter().map(|r| r.1).max().unwrap_or(0);
        println!(
            "server RSS: start {:.1} MiB, middle ({:.0} s) {:.1} MiB, end {:.1} MiB, most {:.1} MiB",
            first.1 as f64 / 1024.0,
            middle.0,
            middle.1 as f64 / 1024.0,
            last.1 as f64 / 1024.0,
            most as f64 / 1024.0
        );
    }
    let mut cut: BTreeMap<&str, usize> = BTreeMap::new();
    for e in endings {
        *cut.entry(e.as_str()).or_default() += 1;
    }
    println!("slowloris clients cut off with: {cut:?}");
}
