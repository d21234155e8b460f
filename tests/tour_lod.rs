//! Tours through an indexed scan drawn through the level of detail: with a threshold that
//! selects every node the frames are bit for bit those of every point kept resident; with a
//! threshold of a pixel or half one they cover nearly the same pixels (coverage IoU, measured
//! values in the test), closer with a floor of points, and the default floor draws the
//! statue whole; a small node cache evicts and
//! stays within its bound while drawing the same frames.

#[path = "raster_common/gpu.rs"]
mod gpu;

use std::path::{Path, PathBuf};

use indicatif::ProgressBar;
use omnicloud::Rendered;
use omnicloud::index::{self, IndexOptions};
use omnicloud::prepare::PrepareOptions;
use omnicloud::prepare::lod::NodeRadii;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{ColorMode, ColorRule, RenderSettings, RendererKind};
use omnicloud::renderer::{NodeRules, NodeStream, Resident};
use omnicloud::tour::{self, Sampling, Tour, TourRequest};

/// A dense terrestrial scan: a lion statue, 342 k points in a 4 x 6 x 5 m box.
const SCAN: &str = "tests/data/potree/lion_takanawa.laz";
/// A walk past the statue, 1.5 m to 3 m from it, heights given.
const WALK: &str = "x,y,z\n-4.8,1.2,0.3\n-4.6,6.5,0.6\n-1.0,6.5,0.3\n";
const WIDTH: u32 = 512;

/// The scan indexed into `dir` (radii stored), and the walk laid out on it.
fn indexed_walk(dir: &Path, frames: usize) -> (PathBuf, TourRequest, Tour) {
    let copc = dir.join("lion.copc.laz");
    let walk = dir.join("walk.csv");
    std::fs::write(&walk, WALK).unwrap();
    index::index(
        &[PathBuf::from(SCAN)],
        &copc,
        &IndexOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap();
    let request = TourRequest {
        scan: tour::TourScan::File(copc.clone()),
        route: tour::Route::Path(walk),
        prepare: PrepareOptions::default(),
        height: PrepareOptions::default().height,
        sampling: Sampling::Frames(frames),
        heading_window: 2.0,
        yaw_offset: 0.0,
        pitch_offset: 0.0,
        roll_offset: 0.0,
    };
    let planned = tour::plan(&request, &ProgressBar::hidden()).unwrap();
    (copc, request, planned)
}

/// ODS at [`WIDTH`], coloured by elevation (measured on the whole scan).
fn settings() -> RenderSettings {
    RenderSettings {
        color: ColorMode::Elevation,
        stereo: Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging::both(PoleMerge::COMFORTABLE),
            offset: OdsOffset::Exact,
        },
        ..RenderSettings::new(WIDTH, Camera::new(glam::DVec3::ZERO, 0.0))
    }
}

/// Every pose's settings (camera in the tour's local frame).
fn poses(planned: &Tour) -> Vec<RenderSettings> {
    planned
        .poses
        .iter()
        .map(|p| RenderSettings {
            camera: Camera::new(glam::DVec3::from_array(p.position) - planned.origin, p.yaw)
                .with_orientation(p.pitch, p.roll),
            ..settings()
        })
        .collect()
}

/// The tour's node stream over `copc` at `pixels` with no floor, `budget` bytes of nodes.
fn stream(
    rasterizer: omnicloud::raster::Rasterizer,
    copc: &Path,
    request: &TourRequest,
    planned: &Tour,
    pixels: f64,
    budget: u64,
) -> NodeStream {
    stream_with_floor(rasterizer, copc, request, planned, pixels, 0, budget)
}

/// The tour's node stream over `copc` at `pixels` reading at least `floor` points a frame,
/// `budget` bytes of nodes.
fn stream_with_floor(
    rasterizer: omnicloud::raster::Rasterizer,
    copc: &Path,
    request: &TourRequest,
    planned: &Tour,
    pixels: f64,
    floor: u64,
    budget: u64,
) -> NodeStream {
    let options = PrepareOptions {
        origin: Some(planned.origin),
        ..request.prepare
    };
    let color = ColorRule::for_scene(&planned.scene, settings().color).unwrap();
    NodeStream::new(
        rasterizer,
        copc,
        &options,
        NodeRules {
            radii: NodeRadii::File,
            color,
            pixels,
            floor,
            budget,
        },
        &settings(),
    )
    .unwrap()
}

fn every_point(planned: &Tour) -> Vec<Rendered> {
    let resident = Resident::new(&planned.scene, RendererKind::Raster, &settings()).unwrap();
    let hidden = ProgressBar::hidden();
    poses(planned)
        .iter()
        .map(|s| resident.render(s, &hidden).unwrap())
        .collect()
}

fn through_nodes(stream: &mut NodeStream, planned: &Tour) -> Vec<Rendered> {
    let hidden = ProgressBar::hidden();
    poses(planned)
        .iter()
        .map(|s| stream.render(s, &hidden).unwrap())
        .collect()
}

/// Covered pixels in both over covered pixels in either, over every eye of every frame.
fn coverage_iou(a: &[Rendered], b: &[Rendered]) -> f64 {
    let (mut both, mut either) = (0u64, 0u64);
    for (a, b) in a.iter().zip(b) {
        for (fa, fb) in a.frames().into_iter().zip(b.frames()) {
            for (ca, cb) in fa.color.iter().zip(&fb.color) {
                let (ia, ib) = (ca[3] != 0, cb[3] != 0);
                both += u64::from(ia && ib);
                either += u64::from(ia || ib);
            }
        }
    }
    both as f64 / either.max(1) as f64
}

#[test]
fn every_node_gives_the_frames_of_every_point_and_fewer_cover_nearly_the_same_pixels() {
    if gpu::rasterizer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (copc, request, planned) = indexed_walk(dir.path(), 6);
    let want = every_point(&planned);

    let mut all = stream(
        gpu::rasterizer().unwrap(),
        &copc,
        &request,
        &planned,
        0.0,
        1 << 30,
    );
    let got = through_nodes(&mut all, &planned);
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(g == w, "frame {i} differs from the resident scan's");
    }
    let total = planned.scene.len() as u64;
    assert_eq!(all.last_frame().points, total);
    let counts = all.cache_counts();
    // Every node is read once, then every later frame reuses it.
    assert_eq!(counts.evicted, 0);
    assert_eq!(counts.hits, counts.misses * 5);

    // Measured on this walk at 512 px ODS: 1 px reads 59.7 % of the points for a coverage IoU
    // of 0.964; half a pixel reads 97.3 % for 0.9961.
    for (pixels, min_iou, max_read) in [(1.0, 0.96, 0.62), (0.5, 0.995, 0.98)] {
        let mut lod = stream(
            gpu::rasterizer().unwrap(),
            &copc,
            &request,
            &planned,
            pixels,
            1 << 30,
        );
        let got = through_nodes(&mut lod, &planned);
        let iou = coverage_iou(&got, &want);
        let read = lod.last_frame().points as f64 / total as f64;
        eprintln!("{pixels} px: coverage IoU {iou:.5}, last frame read {read:.3} of the points");
        assert!(iou >= min_iou, "{pixels} px: coverage IoU {iou}");
        assert!(read <= max_read, "{pixels} px: read {read} of the points");
    }

    // A floor between what a pixel reads and the whole statue: each frame reads up to it,
    // the coarsest-looking nodes refined first, and covers closer to every point's pixels.
    // Measured: a floor of 80 % of the points reads 71.0 % on the last frame for an IoU of
    // 0.9874 (a pixel alone: 59.7 % for 0.964).
    let floor = total * 4 / 5;
    let mut floored = stream_with_floor(
        gpu::rasterizer().unwrap(),
        &copc,
        &request,
        &planned,
        1.0,
        floor,
        1 << 30,
    );
    let got = through_nodes(&mut floored, &planned);
    let iou = coverage_iou(&got, &want);
    let read = floored.last_frame().points;
    eprintln!("1 px, floor {floor}: coverage IoU {iou:.5}, last frame read {read} points");
    assert!(
        read <= floor && read as f64 > 0.62 * total as f64,
        "read {read}"
    );
    assert!(iou >= 0.985, "floor {floor}: coverage IoU {iou}");

    // The default floor holds the whole statue: the frames of every point, bit for bit.
    let mut whole = stream_with_floor(
        gpu::rasterizer().unwrap(),
        &copc,
        &request,
        &planned,
        1.0,
        omnicloud::prepare::lod::LOD_FLOOR_POINTS,
        1 << 30,
    );
    let got = through_nodes(&mut whole, &planned);
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(
            g == w,
            "frame {i} at the default floor differs from the resident scan's"
        );
    }
}

#[test]
fn a_small_node_cache_evicts_within_its_bound_and_draws_the_same_frames() {
    if gpu::rasterizer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (copc, request, planned) = indexed_walk(dir.path(), 4);
    let mut roomy = stream(
        gpu::rasterizer().unwrap(),
        &copc,
        &request,
        &planned,
        1.0,
        1 << 30,
    );
    let want = through_nodes(&mut roomy, &planned);
    let (all_bytes, _) = roomy.cache_bytes();
    let budget = all_bytes / 3;
    let mut tight = stream(
        gpu::rasterizer().unwrap(),
        &copc,
        &request,
        &planned,
        1.0,
        budget,
    );
    let hidden = ProgressBar::hidden();
    for (i, s) in poses(&planned).iter().enumerate() {
        let got = tight.render(s, &hidden).unwrap();
        assert!(got == want[i], "frame {i} differs under a small cache");
        assert!(tight.cache_bytes().0 <= budget);
    }
    let counts = tight.cache_counts();
    assert!(counts.evicted > 0, "{counts:?}");
    assert!(
        counts.misses > roomy.cache_counts().misses,
        "{counts:?} against {:?}",
        roomy.cache_counts()
    );
}

/// A scan truncated, or replaced by another file, while a tour reads it node by node: the next
/// frame is an error naming the file, never a frame drawn from a mix of the two files.
#[test]
fn a_scan_changed_during_the_tour_is_an_error_naming_it() {
    if gpu::rasterizer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (copc, request, planned) = indexed_walk(dir.path(), 3);
    let original = std::fs::read(&copc).unwrap();
    let hidden = ProgressBar::hidden();
    let frames = poses(&planned);
    let changes: [(&str, &dyn Fn()); 2] = [
        ("truncated", &|| {
            let f = std::fs::OpenOptions::new().write(true).open(&copc).unwrap();
            f.set_len(original.len() as u64 / 2).unwrap();
        }),
        ("replaced", &|| {
            // Same bytes, another file: what `cp new.laz scan.laz.tmp && mv` leaves.
            let other = dir.path().join("other.copc.laz");
            std::fs::write(&other, &original).unwrap();
            std::fs::rename(&other, &copc).unwrap();
        }),
    ];
    for (how, change) in changes {
        std::fs::write(&copc, &original).unwrap();
        // Every node read on each frame (0 px): the second frame must read the file again.
        let mut nodes = stream(
            gpu::rasterizer().unwrap(),
            &copc,
            &request,
            &planned,
            0.0,
            0,
        );
        nodes.render(&frames[0], &hidden).unwrap();
        change();
        let err = match nodes.render(&frames[1], &hidden) {
            Ok(_) => panic!("{how}: a frame was drawn from the changed scan"),
            Err(e) => e.to_string(),
        };
        eprintln!("{how}: {err}");
        assert!(err.contains(&copc.display().to_string()), "{how}: {err}");
        assert!(
            err.contains("changed while it was being read"),
            "{how}: {err}"
        );
    }
}
