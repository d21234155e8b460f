//! Streaming a multi-million-point file keeps memory proportional to the chunk size.
//! (Its own test binary, one test: nothing else allocates while memory is measured.)

use omnicloud::io;

/// A field of /proc/self/status in bytes (Linux).
fn status_bytes(field: &str) -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status
        .lines()
        .find(|l| l.starts_with(field))
        .unwrap_or_else(|| panic!("{field} not in /proc/self/status"));
    let kib: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    kib * 1024
}

#[test]
fn streaming_three_million_points_stays_within_a_few_chunks_of_memory() {
    const N: u64 = 3_000_000;
    const CHUNK: usize = 65_536;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.las");
    {
        let mut builder = las::Builder::from((1, 2));
        builder.point_format = las::point::Format::new(2).unwrap();
        builder.transforms = las::Vector {
            x: las::Transform {
                scale: 0.001,
                offset: 637_000.0,
            },
            y: las::Transform {
                scale: 0.001,
                offset: 851_000.0,
            },
            z: las::Transform {
                scale: 0.001,
                offset: 0.0,
            },
        };
        let header = builder.into_header().unwrap();
        let mut writer = las::Writer::from_path(&path, header).unwrap();
        for i in 0..N {
            writer
                .write_point(las::Point {
                    x: 637_000.0 + (i % 1000) as f64,
                    y: 851_000.0 + (i / 1000) as f64 * 0.01,
                    z: (i % 7) as f64,
                    intensity: (i % 65_536) as u16,
                    color: Some(las::Color::new(((i % 256) * 256) as u16, 0, 65_535)),
                    ..Default::default()
                })
                .unwrap();
        }
        writer.close().unwrap();
    }
    let file_len = std::fs::metadata(&path).unwrap().len();
    // What the whole file would take as chunks: f64 positions, colour, intensity, class.
    let in_memory = N * (24 + 3 + 2 + 1);

    // Start the peak from here (clear_refs "5" resets VmHWM); fall back to VmRSS sampling.
    let reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
    let baseline = status_bytes("VmRSS:");
    let mut peak_rss = baseline;
    let (mut count, mut sum_x, mut blue_ok) = (0u64, 0f64, true);
    let reader = io::open(&path).unwrap();
    assert_eq!(reader.info().point_count, N);
    for chunk in reader.chunks(CHUNK) {
        let chunk = chunk.unwrap();
        count += chunk.len() as u64;
        sum_x += chunk.positions.iter().map(|p| p.x - 637_000.0).sum::<f64>();
        blue_ok &= chunk.rgb.as_ref().unwrap().iter().all(|c| c[2] == 255);
        peak_rss = peak_rss.max(status_bytes("VmRSS:"));
    }
    let peak = if reset {
        status_bytes("VmHWM:").max(peak_rss)
    } else {
        peak_rss
    };
    let growth = peak.saturating_sub(baseline);

    assert_eq!(count, N);
    assert!(blue_ok, "full-range colour was not scaled to 255");
    let expected_sum = (N / 1000) as f64 * (0..1000).map(f64::from).sum::<f64>();
    assert!((sum_x - expected_sum).abs() < 1e-3 * N as f64);
    eprintln!(
        "file {:.1} MB, whole file in memory {:.1} MB, peak growth while streaming {:.1} MB (VmHWM reset: {reset})",
        file_len as f64 / 1e6,
        in_memory as f64 / 1e6,
        growth as f64 / 1e6
    );
    assert!(
        growth < in_memory / 8,
        "streaming grew memory by {growth} bytes; the whole file is {in_memory} bytes in memory"
    );
}
