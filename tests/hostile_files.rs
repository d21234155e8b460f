//! Hostile files: a few bytes whose header asks for absurd work. Each is refused with an error
//! naming the file and the field at fault, in under a second and under 100 MB of memory.
//!
//! - a LAS 1.4 header (and a LAZ one) declaring 10^12 points;
//! - a COPC hierarchy whose page refers to itself;
//! - an E57 file whose XML section, or whose points section, runs past the end of the file;
//! - a PLY declaring 2^40 vertices (binary and ASCII).
//!
//! Memory is the peak of live heap bytes, recorded by a counting global allocator (which also
//! refuses to go past 1 GiB, so a runaway reader aborts the test instead of the machine).

use omnicloud::io::{self, LoadError, LoadOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Live heap bytes, and the most seen since the last [`measure`] began.
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Live bytes past which requests fail (the process then aborts with the size).
const REFUSED: usize = 1 << 30;

fn grow(size: usize) -> bool {
    let live = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    if live > REFUSED {
        LIVE.fetch_sub(size, Ordering::Relaxed);
        return false;
    }
    PEAK.fetch_max(live, Ordering::Relaxed);
    true
}

/// The system allocator, counting live bytes.
struct Counting;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !grow(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !grow(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() && !grow(new_size - layout.size()) {
            return std::ptr::null_mut();
        }
        let out = unsafe { System.realloc(ptr, layout, new_size) };
        if out.is_null() {
            LIVE.fetch_sub(new_size.saturating_sub(layout.size()), Ordering::Relaxed);
        } else if new_size < layout.size() {
            LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        out
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The bounds every refusal must keep.
const TIME_LIMIT: Duration = Duration::from_secs(1);
const MEMORY_LIMIT: usize = 100 << 20;
/// A reader that has not answered by now is taken to hang.
const HANG: Duration = Duration::from_secs(20);

/// One measurement at a time: the counters are process-wide.
static SERIAL: Mutex<()> = Mutex::new(());

/// Runs `f` on a worker thread; returns its result, the time it took and the peak of live
/// heap bytes above those live when it started.
fn measure<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> (T, Duration, usize) {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (send, receive) = std::sync::mpsc::channel();
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let start = Instant::now();
    std::thread::spawn(move || {
        let out = f();
        let _ = send.send((out, start.elapsed()));
    });
    let (out, took) = receive
        .recv_timeout(HANG)
        .unwrap_or_else(|_| panic!("no answer within {HANG:?}: the reader hangs"));
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
    (out, took, peak)
}

/// Opens and loads `path` as `omnicloud render` does; the refusal must name the file and
/// contain every one of `field`, within the time and memory bounds.
fn refused(path: &Path, field: &[&str]) -> LoadError {
    let owned = path.to_path_buf();
    let (result, took, peak) = measure(move || {
        let info = io::read_info(&owned);
        let loaded = io::load_scene(&owned, &LoadOptions::default()).map(|(s, _)| s.len());
        (info.map(|i| i.point_count), loaded)
    });
    let (info, loaded) = result;
    let err = match loaded {
        Ok(n) => panic!("{} loaded {n} points", path.display()),
        Err(e) => e,
    };
    let text = err.to_string();
    println!(
        "{}: refused in {took:?}, peak {:.2} MB (read_info: {info:?}): {text}",
        path.file_name().unwrap().to_string_lossy(),
        peak as f64 / 1e6
    );
    assert_eq!(err.path(), path, "{text}");
    assert!(text.contains(&path.display().to_string()), "{text}");
    for f in field {
        assert!(text.contains(f), "the error does not say {f:?}: {text}");
    }
    assert!(took < TIME_LIMIT, "{text}: took {took:?}");
    assert!(peak < MEMORY_LIMIT, "{text}: peak {peak} bytes");
    err
}

/// Runs the CLI on `args`; it must fail within a few seconds (process start included) and its
/// stderr name the file and `field`.
fn cli_refuses(args: &[&str], file: &Path, field: &str) {
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .unwrap();
    let took = start.elapsed();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("omnicloud {}: {took:?}: {stderr}", args.join(" "));
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains(&file.display().to_string()), "{stderr}");
    assert!(stderr.contains(field), "{stderr}");
    assert!(took < Duration::from_secs(5), "took {took:?}");
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A LAS 1.4 file (point format 0; LAZ when `compressed`) of 100 points.
fn las14(dir: &Path, compressed: bool) -> Vec<u8> {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(0).unwrap();
    builder.point_format.is_compressed = compressed;
    let header = builder.into_header().unwrap();
    let path = dir.join(if compressed {
        "source.laz"
    } else {
        "source.las"
    });
    {
        let mut w = las::Writer::from_path(&path, header).unwrap();
        for i in 0..100 {
            w.write_point(las::Point {
                x: f64::from(i),
                y: f64::from(i % 7),
                z: 1.0,
                ..Default::default()
            })
            .unwrap();
        }
        w.close().unwrap();
    }
    std::fs::read(&path).unwrap()
}

/// Sets a LAS 1.4 header's point count: the legacy 32-bit one to 0 and the 64-bit one to `n`.
fn claim_points(las: &mut [u8], n: u64) {
    las[107..111].copy_from_slice(&0u32.to_le_bytes());
    las[247..255].copy_from_slice(&n.to_le_bytes());
}

#[test]
fn las_header_claiming_a_trillion_points() {
    let dir = tempfile::tempdir().unwrap();
    for (name, compressed) in [("trillion.las", false), ("trillion.laz", true)] {
        let mut bytes = las14(dir.path(), compressed);
        claim_points(&mut bytes, 1_000_000_000_000);
        let path = write(dir.path(), name, &bytes);
        refused(&path, &["1000000000000", "points"]);
    }
    let las = dir.path().join("trillion.las");
    let las = las.to_str().unwrap();
    let out = dir.path().join("out.png");
    cli_refuses(
        &["render", las, "-o", out.to_str().unwrap(), "--width", "64"],
        Path::new(las),
        "1000000000000 points",
    );
    assert!(!out.exists());
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

/// `data/courtyard.copc.laz` with one entry of its root hierarchy page turned into a reference
/// to a child page that is the root page itself: following the pages never ends.
fn copc_pointing_at_itself() -> Vec<u8> {
    let mut bytes = std::fs::read("data/courtyard.copc.laz").unwrap();
    // The COPC info VLR is the first VLR: its 160-byte payload follows the 375-byte header
    // and the 54-byte VLR header; the root page's offset and size are at 40 and 48 in it.
    let info = 375 + 54;
    assert_eq!(&bytes[375 + 2..375 + 6], b"copc");
    let (root, size) = (u64_at(&bytes, info + 40), u64_at(&bytes, info + 48));
    // The second entry of the root page (the first is usually the root node).
    let entry = root as usize + 32;
    bytes[entry + 16..entry + 24].copy_from_slice(&root.to_le_bytes());
    bytes[entry + 24..entry + 28].copy_from_slice(&(size as i32).to_le_bytes());
    bytes[entry + 28..entry + 32].copy_from_slice(&(-1i32).to_le_bytes());
    bytes
}

#[test]
fn copc_hierarchy_page_pointing_at_itself() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "loop.copc.laz", &copc_pointing_at_itself());
    let owned = path.clone();
    let (result, took, peak) = measure(move || io::read_octree(&owned).map(|o| o.nodes.len()));
    let err = result.expect_err("a looping hierarchy is refused");
    let text = err.to_string();
    println!("read_octree: refused in {took:?}, peak {peak} bytes: {text}");
    assert!(matches!(err, LoadError::CorruptCopc { .. }), "{text}");
    assert!(text.contains(&path.display().to_string()), "{text}");
    assert!(
        text.contains("hierarchy") && text.contains("page"),
        "{text}"
    );
    assert!(took < TIME_LIMIT, "took {took:?}");
    assert!(peak < MEMORY_LIMIT, "peak {peak} bytes");
    let out = dir.path().join("out.png");
    cli_refuses(
        &[
            "render",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--width",
            "64",
        ],
        &path,
        "reached twice",
    );
    assert!(!out.exists());
}

/// A small E57 file: one scan of 500 points.
fn e57_file(dir: &Path) -> Vec<u8> {
    use e57::{E57Writer, Record, RecordDataType, RecordName, RecordValue};
    let path = dir.join("source.e57");
    {
        let mut w = E57Writer::from_file(&path, "{hostile}").unwrap();
        let proto = [
            RecordName::CartesianX,
            RecordName::CartesianY,
            RecordName::CartesianZ,
        ]
        .map(|name| Record {
            name,
            data_type: RecordDataType::F64,
        })
        .to_vec();
        let mut pc = w.add_pointcloud("{scan}", proto).unwrap();
        for i in 0..500 {
            let v = f64::from(i);
            pc.add_point(vec![
                RecordValue::Double(v),
                RecordValue::Double(v * 0.5),
                RecordValue::Double(1.0),
            ])
            .unwrap();
        }
        pc.finalize().unwrap();
        w.finalize().unwrap();
    }
    std::fs::read(&path).unwrap()
}

/// CRC-32C (Castagnoli), as E57 pages carry it.
fn crc32c(data: &[u8]) -> u32 {
    !data.iter().fold(!0u32, |mut crc, &b| {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0x82F6_3B78
            } else {
                crc >> 1
            };
        }
        crc
    })
}

/// Writes `value` at physical byte `at` (inside one page's data) and renews that page's CRC.
fn e57_patch(bytes: &mut [u8], at: usize, value: u64) {
    const PAGE: usize = 1024;
    assert!(at % PAGE + 8 <= PAGE - 4, "the field straddles a page");
    bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
    let page = at / PAGE * PAGE;
    let crc = crc32c(&bytes[page..page + PAGE - 4]);
    bytes[page + PAGE - 4..page + PAGE].copy_from_slice(&crc.to_be_bytes());
}

#[test]
fn e57_section_sizes_past_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let good = e57_file(dir.path());
    let len = good.len() as u64;

    // The header's XML length (bytes 32..40): 40 MB, which the e57 crate would allocate.
    let mut xml = good.clone();
    e57_patch(&mut xml, 32, 40 << 20);
    let path = write(dir.path(), "xml_past_end.e57", &xml);
    refused(&path, &["XML section", &(40u64 << 20).to_string()]);

    // The points section's length (8 bytes at 8 into its header, at the scan's fileOffset).
    let text = String::from_utf8_lossy(&good);
    let at = text
        .find("type=\"CompressedVector\" fileOffset=\"")
        .expect("the XML lists the points section");
    let rest = &text[at + "type=\"CompressedVector\" fileOffset=\"".len()..];
    let section: usize = rest[..rest.find('"').unwrap()].parse().unwrap();
    let mut points = good.clone();
    let claimed = (1u64 << 40) & !3;
    e57_patch(&mut points, section + 8, claimed);
    let path = write(dir.path(), "section_past_end.e57", &points);
    let err = refused(&path, &["section", &claimed.to_string(), &len.to_string()]);
    assert!(matches!(err, LoadError::CorruptHeader { .. }), "{err}");
}

/// A PLY header declaring 2^40 vertices over a few real ones.
fn ply(format: &str) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat {format} 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nend_header\n",
        1u64 << 40
    )
    .into_bytes();
    for i in 0..50u8 {
        if format == "ascii" {
            bytes.extend(format!("{i} 1 2\n").bytes());
        } else {
            for v in [f32::from(i), 1.0, 2.0] {
                bytes.extend(v.to_le_bytes());
            }
        }
    }
    bytes
}

#[test]
fn ply_with_two_to_the_forty_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let count = (1u64 << 40).to_string();
    let binary = write(dir.path(), "huge_binary.ply", &ply("binary_little_endian"));
    refused(&binary, &[&count]);
    let ascii = write(dir.path(), "huge_ascii.ply", &ply("ascii"));
    refused(&ascii, &[&count]);
}
