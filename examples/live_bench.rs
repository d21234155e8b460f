//! The live stream (`serve`'s `/api/live`) under walking clients: frames a second per client
//! and the time from a pose sent to its frame received (p50, p95), with the server's resident
//! memory at the start and the end; or (`--encoders`) the two JPEG encoders on one pair.
//!
//! `cargo run --release --example live_bench -- [FILE] [--width 1440] [--clients 1,4]
//! [--seconds 20] [--live-scale 1|auto] [--rss-every SECS] [--encoders]` (FILE defaults to the sample,
//! data/autzen_trim.laz). Each client sends a pose every 33 ms (as a page does while a key is
//! held), walking 1.4 m/s back and forth along a line through the start camera, and reads
//! frames as they come. The server runs in this process on a free port with the rasterizer.

use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Parser;
use indicatif::ProgressBar;
use omnicloud::prepare::{LengthScale, PrepareOptions, Units, prepare};
use omnicloud::web::serve::live::jpeg::{encode_jpeg, encode_jpeg_image_crate};
use omnicloud::web::serve::live::{LiveScale, split_frame};
use omnicloud::web::serve::{LiveOptions, LiveScan, LiveServer, StreamOptions};
use tungstenite::Message;

#[derive(Parser)]
struct Args {
    /// The scan.
    #[arg(default_value = "data/autzen_trim.laz")]
    file: PathBuf,
    /// Panorama width per eye.
    #[arg(long, default_value = "1440")]
    width: u32,
    /// Client counts to run, one run each.
    #[arg(long, value_delimiter = ',', default_value = "1,4")]
    clients: Vec<usize>,
    /// Seconds each run walks.
    #[arg(long, default_value = "20")]
    seconds: f64,
    /// `1`: every frame at --width; `auto`: narrower while slow.
    #[arg(long, default_value = "1")]
    live_scale: LiveScale,
    /// Also samples the resident memory every this many seconds while the clients walk, and
    /// prints the samples with their maximum (a soak: is memory flat?).
    #[arg(long)]
    rss_every: Option<f64>,
    /// Time the two JPEG encoders on one rendered pair instead.
    #[arg(long)]
    encoders: bool,
}

/// Resident memory of this process (VmRSS), MiB.
fn rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// What one client measured.
struct Walk {
    frames: usize,
    latencies_ms: Vec<f64>,
    render_ms: f64,
    encode_ms: f64,
}

/// Walks for `seconds`: a pose every 33 ms along X through `start`, `step` file units a pose.
fn walk(
    addr: SocketAddr,
    start: [f64; 3],
    half: f64,
    step: f64,
    seconds: f64,
    offset: f64,
) -> Walk {
    let stream = TcpStream::connect(addr).unwrap();
    let url = format!("ws://127.0.0.1:{}/api/live", addr.port());
    let mut ws = tungstenite::client(url.as_str(), stream).unwrap().0;
    // Reads wait briefly so that poses go out on time.
    ws.get_ref()
        .set_read_timeout(Some(Duration::from_millis(2)))
        .unwrap();
    let started = Instant::now();
    let mut sent: Vec<Instant> = vec![started];
    let mut next_pose = started;
    let mut walk = Walk {
        frames: 0,
        latencies_ms: Vec::new(),
        render_ms: 0.0,
        encode_ms: 0.0,
    };
    while started.elapsed().as_secs_f64() < seconds {
        let now = Instant::now();
        if now >= next_pose {
            let seq = sent.len() as u64;
            // Back and forth over [-half, half] around the start.
            let t = (seq as f64 * step + offset).rem_euclid(4.0 * half);
            let dx = if t < 2.0 * half {
                t - half
            } else {
                3.0 * half - t
            };
            let pose = format!(
                r#"{{"seq": {seq}, "x": {}, "y": {}, "yaw": 90}}"#,
                start[0] + dx,
                start[1]
            );
            ws.send(Message::text(pose)).unwrap();
            sent.push(now);
            next_pose += Duration::from_millis(33);
        }
        match ws.read() {
            Ok(Message::Binary(bytes)) => {
                let (header, _) = split_frame(&bytes).unwrap();
                if !header.still {
                    walk.frames += 1;
                    let at = sent[header.seq as usize];
                    walk.latencies_ms.push(at.elapsed().as_secs_f64() * 1e3);
                    walk.render_ms += header.render_ms;
                    walk.encode_ms += header.encode_ms;
                }
            }
            Ok(_) => {}
            Err(tungstenite::Error::Io(e)) if e.kind() == std::io::ErrorKind::WouldBlock => {}
            Err(e) => panic!("the stream failed: {e}"),
        }
    }
    walk
}

/// Resident memory (seconds since the start, MiB) every `every` seconds while `walking`.
fn sample_rss(every: f64, walking: &std::sync::atomic::AtomicBool) -> Vec<(f64, f64)> {
    let started = Instant::now();
    let mut samples = vec![(0.0, rss_mib())];
    let mut next = every;
    while walking.load(std::sync::atomic::Ordering::SeqCst) {
        let t = started.elapsed().as_secs_f64();
        if t >= next {
            samples.push((t, rss_mib()));
            next += every;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    samples.push((started.elapsed().as_secs_f64(), rss_mib()));
    samples
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let info = omnicloud::io::read_info(&args.file)?;
    let scale = LengthScale::for_info(&info, Units::Metres, omnicloud::io::Up::Z);
    let prepared = prepare(
        &args.file,
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )?;
    let options = LiveOptions {
        width: args.width,
        height: scale.height(1.7),
        per_metre: scale.length(1.0),
        metres_per_unit: scale.metres_per_unit,
        map_size: 256,
        ..LiveOptions::default()
    };
    let scan = LiveScan::new(&args.file, prepared.scene, options)?;
    if args.encoders {
        return time_encoders(scan, args.width);
    }
    let server = LiveServer::bind("127.0.0.1", 0, scan)?.with_stream(StreamOptions {
        scale: args.live_scale,
        ..StreamOptions::default()
    });
    println!(
        "{}: ODS {} per eye on {}, --live-scale {:?}",
        args.file.display(),
        args.width,
        server.renderer().adapter(),
        args.live_scale
    );
    let start = server.scan().info.camera;
    let lo = server.scan().limits.lo;
    let hi = server.scan().limits.hi;
    // Half the walk: a fifth of the scan's width, within it.
    let half = ((hi.x - lo.x) / 5.0)
        .min(start[0] - lo.x)
        .min(hi.x - start[0]);
    let step = scale.length(1.4) * 0.033;
    let addr = server.addr();
    let running = server.spawn();
    for &clients in &args.clients {
        let rss_before = rss_mib();
        let walking = &std::sync::atomic::AtomicBool::new(true);
        let (walks, samples): (Vec<Walk>, Vec<(f64, f64)>) = std::thread::scope(|s| {
            let handles: Vec<_> = (0..clients)
                .map(|k| {
                    let offset = half * k as f64;
                    s.spawn(move || walk(addr, start, half, step, args.seconds, offset))
                })
                .collect();
            let sampler = args
                .rss_every
                .map(|every| s.spawn(move || sample_rss(every, walking)));
            let walks = handles.into_iter().map(|h| h.join().unwrap()).collect();
            walking.store(false, std::sync::atomic::Ordering::SeqCst);
            let samples = sampler.map_or(Vec::new(), |h| h.join().unwrap());
            (walks, samples)
        });
        if !samples.is_empty() {
            let line: Vec<String> = samples
                .iter()
                .map(|(t, mib)| format!("{t:.0} s {mib:.0}"))
                .collect();
            let max = samples.iter().map(|s| s.1).fold(f64::NAN, f64::max);
            println!("RSS samples (MiB): {}; max {max:.0} MiB", line.join(", "));
        }
        let mut all: Vec<f64> = walks.iter().flat_map(|w| w.latencies_ms.clone()).collect();
        all.sort_by(f64::total_cmp);
        let rates: Vec<String> = walks
            .iter()
            .map(|w| format!("{:.1}", w.frames as f64 / args.seconds))
            .collect();
        let frames: usize = walks.iter().map(|w| w.frames).sum::<usize>().max(1);
        let render: f64 = walks.iter().map(|w| w.render_ms).sum::<f64>() / frames as f64;
        let encode: f64 = walks.iter().map(|w| w.encode_ms).sum::<f64>() / frames as f64;
        println!(
            "{clients} client(s), {} s: frames/s per client {}; pose→frame p50 {:.0} ms, p95 {:.0} ms; mean render {render:.0} ms, encode {encode:.0} ms; RSS {:.0} → {:.0} MiB",
            args.seconds,
            rates.join(", "),
            percentile(&all, 0.5),
            percentile(&all, 0.95),
            rss_before,
            rss_mib()
        );
    }
    drop(running);
    Ok(())
}

/// Renders the start camera's pair once and times each encoder on it at quality 80.
fn time_encoders(scan: LiveScan, width: u32) -> anyhow::Result<()> {
    use omnicloud::web::serve::{RenderRequest, RenderThread};
    let scan = std::sync::Arc::new(scan);
    let thread = RenderThread::start(scan.clone(), omnicloud::render::RendererKind::Raster)?;
    let request = RenderRequest::default_at(&scan.limits);
    let raw = thread
        .queue()
        .submit(request, width)
        .recv()?
        .map_err(anyhow::Error::msg)?;
    let frame = &raw.frame;
    println!(
        "one {}x{} top-bottom pair, quality 80, best of 5:",
        frame.width, frame.height
    );
    type Encoder =
        fn(&omnicloud::Frame, u8) -> Result<Vec<u8>, omnicloud::web::serve::live::jpeg::JpegError>;
    let encoders: [(&str, Encoder); 2] = [
        ("jpeg-encoder (SIMD)", encode_jpeg),
        ("image crate", encode_jpeg_image_crate),
    ];
    for (name, encode) in encoders {
        let mut best = f64::INFINITY;
        let mut bytes = 0;
        for _ in 0..5 {
            let t = Instant::now();
            bytes = encode(frame, 80)?.len();
            best = best.min(t.elapsed().as_secs_f64() * 1e3);
        }
        println!("  {name}: {best:.1} ms, {} KiB", bytes / 1024);
    }
    Ok(())
}
