//! Mutation fuzzing of the point-cloud readers: truncated, bit-flipped and garbage-header
//! variants of every LAS/LAZ file of laspy's test data, of generated PLY files (ascii,
//! binary LE/BE) and of a real E57 file.
//!
//! For every variant, `open` + streaming all chunks + `load_scene` must return an error naming
//! the file or a valid scene; never panic, never hang (each input runs on a worker thread with
//! a deadline) and never ask for absurd memory (a capped global allocator records the largest
//! single request; inputs are below 1 MB, so no request may reach [`LARGEST_ALLOWED`]).
//!
//! `PROPTEST_CASES` scales the random parts (proptest default: 256 cases per property).

mod data_common;

use data_common::{LASPY_FILES, laspy};
use omnicloud::io::{self, LoadError, LoadOptions};
use proptest::prelude::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::Path;
use std::time::Duration;

/// Any single allocation above this, caused by inputs under 1 MB, is a bug (a header count
/// trusted for a `Vec::with_capacity`). The largest legitimate one is a 65,536-point chunk.
const LARGEST_ALLOWED: usize = 64 << 20;
/// Requests above this are refused outright (the process aborts with the size) instead of
/// letting the machine swap.
const REFUSED: usize = 1 << 30;

thread_local! {
    /// Largest request made on this thread (each input is read on its own thread).
    static LARGEST: Cell<usize> = const { Cell::new(0) };
    /// Inputs run by [`exercise`] on this (test) thread.
    static EXERCISED: Cell<usize> = const { Cell::new(0) };
}

/// Runs `body`, then prints how many inputs it ran (`cargo test -- --nocapture` shows it).
fn counted(test: &str, body: impl FnOnce()) {
    let before = EXERCISED.with(Cell::get);
    body();
    let ran = EXERCISED.with(Cell::get) - before;
    println!("{test}: {ran} inputs, no panic, no allocation above {LARGEST_ALLOWED} bytes");
}

/// Proptest settings: a fixed seed so CI runs the same cases every time
/// (`FUZZ_SEED=<u64>` picks others), `PROPTEST_CASES` cases (default 256).
fn config() -> ProptestConfig {
    let seed = std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x6f6d_6e69_636c_6f75);
    ProptestConfig {
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        ..ProptestConfig::default()
    }
}

/// Runs a property through proptest with [`config`], counting its inputs.
fn property<S: Strategy>(test: &str, strategy: S, check: impl Fn(S::Value)) {
    counted(test, || {
        let mut runner = proptest::test_runner::TestRunner::new(config());
        runner
            .run(&strategy, |value| {
                check(value);
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{test}: {e}"));
    });
}

fn note(size: usize) {
    // `try_with`: the slot is gone while the thread itself is being torn down.
    let _ = LARGEST.try_with(|l| l.set(l.get().max(size)));
}

/// The system allocator, recording the largest request per thread.
struct Capped;

unsafe impl GlobalAlloc for Capped {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        if layout.size() > REFUSED {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        if layout.size() > REFUSED {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        if new_size > REFUSED {
            return std::ptr::null_mut();
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Capped = Capped;

/// Longest time one input may take (open + chunks + load_scene), generous for a loaded CI
/// machine: the largest input (autzen_trim.laz, 110,000 points) loads twice in ~0.2 s.
const DEADLINE: Duration = Duration::from_secs(30);

/// Every LAS/LAZ file of laspy's test data: (name, bytes), by name.
fn las_files() -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = LASPY_FILES
        .iter()
        .map(|name| (name.to_string(), std::fs::read(laspy(name)).unwrap()))
        .collect();
    files.sort();
    files
}

/// The three PLY encodings.
#[derive(Debug, Clone, Copy)]
enum Ply {
    Ascii,
    Le,
    Be,
}

/// A small PLY with a list element before the vertices (so readers must skip it), float
/// positions, uchar colour, a radius and a trailing list property on the vertex.
fn generated_ply(kind: Ply) -> Vec<u8> {
    let n = 40;
    let format = match kind {
        Ply::Ascii => "ascii",
        Ply::Le => "binary_little_endian",
        Ply::Be => "binary_big_endian",
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment fuzz seed\nelement face 2\n\
         property list uchar int vertex_indices\nelement vertex {n}\n\
         property float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         property float radius\nproperty list uchar ushort tags\nend_header\n"
    )
    .into_bytes();
    let vertex = |i: u32| {
        let f = i as f32;
        (
            [f * 0.5, (f * 0.3).sin() * 4.0, f * 0.01],
            [i as u8, 255 - i as u8, 7],
            0.05f32,
            [i as u16, 3],
        )
    };
    match kind {
        Ply::Ascii => {
            out.extend_from_slice(b"3 0 1 2\n3 2 1 0\n");
            for i in 0..n {
                let (p, c, r, t) = vertex(i);
                out.extend_from_slice(
                    format!(
                        "{} {} {} {} {} {} {} 2 {} {}\n",
                        p[0], p[1], p[2], c[0], c[1], c[2], r, t[0], t[1]
                    )
                    .as_bytes(),
                );
            }
        }
        Ply::Le | Ply::Be => {
            let le = matches!(kind, Ply::Le);
            let u32b = |v: u32| if le { v.to_le_bytes() } else { v.to_be_bytes() };
            let f32b = |v: f32| if le { v.to_le_bytes() } else { v.to_be_bytes() };
            let u16b = |v: u16| if le { v.to_le_bytes() } else { v.to_be_bytes() };
            for face in [[0u32, 1, 2], [2, 1, 0]] {
                out.push(3);
                for v in face {
                    out.extend_from_slice(&u32b(v));
                }
            }
            for i in 0..n {
                let (p, c, r, t) = vertex(i);
                for v in p {
                    out.extend_from_slice(&f32b(v));
                }
                out.extend_from_slice(&c);
                out.extend_from_slice(&f32b(r));
                out.push(2);
                for v in t {
                    out.extend_from_slice(&u16b(v));
                }
            }
        }
    }
    out
}

/// Runs the three entry points on `bytes` saved as `name`; every outcome must be an error that
/// names the file or a valid scene.
fn exercise(dir: &Path, name: &str, bytes: &[u8]) {
    EXERCISED.with(|n| n.set(n.get() + 1));
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    let worker_path = path.clone();
    let (tx, rx) = std::sync::mpsc::channel();
    let worker = std::thread::spawn(move || {
        let result = std::panic::catch_unwind(|| read_everything(&worker_path));
        let _ = tx.send(result.map(|()| LARGEST.with(Cell::get)));
    });
    match rx.recv_timeout(DEADLINE) {
        Ok(Ok(largest)) => {
            if largest > LARGEST_ALLOWED {
                save_crash(name, bytes);
                panic!("{name}: an allocation of {largest} bytes was requested");
            }
        }
        Ok(Err(panic)) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            save_crash(name, bytes);
            panic!("{name}: reading panicked: {msg}");
        }
        Err(_) => {
            save_crash(name, bytes);
            panic!("{name}: reading took longer than {DEADLINE:?}");
        }
    }
    let _ = worker.join();
}

/// Keeps a failing input for a regression test (under target/, not committed automatically).
fn save_crash(name: &str, bytes: &[u8]) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-crashes");
    let _ = std::fs::create_dir_all(&dir);
    let file = dir.join(format!("{:016x}-{name}", fxhash(bytes)));
    let _ = std::fs::write(&file, bytes);
    eprintln!("failing input saved to {}", file.display());
}

fn fxhash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf29ce484222325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
    })
}

fn check_error(path: &Path, e: &LoadError) {
    assert_eq!(e.path(), path, "error names another file: {e}");
    let text = e.to_string();
    assert!(
        text.contains(&*path.file_name().unwrap().to_string_lossy()),
        "error does not name the file: {text}"
    );
}

fn read_everything(path: &Path) {
    if let Err(e) = io::read_info(path) {
        check_error(path, &e);
    }
    match io::open(path) {
        Err(e) => check_error(path, &e),
        Ok(reader) => {
            let declared = reader.info().point_count;
            let mut total = 0u64;
            for chunk in reader.chunks(4096) {
                match chunk {
                    Ok(c) => {
                        let n = c.len();
                        assert!(n > 0 && n <= 65_536, "chunk of {n} points");
                        for attr in [
                            c.rgb.as_ref().map(Vec::len),
                            c.intensity.as_ref().map(Vec::len),
                            c.classification.as_ref().map(Vec::len),
                            c.radius.as_ref().map(Vec::len),
                        ]
                        .into_iter()
                        .flatten()
                        {
                            assert_eq!(attr, n, "attribute length differs from positions");
                        }
                        total += n as u64;
                    }
                    Err(e) => {
                        check_error(path, &e);
                        break;
                    }
                }
            }
            assert!(
                total <= declared,
                "{total} points read of {declared} declared"
            );
        }
    }
    match io::load_scene(path, &LoadOptions::default()) {
        Err(e) => check_error(path, &e),
        Ok((scene, report)) => {
            let n = scene.len();
            assert!(n > 0);
            assert_eq!(report.points_kept, n as u64);
            assert!(
                scene.positions.iter().all(|p| p.is_finite()),
                "a loaded position is not finite"
            );
            assert!(scene.origin.is_finite());
            for attr in [
                scene.attributes.rgb.as_ref().map(Vec::len),
                scene.attributes.intensity.as_ref().map(Vec::len),
                scene.attributes.classification.as_ref().map(Vec::len),
            ]
            .into_iter()
            .flatten()
            {
                assert_eq!(attr, n);
            }
        }
    }
}

fn tempdir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn extension(name: &str) -> &str {
    name.rsplit('.').next().unwrap_or("las")
}

/// Cut points: every byte of the header and VLRs (step 3), then spread over the points.
fn cut_points(len: usize, header_end: usize) -> Vec<usize> {
    let header_end = header_end.min(len);
    let mut cuts: Vec<usize> = (0..header_end).step_by(3).collect();
    let spread = 40usize;
    cuts.extend((0..spread).map(|k| header_end + (len - header_end) * k / spread));
    cuts.push(len.saturating_sub(1));
    cuts.dedup();
    cuts
}

fn las_point_offset(bytes: &[u8]) -> usize {
    u32::from_le_bytes(bytes[96..100].try_into().unwrap()) as usize
}

#[test]
fn truncated_las_and_laz_files_never_panic() {
    counted(
        "truncated_las_and_laz_files_never_panic",
        truncated_las_and_laz,
    );
}

fn truncated_las_and_laz() {
    let dir = tempdir();
    for (name, bytes) in las_files() {
        let header_end = las_point_offset(&bytes) + 64;
        for cut in cut_points(bytes.len(), header_end) {
            exercise(
                dir.path(),
                &format!("cut{cut}.{}", extension(&name)),
                &bytes[..cut],
            );
        }
    }
}

#[test]
fn truncated_ply_files_never_panic() {
    counted("truncated_ply_files_never_panic", truncated_ply);
}

fn truncated_ply() {
    let dir = tempdir();
    for kind in [Ply::Ascii, Ply::Le, Ply::Be] {
        let bytes = generated_ply(kind);
        let header_end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        // Every byte of the header, every other byte of the body.
        let cuts = (0..header_end).chain((header_end..bytes.len()).step_by(2));
        for cut in cuts {
            exercise(dir.path(), &format!("cut{cut}-{kind:?}.ply"), &bytes[..cut]);
        }
    }
}

/// Every laspy LAS/LAZ file with each size field of its header and VLRs made too large (one
/// at a time): the header size, the offset to the point data, the VLR count, each VLR's
/// length, the EVLR start and count, the record length and the point counts. A field that
/// points past the end of the file must give an error.
#[test]
fn oversized_header_fields_of_every_las_file_give_errors() {
    counted(
        "oversized_header_fields_of_every_las_file_give_errors",
        || {
            let dir = tempdir();
            for (name, original) in las_files() {
                let len = original.len() as u64;
                let mut fields: Vec<(usize, usize)> = LAS_FIELDS
                    .iter()
                    .filter(|(what, ..)| !what.contains("scale") && !what.contains(" x"))
                    .map(|&(_, at, width)| (at, width))
                    .collect();
                fields.extend(vlr_fields(&original));
                for (at, width) in fields {
                    let max = if width == 8 {
                        u64::MAX
                    } else {
                        (1u64 << (8 * width)) - 1
                    };
                    for value in [len, len + 1, max / 2 + 1, max] {
                        let mut bytes = original.clone();
                        put(&mut bytes, at, width, value.min(max));
                        if bytes == original {
                            continue;
                        }
                        let file = format!("big{at}.{}", extension(&name));
                        exercise(dir.path(), &file, &bytes);
                        let past_end = matches!(at, 94 | 96) && value.min(max) >= len;
                        if past_end {
                            let path = dir.path().join(&file);
                            let e = io::load_scene(&path, &LoadOptions::default())
                                .map(|_| ())
                                .expect_err(&format!("{name}: byte {at} = {value} loaded"));
                            check_error(&path, &e);
                        }
                    }
                }
            }
        },
    );
}

/// Every laspy LAS/LAZ file, one byte inverted at a time: every byte of the LAS header, of
/// each VLR's header, of the LASzip VLR and of the first 64 bytes of point data (chunk table
/// offset, first chunk), and every 23rd byte of the other VLR payloads (projection text).
/// Files above 100 kB (each variant reads up to 110,000 points) take every 23rd of those.
#[test]
fn header_bytes_of_every_las_file_inverted() {
    counted("header_bytes_of_every_las_file_inverted", || {
        let dir = tempdir();
        for (name, original) in las_files() {
            let step = if original.len() <= 100_000 { 1 } else { 23 };
            for at in decision_bytes(&original).into_iter().step_by(step) {
                let mut bytes = original.clone();
                bytes[at] = !bytes[at];
                exercise(dir.path(), &format!("inv{at}.{}", extension(&name)), &bytes);
            }
        }
    });
}

/// Offsets of the bytes that parsing decisions read (see
/// [`header_bytes_of_every_las_file_inverted`]), in order.
fn decision_bytes(bytes: &[u8]) -> Vec<usize> {
    let header_size = u16::from_le_bytes([bytes[94], bytes[95]]) as usize;
    let count = u32::from_le_bytes(bytes[100..104].try_into().unwrap()) as usize;
    let point_data = las_point_offset(bytes);
    let mut offsets: Vec<usize> = (0..header_size).collect();
    let mut at = header_size;
    for _ in 0..count {
        if at + 54 > point_data {
            break;
        }
        let len = u16::from_le_bytes([bytes[at + 20], bytes[at + 21]]) as usize;
        let payload = (at + 54..at + 54 + len).filter(|&i| i < point_data);
        offsets.extend(at..at + 54);
        if &bytes[at + 2..at + 16] == b"laszip encoded" {
            offsets.extend(payload);
        } else {
            offsets.extend(payload.step_by(23));
        }
        at += 54 + len;
    }
    offsets.extend(point_data..(point_data + 64).min(bytes.len()));
    offsets
}

/// Values that break assumptions: zero, one, all-ones, sign bits, just past small limits.
fn nasty(width: usize) -> impl Strategy<Value = u64> {
    let max = if width == 8 {
        u64::MAX
    } else {
        (1u64 << (8 * width)) - 1
    };
    prop_oneof![
        Just(0u64),
        Just(1),
        Just(max),
        Just(max / 2),
        Just(max / 2 + 1),
        Just(max - 1),
        0..300u64,
        0..=max,
    ]
}

/// LAS header fields worth corrupting: (name, offset, width in bytes).
const LAS_FIELDS: &[(&str, usize, usize)] = &[
    ("header size", 94, 2),
    ("offset to point data", 96, 4),
    ("number of VLRs", 100, 4),
    ("point format", 104, 1),
    ("point record length", 105, 2),
    ("legacy point count", 107, 4),
    ("legacy points by return", 111, 4),
    ("version minor", 25, 1),
    ("x scale", 131, 8),
    ("x offset", 155, 8),
    ("max x", 179, 8),
    ("start of waveform", 227, 8),
    ("start of first EVLR", 235, 8),
    ("number of EVLRs", 243, 4),
    ("point count (1.4)", 247, 8),
];

fn put(bytes: &mut [u8], at: usize, width: usize, value: u64) {
    if at + width <= bytes.len() {
        bytes[at..at + width].copy_from_slice(&value.to_le_bytes()[..width]);
    }
}

/// Offsets of each VLR's `record_length_after_header` field and of the LASzip VLR's payload.
fn vlr_fields(bytes: &[u8]) -> Vec<(usize, usize)> {
    let header_size = u16::from_le_bytes([bytes[94], bytes[95]]) as usize;
    let count = u32::from_le_bytes(bytes[100..104].try_into().unwrap()) as usize;
    let mut at = header_size;
    let mut fields = Vec::new();
    for _ in 0..count {
        if at + 54 > bytes.len() {
            break;
        }
        let len = u16::from_le_bytes([bytes[at + 20], bytes[at + 21]]) as usize;
        fields.push((at + 20, 2));
        // LASzip VLR payload: compressor, coder, versions, options, chunk size, counts,
        // item count and item records: every u16/u32 in its first 34 bytes.
        if &bytes[at + 2..at + 16] == b"laszip encoded" {
            for off in (0..34).step_by(2) {
                fields.push((at + 54 + off, 2));
                fields.push((at + 54 + off, 4));
            }
        }
        at += 54 + len;
    }
    fields
}

#[test]
fn las_header_fields_with_nasty_values_never_panic() {
    let strategy = (
        0usize..7,
        0usize..LAS_FIELDS.len() + 8,
        any::<prop::sample::Index>(),
        prop_oneof![nasty(1), nasty(2), nasty(4), nasty(8)],
        proptest::option::of((0usize..LAS_FIELDS.len(), nasty(4))),
    );
    let files = las_files();
    property(
        "las_header_fields_with_nasty_values_never_panic",
        strategy,
        |(file, field, vlr_field, value, second)| {
            let (name, original) = &files[file % files.len()];
            let mut bytes = original.clone();
            let (at, width) = if field < LAS_FIELDS.len() {
                (LAS_FIELDS[field].1, LAS_FIELDS[field].2)
            } else {
                let fields = vlr_fields(&bytes);
                if fields.is_empty() {
                    (107, 4)
                } else {
                    fields[vlr_field.index(fields.len())]
                }
            };
            put(&mut bytes, at, width, value);
            if let Some((f, v)) = second {
                put(&mut bytes, LAS_FIELDS[f].1, LAS_FIELDS[f].2, v);
            }
            let dir = tempdir();
            exercise(dir.path(), &format!("field.{}", extension(name)), &bytes);
        },
    );
}

#[test]
fn bit_flipped_las_and_laz_files_never_panic() {
    let strategy = (
        0usize..7,
        prop::collection::vec((any::<prop::sample::Index>(), 0u8..8, any::<bool>()), 1..12),
        proptest::option::of(any::<prop::sample::Index>()),
    );
    let files = las_files();
    property(
        "bit_flipped_las_and_laz_files_never_panic",
        strategy,
        |(file, flips, cut)| {
            let (name, original) = &files[file % files.len()];
            let mut bytes = original.clone();
            // Half the flips land in the header, VLRs and first points, where parsing
            // decisions are made; the rest anywhere.
            let head = (las_point_offset(&bytes) + 512).min(bytes.len());
            for (k, (index, bit, in_head)) in flips.iter().enumerate() {
                let at = if *in_head {
                    index.index(head)
                } else {
                    index.index(bytes.len())
                };
                if k % 3 == 2 {
                    bytes[at] = index.index(256) as u8;
                } else {
                    bytes[at] ^= 1 << bit;
                }
            }
            if let Some(cut) = cut {
                bytes.truncate(cut.index(bytes.len()));
            }
            let dir = tempdir();
            exercise(dir.path(), &format!("flip.{}", extension(name)), &bytes);
        },
    );
}

#[test]
fn bit_flipped_ply_files_never_panic() {
    let strategy = (
        prop_oneof![Just(Ply::Ascii), Just(Ply::Le), Just(Ply::Be)],
        prop::collection::vec((any::<prop::sample::Index>(), 0u8..8), 1..8),
    );
    property(
        "bit_flipped_ply_files_never_panic",
        strategy,
        |(kind, flips)| {
            let mut bytes = generated_ply(kind);
            for (index, bit) in &flips {
                let at = index.index(bytes.len());
                bytes[at] ^= 1 << bit;
            }
            let dir = tempdir();
            exercise(dir.path(), "flip.ply", &bytes);
        },
    );
}

/// A real E57 file (1,220 points with colour and intensity, libE57's writer). Its points are
/// decoded on the reader's own thread, whose allocations the per-thread record does not see:
/// for E57 only the allocator's refusal above 1 GiB watches them.
fn e57_seed() -> Vec<u8> {
    std::fs::read(data_common::repo_file("tests/data/e57/pipeSpherical.e57")).unwrap()
}

#[test]
fn truncated_e57_files_never_panic() {
    counted("truncated_e57_files_never_panic", || {
        let dir = tempdir();
        let bytes = e57_seed();
        // Every third byte of the 48-byte header and the first page, then spread over the rest.
        for cut in cut_points(bytes.len(), 1024) {
            exercise(dir.path(), &format!("cut{cut}.e57"), &bytes[..cut]);
        }
    });
}

/// Bit flips anywhere: most break a page's checksum, which must be an error naming the file.
#[test]
fn bit_flipped_e57_files_never_panic() {
    let strategy = prop::collection::vec((any::<prop::sample::Index>(), 0u8..8), 1..8);
    property("bit_flipped_e57_files_never_panic", strategy, |flips| {
        let mut bytes = e57_seed();
        for (index, bit) in &flips {
            let at = index.index(bytes.len());
            bytes[at] ^= 1 << bit;
        }
        let dir = tempdir();
        exercise(dir.path(), "flip.e57", &bytes);
    });
}

#[test]
fn garbage_ply_headers_never_panic() {
    let strategy = (
        prop_oneof![Just(Ply::Ascii), Just(Ply::Le), Just(Ply::Be)],
        prop::collection::vec((0usize..6, any::<prop::sample::Index>()), 1..4),
    );
    property(
        "garbage_ply_headers_never_panic",
        strategy,
        |(kind, edits)| {
            let bytes = garbage_ply(kind, &edits);
            let dir = tempdir();
            exercise(dir.path(), "garbage.ply", &bytes);
        },
    );
}

/// A generated PLY whose header went through `edits`: (what to change, which value).
fn garbage_ply(kind: Ply, edits: &[(usize, prop::sample::Index)]) -> Vec<u8> {
    let original = generated_ply(kind);
    let split = original
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let mut header = String::from_utf8(original[..split].to_vec()).unwrap();
    let body = &original[split..];
    const COUNTS: &[&str] = &[
        "0",
        "1",
        "39",
        "41",
        "4294967295",
        "4294967296",
        "18446744073709551615",
        "99999999999999999999999",
        "-1",
        "1e9",
        "",
    ];
    const TYPES: &[&str] = &[
        "char",
        "uchar",
        "short",
        "ushort",
        "int",
        "uint",
        "float",
        "double",
        "int8",
        "float64",
        "int128",
        "list uchar int",
        "list uint uchar",
        "list int double",
        "list float int",
        "",
    ];
    const FORMATS: &[&str] = &[
        "ascii",
        "binary_little_endian",
        "binary_big_endian",
        "binary",
        "ascii 2.0",
        "",
    ];
    for (what, pick) in edits {
        header = match what {
            0 => header.replace(
                "element vertex 40",
                &format!("element vertex {}", COUNTS[pick.index(COUNTS.len())]),
            ),
            1 => header.replace(
                "element face 2",
                &format!("element face {}", COUNTS[pick.index(COUNTS.len())]),
            ),
            2 => {
                // Retype one property line.
                let lines: Vec<&str> = header.lines().collect();
                let props: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].starts_with("property"))
                    .collect();
                let i = props[pick.index(props.len())];
                let name = lines[i].rsplit(' ').next().unwrap();
                let ty = TYPES[pick.index(TYPES.len())];
                let mut out: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                out[i] = format!("property {ty} {name}");
                out.join("\n") + "\n"
            }
            3 => {
                let f = FORMATS[pick.index(FORMATS.len())];
                let lines: Vec<String> = header
                    .lines()
                    .map(|l| {
                        if l.starts_with("format") {
                            format!("format {f} 1.0")
                        } else {
                            l.to_string()
                        }
                    })
                    .collect();
                lines.join("\n") + "\n"
            }
            4 => {
                // Drop one header line.
                let mut lines: Vec<&str> = header.lines().collect();
                let i = pick.index(lines.len());
                lines.remove(i);
                lines.join("\n") + "\n"
            }
            _ => header.replace("list uchar ushort tags", "list uint ushort tags"),
        };
    }
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

/// The unmodified seeds load: the harness reads what it fuzzes.
#[test]
fn unmodified_seeds_load() {
    let dir = tempdir();
    for (name, bytes) in las_files() {
        let path = dir.path().join(&name);
        std::fs::write(&path, &bytes).unwrap();
        let (scene, _) = io::load_scene(&path, &LoadOptions::default()).unwrap();
        assert!(!scene.is_empty(), "{name}");
    }
    for kind in [Ply::Ascii, Ply::Le, Ply::Be] {
        let path = dir.path().join(format!("{kind:?}.ply"));
        std::fs::write(&path, generated_ply(kind)).unwrap();
        let (scene, _) = io::load_scene(&path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        assert_eq!(scene.len(), 40, "{kind:?}");
        assert_eq!(
            scene.radii,
            omnicloud::scene::Radii::PerPoint(vec![0.05; 40])
        );
    }
}

/// Regressions: the exact inputs the harness found, rebuilt from laspy's files by the
/// bytes that differ. Each must give an error naming the file (or a valid scene), with no
/// allocation above the cap.
fn regression(file: &str, edits: &[(usize, &[u8])]) -> Vec<u8> {
    let mut bytes = std::fs::read(laspy(file)).unwrap();
    for (at, new) in edits {
        bytes[*at..*at + new.len()].copy_from_slice(new);
    }
    bytes
}

fn load_error(dir: &Path, name: &str, bytes: &[u8]) -> Option<LoadError> {
    exercise(dir, name, bytes);
    std::fs::write(dir.join(name), bytes).unwrap();
    io::load_scene(&dir.join(name), &LoadOptions::default()).err()
}

#[test]
fn regression_laz_decoder_assertion_becomes_an_error() {
    // One byte of autzen_trim.laz's compressed points: the laz crate panicked with
    // "assertion failed: sym < (1 << 16)".
    let dir = tempdir();
    for (at, byte) in [(142_198usize, 4u8), (71_102, 140)] {
        let bytes = regression("autzen_trim.laz", &[(at, &[byte])]);
        let e = load_error(dir.path(), "autzen_flip.laz", &bytes).expect("corrupt points load");
        assert!(
            matches!(
                e,
                LoadError::DecoderPanic { .. } | LoadError::CorruptPoints { .. }
            ),
            "{e}"
        );
    }
}

#[test]
fn regression_huge_laz_point_count_reserves_no_memory() {
    // LAS 1.4 point count set to 2^40 in a 9 kB LAZ: load_scene reserved 16 M points (192 MB).
    let dir = tempdir();
    let bytes = regression("1_4_w_evlr.laz", &[(247, &(1u64 << 40).to_le_bytes())]);
    assert!(load_error(dir.path(), "count.laz", &bytes).is_some());
}

#[test]
fn regression_extended_vlr_length_is_checked() {
    // A corrupt 64-bit EVLR length went straight into a Vec::resize (17 GB).
    let dir = tempdir();
    let original = std::fs::read(laspy("1_4_w_evlr.laz")).unwrap();
    let start = u64::from_le_bytes(original[235..243].try_into().unwrap()) as usize;
    let bytes = regression(
        "1_4_w_evlr.laz",
        &[(start + 20, &(1u64 << 34).to_le_bytes())],
    );
    let e = load_error(dir.path(), "evlr.laz", &bytes).expect("must fail");
    assert!(matches!(e, LoadError::CorruptHeader { .. }), "{e}");
    assert!(e.to_string().contains("extended VLR"), "{e}");
}

#[test]
fn regression_laz_record_length_does_not_size_the_buffer() {
    // Point record length 32768 in simple.laz: the decoder buffer for one 65,536-point chunk
    // was 2 GB.
    let dir = tempdir();
    let bytes = regression("simple.laz", &[(105, &32_768u16.to_le_bytes())]);
    let _ = load_error(dir.path(), "reclen.laz", &bytes);
}

#[test]
fn regression_ply_double_read_as_huge_stays_finite() {
    // "property float x" retyped to double in a binary PLY: pairs of floats read as doubles
    // near 1e300 that became infinite once stored as f32 relative to the origin.
    let dir = tempdir();
    let original = generated_ply(Ply::Le);
    let split = original
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = String::from_utf8(original[..split].to_vec())
        .unwrap()
        .replace("property float y", "property double y");
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(&original[split..]);
    // A double that is finite in f64 and overflows f32: put 1e300 in the first vertex's y.
    exercise(dir.path(), "retyped.ply", &bytes);
    let mut big = generated_ply(Ply::Le);
    let at = split + 2 * 13 + 4; // after the faces (2 x 13 bytes) and the first x
    let header = String::from_utf8(big[..split].to_vec())
        .unwrap()
        .replace("property float y", "property double y");
    let mut body = big.split_off(split);
    body.splice(at - split..at - split + 4, 1e300f64.to_le_bytes());
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(&body);
    exercise(dir.path(), "huge.ply", &bytes);
}

#[test]
fn regression_absurd_header_bounds_do_not_become_the_origin() {
    // A flipped exponent bit in simple.las's Max X (header offset 179) made the bounds
    // 1e300 m wide: the data still lay inside them, their centre became the origin, and every
    // position overflowed f32 to infinity.
    let dir = tempdir();
    let bytes = regression("simple.las", &[(179, &1e300f64.to_le_bytes())]);
    exercise(dir.path(), "bounds.las", &bytes);
    std::fs::write(dir.path().join("bounds.las"), &bytes).unwrap();
    let (scene, _) = io::load_scene(&dir.path().join("bounds.las"), &LoadOptions::default())
        .expect("the points themselves are fine");
    assert_eq!(scene.len(), 1065);
    assert!(
        scene
            .positions
            .iter()
            .all(|p| p.is_finite() && p.abs().max_element() < 1e4)
    );
}

/// Byte offset of the LASzip VLR's payload.
fn laszip_payload(bytes: &[u8]) -> usize {
    bytes
        .windows(14)
        .position(|w| w == b"laszip encoded")
        .expect("a LAZ file")
        - 2
        + 54
}

#[test]
fn regression_laz_chunk_size_of_one_is_an_error_not_minutes_of_decoding() {
    // autzen_trim.laz with the LASzip chunk size 50,000 turned into 1 (found by the proptest
    // harness with 3,000 cases): the decoder restarted on each of its 110,000 points, reading
    // garbage, for more than 30 s before it failed.
    let dir = tempdir();
    let original = std::fs::read(laspy("autzen_trim.laz")).unwrap();
    let at = laszip_payload(&original) + 12;
    let bytes = regression("autzen_trim.laz", &[(at, &1u32.to_le_bytes())]);
    let started = std::time::Instant::now();
    let e = load_error(dir.path(), "chunk1.laz", &bytes).expect("must fail");
    assert!(matches!(e, LoadError::CorruptPoints { read: 0, .. }), "{e}");
    assert!(e.to_string().contains("chunk size 1"), "{e}");
    assert!(started.elapsed() < Duration::from_secs(5));
}

#[test]
fn regression_layered_laz_layer_size_is_checked_before_the_decoder_allocates_it() {
    // 1_4_w_evlr.laz (point format 6, layered): the first chunk's first layer size (after the
    // 8-byte chunk table offset, the 30-byte raw first point and the u32 point count) set to
    // 4 GB - 16. laz zero-filled that much before reading; the allocator cap aborted.
    let dir = tempdir();
    let original = std::fs::read(laspy("1_4_w_evlr.laz")).unwrap();
    let first_layer = las_point_offset(&original) + 8 + 30 + 4;
    for (k, size) in [(0usize, 0xFFFF_FFF0u32), (8, 1 << 31), (4, 9_000)] {
        let at = first_layer + 4 * k;
        let bytes = regression("1_4_w_evlr.laz", &[(at, &size.to_le_bytes())]);
        let e = load_error(dir.path(), "layer.laz", &bytes).expect("must fail");
        assert!(matches!(e, LoadError::CorruptPoints { .. }), "{e}");
        assert!(e.to_string().contains("bytes of layers"), "{e}");
    }
}

#[test]
fn regression_laz_chunk_table_count_is_checked_before_the_decoder_reserves_it() {
    // The u32 chunk count of 1_4_w_evlr.laz's chunk table set to 2^32 - 1: laz reserved
    // 16 bytes per entry (64 GiB) before decoding the table.
    let dir = tempdir();
    let original = std::fs::read(laspy("1_4_w_evlr.laz")).unwrap();
    let p = las_point_offset(&original);
    let table = i64::from_le_bytes(original[p..p + 8].try_into().unwrap()) as usize;
    let bytes = regression("1_4_w_evlr.laz", &[(table + 4, &u32::MAX.to_le_bytes())]);
    let e = load_error(dir.path(), "table.laz", &bytes).expect("must fail");
    assert!(e.to_string().contains("chunk table"), "{e}");
}

/// A layered LAZ (LAS 1.4, point format `format` with `extra` extra bytes) of `n` points:
/// more than 50,000 makes a second chunk.
fn layered_laz(format: u8, extra: u16, n: u32) -> Vec<u8> {
    let mut builder = las::Builder::from((1, 4));
    let mut point_format = las::point::Format::new(format).unwrap();
    point_format.extra_bytes = extra;
    point_format.is_compressed = true;
    builder.point_format = point_format;
    let header = builder.into_header().unwrap();
    let mut writer = las::Writer::new(std::io::Cursor::new(Vec::new()), header).unwrap();
    for i in 0..n {
        let f = f64::from(i);
        writer
            .write_point(las::Point {
                x: (f * 0.37).sin() * 20.0,
                y: f * 0.001,
                z: (i % 13) as f64,
                intensity: i as u16,
                gps_time: Some(f * 1e-3),
                color: point_format
                    .has_color
                    .then(|| las::Color::new(i as u16, 7, 65_535)),
                nir: point_format.has_nir.then_some(i as u16 ^ 0x5a5a),
                extra_bytes: (0..extra).map(|k| (i as u16 + k) as u8).collect(),
                ..Default::default()
            })
            .unwrap();
    }
    writer.into_inner().unwrap().into_inner()
}

#[test]
fn layered_laz_with_two_chunks_loads_and_a_corrupt_second_chunk_is_refused() {
    // The chunk walk of the layer-size check must follow the decoder exactly: every layered
    // item kind (Point14, RGB14, RGBNIR14, Byte14), across a chunk boundary.
    let dir = tempdir();
    for (format, extra) in [(6u8, 0u16), (7, 2), (8, 3)] {
        let n = 50_100;
        let bytes = layered_laz(format, extra, n);
        let name = format!("layered{format}.laz");
        let path = dir.path().join(&name);
        std::fs::write(&path, &bytes).unwrap();
        let (scene, _) = io::load_scene(&path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("format {format}: {e}"));
        assert_eq!(scene.len(), n as usize, "format {format}");

        // The second chunk starts where the first one's layers end.
        let record = 30 + [0, 6, 8][usize::from(format - 6)] + usize::from(extra);
        let layers = 9 + [0, 1, 2][usize::from(format - 6)] + usize::from(extra);
        let sizes_at = las_point_offset(&bytes) + 8 + record + 4;
        let first_chunk: usize = (0..layers)
            .map(|k| {
                u32::from_le_bytes(bytes[sizes_at + 4 * k..][..4].try_into().unwrap()) as usize
            })
            .sum();
        let second_sizes = sizes_at + 4 * layers + first_chunk + record + 4;
        let mut corrupt = bytes.clone();
        let last_layer = second_sizes + 4 * (layers - 1);
        corrupt[last_layer..last_layer + 4].copy_from_slice(&0x7FFF_FFFFu32.to_le_bytes());
        let e = load_error(dir.path(), &name, &corrupt).expect("must fail");
        assert!(
            e.to_string().contains("LAZ chunk 1 at byte"),
            "format {format}: {e}"
        );
    }
}

#[test]
fn regression_laz_chunk_table_offset_past_the_end_is_an_error() {
    // Byte 5 of 1_4_w_evlr.laz's chunk table offset inverted (found by
    // header_bytes_of_every_las_file_inverted): the offset, 2^48, is past what the file system
    // can seek to; laz then started decoding 8 bytes late and zero-filled a 4.2 GB layer.
    let dir = tempdir();
    let original = std::fs::read(laspy("1_4_w_evlr.laz")).unwrap();
    let at = las_point_offset(&original) + 5;
    let bytes = regression("1_4_w_evlr.laz", &[(at, &[!original[at]])]);
    let e = load_error(dir.path(), "offset.laz", &bytes).expect("must fail");
    assert!(matches!(e, LoadError::CorruptPoints { .. }), "{e}");
    assert!(e.to_string().contains("past the end"), "{e}");
}

/// An input a fuzz target found, kept under tests/data/fuzz/.
fn fuzz_input(name: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn regression_wkt_with_a_closing_bracket_of_the_other_kind_is_read_at_once() {
    // Found by the read_las fuzz target: a LAS file whose WKT VLR reads `...](AUTHORITY[..]]`,
    // a `]` inside `(...)`. The WKT parser took it as an empty word and met it again forever:
    // 8 GB in 20 s. Now the WKT does not parse, and the CRS keeps only its text.
    let dir = tempdir();
    let bytes = fuzz_input("las_wkt_bracket_mismatch.las");
    exercise(dir.path(), "wkt.las", &bytes);
    let started = std::time::Instant::now();
    let info = io::read_info(&dir.path().join("wkt.las")).expect("the header reads");
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "{:?}",
        started.elapsed()
    );
    let crs = info.las.and_then(|l| l.crs).expect("the WKT VLR is kept");
    assert_eq!((crs.name, crs.epsg), (None, None));
    assert!(
        crs.wkt
            .is_some_and(|w| w.starts_with("PROJCS[\"NAD83(HARN)"))
    );
    assert_eq!(info.point_count, 60);
}

#[test]
fn regression_copc_node_layer_sizes_are_checked_before_the_decoder_allocates_them() {
    // Found by the read_copc fuzz target: a 2 kB COPC file (40 points, one node) whose node
    // chunk's layer sizes add up to 2 GB. Reading the node's points made laz zero-fill the
    // layers first (the plain LAZ reader checks them; reading chosen nodes did not).
    let dir = tempdir();
    let path = dir.path().join("node.copc.laz");
    std::fs::write(&path, fuzz_input("copc_node_layer_sizes.copc.laz")).unwrap();
    let octree = io::read_octree(&path).expect("the hierarchy is sound");
    let keys: Vec<io::NodeKey> = octree.nodes.keys().copied().collect();
    LARGEST.with(|l| l.set(0));
    let e = io::open_nodes(&path, &keys).expect_err("the node's layers do not fit");
    assert!(LARGEST.with(Cell::get) < LARGEST_ALLOWED);
    assert!(matches!(e, LoadError::CorruptCopc { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("node.copc.laz") && text.contains("node 0-0-0-0"),
        "{text}"
    );
    assert!(text.contains("bytes of layers"), "{text}");
}

#[test]
fn regression_exr_frame_declaring_a_huge_image_is_refused_before_decoding() {
    // Found by the frame_folder fuzz target: a 1.9 kB EXR frame whose header declares an
    // image 2^29 pixels wide; the exr crate allocated a 110 GB block for it and aborted.
    let dir = tempdir();
    let path = dir.path().join("frame_000000.exr");
    std::fs::write(&path, fuzz_input("exr_huge_data_window.exr")).unwrap();
    LARGEST.with(|l| l.set(0));
    let e = omnicloud::output::read_image(&path).expect_err("the size is refused");
    let frames = omnicloud::frames::dimensions(&path).expect_err("the folder's frame too");
    assert!(LARGEST.with(Cell::get) < LARGEST_ALLOWED);
    for text in [e.to_string(), frames.to_string()] {
        assert!(
            text.contains("frame_000000.exr") && text.contains("pixels"),
            "{text}"
        );
    }
}

#[test]
fn regression_exr_frame_declaring_far_more_than_it_holds_is_refused_at_once() {
    // Found by the frame_folder fuzz target (a timeout): a 1.3 kB EXR frame declaring
    // 6,094,864 x 8 pixels took 1.75 GB and seconds to decode. A frame from a real render is
    // still read.
    let dir = tempdir();
    let path = dir.path().join("frame_000001.exr");
    std::fs::write(&path, fuzz_input("exr_declares_far_more_than_it_holds.exr")).unwrap();
    let started = std::time::Instant::now();
    let e = omnicloud::output::read_image(&path).expect_err("the size is refused");
    assert!(
        started.elapsed() < Duration::from_secs(1),
        "{:?}",
        started.elapsed()
    );
    assert!(e.to_string().contains("6094864 x 8 pixels"), "{e}");
    assert!(e.to_string().contains("can hold"), "{e}");
}

#[test]
fn regression_laszip_vlr_user_id_is_matched_as_the_las_crate_reads_it() {
    // Found by the read_copc fuzz target: the LASzip VLR's user id `laszip encoded\0X` (a
    // byte after its NUL changed). The las crate reads a user id up to its first NUL and
    // decoded with that VLR; the chunk checks did not recognise it, and a node's layer sizes
    // of 33 GB went unchecked.
    let dir = tempdir();
    let path = dir.path().join("user_id.copc.laz");
    std::fs::write(&path, fuzz_input("copc_laszip_user_id_after_nul.copc.laz")).unwrap();
    let octree = io::read_octree(&path).expect("the hierarchy is sound");
    let keys: Vec<io::NodeKey> = octree.nodes.keys().copied().collect();
    LARGEST.with(|l| l.set(0));
    let e = io::open_nodes(&path, &keys).expect_err("node 1-1-1-1's layers do not fit");
    assert!(LARGEST.with(Cell::get) < LARGEST_ALLOWED);
    assert!(
        e.to_string().contains("node 1-1-1-1") && e.to_string().contains("layers"),
        "{e}"
    );
}

#[test]
fn regression_laz_chunk_table_is_checked_when_the_laszip_vlr_lists_no_items() {
    // Found by the read_las fuzz target: a LASzip VLR with no items and a chunk table
    // claiming 2,955,349,533 entries; the checks skipped item-less VLRs, laz reserved 47 GB.
    let dir = tempdir();
    let bytes = fuzz_input("laz_no_items_huge_chunk_table.las");
    let e = load_error(dir.path(), "no_items.laz", &bytes).expect("must fail");
    assert!(e.to_string().contains("2955349533 chunks"), "{e}");
}

#[test]
fn regression_copc_header_shorter_than_its_version_hides_no_laszip_vlr_from_the_checks() {
    // Found by the read_copc fuzz target: a 2 kB COPC file whose header states 374 bytes for
    // a LAS 1.4 header of 375. The las crate reads the VLRs after the 375 bytes, and the
    // decoder took the LASzip VLR found there; the chunk checks walked the VLRs from byte 374,
    // found none, and let the node's layer sizes (13 GB) through: laz zero-filled 1.85 GB.
    let dir = tempdir();
    let bytes = fuzz_input("copc_short_header_hides_laszip_vlr.copc.laz");
    let path = dir.path().join("short.copc.laz");
    std::fs::write(&path, &bytes).unwrap();
    let octree = io::read_octree(&path).expect("the hierarchy is sound");
    let keys: Vec<io::NodeKey> = octree.nodes.keys().copied().collect();
    LARGEST.with(|l| l.set(0));
    let e = io::open_nodes(&path, &keys).expect_err("the node's layers do not fit");
    assert!(LARGEST.with(Cell::get) < LARGEST_ALLOWED);
    assert!(matches!(e, LoadError::CorruptCopc { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("short.copc.laz") && text.contains("node 0-0-0-0"),
        "{text}"
    );
    assert!(text.contains("13407739971 bytes of layers"), "{text}");
    // Read as a whole LAZ file, through the same checks.
    exercise(dir.path(), "whole.copc.laz", &bytes);
}

#[test]
fn regression_laz_gps_time_switching_sequences_without_end_is_an_error_not_a_stack_overflow() {
    // Found by the read_copc fuzz target (a segmentation fault): a 2 kB COPC file whose node
    // decodes "switch to another GPS time sequence" over and over. laz recursed once per
    // switch and overflowed the stack; its decoders now loop (vendor/laz/PATCHES.md) and
    // refuse a point past 1024 switches.
    let dir = tempdir();
    let bytes = fuzz_input("copc_gps_time_switches_without_end.copc.laz");
    let path = dir.path().join("switches.copc.laz");
    std::fs::write(&path, &bytes).unwrap();
    let octree = io::read_octree(&path).expect("the hierarchy is sound");
    let keys: Vec<io::NodeKey> = octree.nodes.keys().copied().collect();
    let started = std::time::Instant::now();
    let reader = io::open_nodes(&path, &keys).expect("the node's chunk is in place");
    let e = reader
        .chunks(4096)
        .find_map(Result::err)
        .expect("the node's points do not decode");
    assert!(
        started.elapsed() < Duration::from_secs(1),
        "{:?}",
        started.elapsed()
    );
    let text = e.to_string();
    assert!(text.contains("switches.copc.laz"), "{text}");
    assert!(
        text.contains("switches sequence more than 1024 times"),
        "{text}"
    );
    exercise(dir.path(), "whole.copc.laz", &bytes);
}

#[test]
fn regression_laszip_items_larger_than_the_point_records_are_refused_before_decoding() {
    // Found by the read_copc fuzz target (a slow unit): a 4.5 kB COPC file whose LASzip VLR
    // lists an extra-bytes item of 63,495 bytes for 38-byte records. laz set up a model per
    // extra byte before reading a point: 620 MB and a second to open the file.
    let dir = tempdir();
    let bytes = fuzz_input("copc_extra_bytes_item_larger_than_the_records.copc.laz");
    let path = dir.path().join("items.copc.laz");
    std::fs::write(&path, &bytes).unwrap();
    LARGEST.with(|l| l.set(0));
    let started = std::time::Instant::now();
    let e = io::read_octree(&path).expect_err("the items do not match the records");
    assert!(
        started.elapsed() < Duration::from_millis(100),
        "{:?}",
        started.elapsed()
    );
    assert!(LARGEST.with(Cell::get) < 1 << 20);
    assert!(matches!(e, LoadError::CorruptHeader { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("items.copc.laz")
            && text.contains("add up to 63525 bytes a point")
            && text.contains("records are 38 bytes"),
        "{text}"
    );
    exercise(dir.path(), "whole.copc.laz", &bytes);
}

#[test]
fn regression_copc_cube_whose_corners_overflow_is_refused() {
    // Found by the read_copc fuzz target: an info VLR with a halfsize of 1.19e308 (finite, so
    // it passed), whose node cubes came out NaN and infinite.
    let dir = tempdir();
    let bytes = fuzz_input("copc_cube_corners_overflow.copc.laz");
    let path = dir.path().join("cube.copc.laz");
    std::fs::write(&path, &bytes).unwrap();
    let e = io::read_octree(&path).expect_err("the cube does not fit in f64");
    assert!(matches!(e, LoadError::CorruptCopc { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("cube.copc.laz") && text.contains("halfsize 118647747017762"),
        "{text}"
    );
    exercise(dir.path(), "whole.copc.laz", &bytes);
}
