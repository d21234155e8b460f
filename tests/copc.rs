//! COPC input: the octree read and checked, view-dependent detail against full detail, a
//! corrupt hierarchy, and the COPC reader against the plain LAZ reader.
//!
//! The fixture is data/courtyard.copc.laz (tools/make_copc.py): 431,121 points, 60 m x 60 m
//! of ground, a wall and ten pillars, all sampled every 0.1 m, in a depth-5 octree. The
//! renders are ray-traced (the exact renderer) at 384 x 192 from the centre, 1.7 m up, with a
//! 0.08 m radius: it closes the 0.1 m sampling, so coverage measures surfaces and their
//! outlines, not the sampling noise of open surfaces. Measured: level of detail at a pixel
//! with no floor reads 173,354 points (40.2%) for IoU 0.9979 against the full cloud; a floor
//! of 300,000 points reads 296,301 for 0.9985; the default floor reads every point.

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::io::{self, LoadOptions, NodeKey, load_scene};
use omnicloud::output::LinearImage;
use omnicloud::prepare::{Lod, PrepareOptions, Prepared, RadiusChoice, prepare};
use omnicloud::projection::Camera;
use omnicloud::render::RenderSettings;
use omnicloud::{Rendered, raytrace};
use std::path::{Path, PathBuf};
use std::process::Command;

const POINTS: u64 = 431_121;
const WIDTH: u32 = 384;

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/courtyard.copc.laz")
}

fn options(lod: Lod) -> PrepareOptions {
    PrepareOptions {
        camera: omnicloud::prepare::CameraChoice::At(DVec3::new(0.0, 0.0, 1.7)),
        radius: Some(RadiusChoice::Fixed(0.08)),
        lod,
        ..PrepareOptions::default()
    }
}

/// The threshold alone (no floor).
fn lod(pixels: f64) -> Lod {
    Lod::Pixels {
        width: WIDTH,
        pixels,
        floor: 0,
    }
}

fn render(prepared: &Prepared) -> LinearImage {
    let settings = RenderSettings::new(WIDTH, Camera::new(DVec3::ZERO, 0.0));
    match raytrace::render(&prepared.scene, &settings, &ProgressBar::hidden()).unwrap() {
        Rendered::Mono(f) => LinearImage::from_frame(&f),
        Rendered::Stereo { .. } => unreachable!("mono settings"),
    }
}

#[test]
fn octree_is_read_and_checked() {
    let octree = io::read_octree(&fixture()).unwrap();
    assert_eq!(octree.point_count, POINTS);
    assert_eq!(octree.depth(), 5);
    assert_eq!(octree.nonempty_nodes(), 1604);
    assert!((octree.spacing - 1.8775).abs() < 1e-3, "{}", octree.spacing);
    assert_eq!(octree.nodes.values().sum::<u64>(), POINTS);
    let info = io::read_info(&fixture()).unwrap();
    assert!(io::is_copc(&info));
    let plain = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz");
    assert!(!io::is_copc(&io::read_info(&plain).unwrap()));
    let err = io::read_octree(&plain).unwrap_err().to_string();
    assert!(
        err.contains("autzen_trim.laz") && err.contains("not a COPC file"),
        "{err}"
    );
}

#[test]
fn lod_matches_full_detail_reading_less_than_half() {
    let full = prepare(&fixture(), &options(Lod::Off), &ProgressBar::hidden()).unwrap();
    assert!(full.lod.is_none());
    assert_eq!(full.scene.len() as u64, POINTS);
    let near = prepare(&fixture(), &options(lod(1.0)), &ProgressBar::hidden()).unwrap();
    let report = near.lod.unwrap();
    assert_eq!(report.points_total, POINTS);
    assert_eq!(report.points_read, near.scene.len() as u64);
    assert_eq!((report.depth, report.deepest), (5, 5));
    let share = report.points_read as f64 / POINTS as f64;
    let cmp = omnicloud::compare::compare(&render(&full), &render(&near)).unwrap();
    let iou = cmp.eyes[0].all.iou;
    eprintln!(
        "{report}: {:.1}% of the points, IoU {iou:.4}",
        100.0 * share
    );
    assert!(share < 0.45, "read {:.1}%", 100.0 * share);
    assert!(iou >= 0.995, "IoU {iou}");
}

#[test]
fn lod_reading_every_node_equals_lod_off() {
    // A threshold far below a pixel refines everything: the COPC path must then give the
    // plain read's render exactly (same points, same radii).
    let full = prepare(&fixture(), &options(Lod::Off), &ProgressBar::hidden()).unwrap();
    let all = prepare(&fixture(), &options(lod(0.01)), &ProgressBar::hidden()).unwrap();
    assert_eq!(all.lod.unwrap().points_read, POINTS);
    let cmp = omnicloud::compare::compare(&render(&full), &render(&all)).unwrap();
    assert!(cmp.is_identical(), "{:?}", cmp.eyes[0].all);
}

#[test]
fn a_floor_spends_its_points_where_the_threshold_stopped() {
    let full = render(&prepare(&fixture(), &options(Lod::Off), &ProgressBar::hidden()).unwrap());
    let iou = |floor: u64| {
        let p = prepare(
            &fixture(),
            &options(lod(1.0).with_floor(floor)),
            &ProgressBar::hidden(),
        )
        .unwrap();
        let read = p.lod.unwrap().points_read;
        let cmp = omnicloud::compare::compare(&full, &render(&p)).unwrap();
        eprintln!("floor {floor}: read {read}, IoU {:.5}", cmp.eyes[0].all.iou);
        (read, cmp.eyes[0].all.iou, cmp.is_identical())
    };
    // The default floor holds the whole courtyard: every point, the full render exactly.
    let (read, _, identical) = iou(omnicloud::prepare::lod::LOD_FLOOR_POINTS);
    assert_eq!(read, POINTS);
    assert!(
        identical,
        "the default floor's render differs from every point's"
    );
    // A floor between the threshold's 173,354 points and the whole: within it, and closer.
    let (alone, alone_iou, _) = iou(0);
    let (read, floor_iou, _) = iou(300_000);
    assert!(read > alone && read <= 300_000, "{read}");
    assert!(floor_iou > alone_iou, "{floor_iou} against {alone_iou}");
}

#[test]
fn copc_reader_reads_the_laz_readers_points() {
    let path = fixture();
    let octree = io::read_octree(&path).unwrap();
    let keys: Vec<NodeKey> = octree.nodes.keys().copied().collect();
    let mut copc = Vec::new();
    let mut classes = Vec::new();
    for chunk in io::open_nodes(&path, &keys).unwrap().chunks(1 << 16) {
        let chunk = chunk.unwrap();
        copc.extend(chunk.positions);
        classes.extend(chunk.classification.unwrap());
    }
    let mut laz = Vec::new();
    let mut laz_classes = Vec::new();
    for chunk in io::open(&path).unwrap().chunks(1 << 16) {
        let chunk = chunk.unwrap();
        laz.extend(chunk.positions);
        laz_classes.extend(chunk.classification.unwrap());
    }
    // Nodes are read in file order, as the LAZ reader reads the chunks.
    assert_eq!(copc.len() as u64, POINTS);
    assert!(copc == laz, "the COPC and LAZ readers disagree");
    assert_eq!(classes, laz_classes);
    // And `--lod off` is the plain LAZ read.
    let (scene, _) = load_scene(
        &path,
        &LoadOptions {
            origin: Some(DVec3::new(0.0, 0.0, 1.7)),
            ..LoadOptions::default()
        },
    )
    .unwrap();
    let off = prepare(&path, &options(Lod::Off), &ProgressBar::hidden()).unwrap();
    assert_eq!(off.scene.positions, scene.positions);
}

/// One opened file serves many node reads, from several threads at once, each the points a
/// read of its own gives; a key not in the hierarchy is refused by name.
#[test]
fn one_opened_file_reads_any_nodes_from_any_thread() {
    use std::collections::HashSet;
    let path = fixture();
    let copc = io::CopcFile::open(&path).unwrap();
    assert_eq!(copc.octree(), &io::read_octree(&path).unwrap());
    let mut keys: Vec<NodeKey> = copc.octree().nodes.keys().copied().collect();
    keys.sort_unstable();
    let positions = |reader: io::PointReader| -> Vec<DVec3> {
        reader
            .chunks(1 << 16)
            .flat_map(|c| c.unwrap().positions)
            .collect()
    };
    let groups: Vec<&[NodeKey]> = keys.chunks(97).collect();
    let shared: Vec<Vec<DVec3>> = std::thread::scope(|s| {
        let handles: Vec<_> = groups
            .iter()
            .map(|g| s.spawn(|| positions(copc.read_nodes(g, &HashSet::new()).unwrap())))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut total = 0;
    for (group, got) in groups.iter().zip(&shared) {
        assert_eq!(got, &positions(io::open_nodes(&path, group).unwrap()));
        // A node reader announces its nodes' points, not the file's.
        let reader = copc.read_nodes(group, &HashSet::new()).unwrap();
        assert_eq!(reader.points_to_read(), got.len() as u64);
        assert_eq!(reader.info().point_count, POINTS);
        total += got.len() as u64;
    }
    assert_eq!(total, POINTS);
    // So a load of some nodes counts its progress against them.
    let progress = ProgressBar::hidden();
    let (scene, _) = io::load_files_with_reader(
        std::slice::from_ref(&path),
        &LoadOptions::default(),
        &progress,
        &|_| copc.read_nodes(groups[1], &HashSet::new()),
    )
    .unwrap();
    assert_eq!(progress.length(), Some(shared[1].len() as u64));
    assert_eq!(scene.positions.len(), shared[1].len());
    let missing = NodeKey {
        depth: 9,
        x: 0,
        y: 0,
        z: 0,
    };
    let Err(err) = copc.read_nodes(&[missing], &HashSet::new()) else {
        panic!("a node the hierarchy does not list was read");
    };
    assert!(
        err.to_string().contains("no node 9-0-0-0 in the hierarchy"),
        "{err}"
    );
}

/// Byte offset and length of the COPC hierarchy EVLR's data.
fn hierarchy_evlr(bytes: &[u8]) -> (usize, usize) {
    let u64_at = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
    let mut at = u64_at(235); // start of the first EVLR (LAS 1.4 header)
    let count = u32::from_le_bytes(bytes[243..247].try_into().unwrap());
    for _ in 0..count {
        let user = String::from_utf8_lossy(&bytes[at + 2..at + 18]);
        let record = u16::from_le_bytes([bytes[at + 18], bytes[at + 19]]);
        let len = u64_at(at + 20);
        if user.trim_end_matches('\0') == "copc" && record == 1000 {
            return (at + 60, len);
        }
        at += 60 + len;
    }
    panic!("no COPC hierarchy EVLR");
}

/// Bytes flipped in a hierarchy's data.
type Flip = fn(&mut [u8]);

/// A copy of the fixture with `flip` applied to its hierarchy's data.
fn corrupted(dir: &Path, name: &str, flip: impl Fn(&mut [u8])) -> PathBuf {
    let mut bytes = std::fs::read(fixture()).unwrap();
    let (start, len) = hierarchy_evlr(&bytes);
    flip(&mut bytes[start..start + len]);
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn corrupt_hierarchy_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    // Each hierarchy entry is 32 bytes: key (4 x i32), offset u64, byte size i32, points i32.
    // A wrong key, a wrong count, an offset past the end, an offset 16 bytes off.
    let cases: [(&str, Flip, &str); 4] = [
        (
            "key.copc.laz",
            |h| h[32..48].iter_mut().for_each(|b| *b ^= 0xFF),
            "impossible node",
        ),
        (
            "count.copc.laz",
            |h| h[32 + 28] ^= 0x01,
            "points but the header declares",
        ),
        ("offset.copc.laz", |h| h[32 + 23] ^= 0x40, "outside the"),
        ("near.copc.laz", |h| h[64 + 16] ^= 0x10, "overlap"),
    ];
    for (name, flip, says) in cases {
        let path = corrupted(dir.path(), name, flip);
        let err = io::read_octree(&path).unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
        assert!(
            err.contains("corrupt COPC hierarchy") && err.contains(says),
            "{err}"
        );
        let err = prepare(&path, &options(lod(1.0)), &ProgressBar::hidden())
            .unwrap_err()
            .to_string();
        assert!(err.contains(name) && err.contains(says), "{err}");
    }
    // The CLI says so too, and `--lod off` reads the points without the hierarchy.
    let path = corrupted(dir.path(), "cli.copc.laz", |h| {
        h[32..48].iter_mut().for_each(|b| *b ^= 0xFF)
    });
    let out = dir.path().join("out.png");
    let run = |lod: &str| {
        Command::new(env!("CARGO_BIN_EXE_omnicloud"))
            .args(["render", path.to_str().unwrap(), "--renderer", "raytrace"])
            .args(["--width", "64", "--camera", "0,0,1.7", "--lod", lod, "-o"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let failed = run("on");
    let stderr = String::from_utf8_lossy(&failed.stderr);
    assert!(!failed.status.success());
    assert!(
        stderr.contains("cli.copc.laz") && stderr.contains("corrupt COPC hierarchy"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(run("off").status.success());
}

/// `omnicloud render` of the fixture, ray-traced 128 px wide from the centre, with `extra`
/// options, to `out`.
fn trace_128(extra: &[&str], out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .arg("render")
        .arg(fixture())
        .args([
            "--renderer",
            "raytrace",
            "--width",
            "128",
            "--camera",
            "0,0,1.7",
        ])
        .args(extra)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn render_reports_points_read() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pano.png");
    let read = |floor: &[&str]| {
        let run = trace_128(floor, &out);
        let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
        assert!(run.status.success(), "{stderr}");
        let line = stderr
            .lines()
            .find(|l| l.contains("level of detail"))
            .unwrap_or_else(|| panic!("no level-of-detail line in {stderr}"))
            .to_string();
        assert!(line.contains(&format!("of {POINTS} points")), "{line}");
        let read: u64 = line
            .split("read ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap();
        (read, line)
    };
    // At 128 pixels a pixel spans 4.9 cm at 1 m: far less than the full cloud is needed.
    let (alone, line) = read(&["--lod-floor", "0"]);
    assert!(alone < POINTS / 5, "{line}");
    assert!(line.contains("floor 0 points"), "{line}");
    // The default floor (a million points) holds the whole courtyard.
    let (all, line) = read(&[]);
    assert_eq!(all, POINTS, "{line}");
    assert!(line.contains("floor 1000000 points"), "{line}");
}

#[test]
fn info_describes_the_octree() {
    let run = |json: bool| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
        command.arg("info").arg(fixture());
        if json {
            command.arg("--json");
        }
        let out = command.output().unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let text = run(false);
    assert!(
        text.contains(
            "copc:          octree of depth 5, 1604 nodes with points, root spacing 1.8775 m"
        ),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(&run(true)).unwrap();
    assert_eq!(json["copc"]["depth"], 5);
    assert_eq!(json["copc"]["nodes"], 1604);
}

#[test]
fn streamed_plan_holds_the_selection() {
    use omnicloud::stream::{PlanOptions, plan};
    let near = PlanOptions {
        prepare: options(lod(1.0)),
        // Smaller than the file: without level of detail the file would be surveyed and
        // streamed; with it the selection is held whole.
        survey_points: 1 << 16,
        ..PlanOptions::default()
    };
    let p = plan(&fixture(), &near, &ProgressBar::hidden()).unwrap();
    let report = p.lod.unwrap();
    assert_eq!(report.points_read, 173_354);
    assert_eq!(p.whole.unwrap().len() as u64, report.points_read);
    let off = PlanOptions {
        prepare: options(Lod::Off),
        ..near
    };
    let p = plan(&fixture(), &off, &ProgressBar::hidden()).unwrap();
    assert!(p.lod.is_none() && p.whole.is_none());
}

#[test]
fn memory_cap_counts_the_selection() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pano.png");
    let run = |lod: &str| trace_128(&["--max-memory", "120M", "--lod", lod], &out);
    // The whole cloud needs an estimated 197.5 MiB; the selection a fraction of it.
    let off = run("off");
    assert!(!off.status.success());
    assert!(String::from_utf8_lossy(&off.stderr).contains("over the memory cap"));
    let on = run("on");
    assert!(
        on.status.success(),
        "{}",
        String::from_utf8_lossy(&on.stderr)
    );
}
