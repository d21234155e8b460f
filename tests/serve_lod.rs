//! `serve` of an indexed scan through its level of detail: the render thread draws the COPC
//! file's octree nodes its camera needs, kept in a node cache across requests. With every node
//! selected, the pairs it answers, per click (`/api/render`) and per live frame, are bit for
//! bit those of the scan kept resident, as they are at a pixel with the default floor of points
//! (it holds the statue); at a pixel alone they cover nearly the same pixels.
#![cfg(all(feature = "web", feature = "gpu"))]

#[path = "raster_common/gpu.rs"]
mod gpu;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec2;
use indicatif::ProgressBar;
use omnicloud::frame::Frame;
use omnicloud::index::{self, IndexOptions};
use omnicloud::io::Up;
use omnicloud::prepare::lod::NodeRadii;
use omnicloud::prepare::{CameraChoice, PrepareOptions, prepare};
use omnicloud::raster::RasterError;
use omnicloud::render::{ColorMode, RendererKind};
use omnicloud::renderer::ResidentError;
use omnicloud::web::serve::{
    LiveOptions, LiveScan, RenderRequest, RenderThread, ServeError, ServedLod,
};

/// Panorama width per eye of the served pairs.
const WIDTH: u32 = 256;

/// A dense terrestrial scan: a lion statue, 342 k points in a 4 x 6 x 5 m box, indexed into
/// `dir` (radii stored).
fn indexed(dir: &Path) -> PathBuf {
    let copc = dir.join("lion.copc.laz");
    index::index(
        &[PathBuf::from("tests/data/potree/lion_takanawa.laz")],
        &copc,
        &IndexOptions::default(),
        &ProgressBar::hidden(),
    )
    .unwrap();
    copc
}

/// The index served as `serve` serves it, through its level of detail at `(pixels, floor)`
/// when given; `None` (after the GPU rule's notice) without an adapter.
fn start(copc: &Path, lod: Option<(f64, u64)>) -> Option<(RenderThread, Arc<LiveScan>)> {
    let prepared = prepare(
        copc,
        &PrepareOptions {
            camera: CameraChoice::Center,
            ..PrepareOptions::default()
        },
        &ProgressBar::hidden(),
    )
    .unwrap();
    let options = LiveOptions {
        width: WIDTH,
        map_size: 64,
        color: ColorMode::Elevation,
        ..LiveOptions::default()
    };
    let mut scan = LiveScan::new(copc, prepared.scene, options).unwrap();
    if let Some((pixels, floor)) = lod {
        scan = scan.with_lod(ServedLod {
            path: copc.to_path_buf(),
            up: Up::Z,
            radii: NodeRadii::File,
            pixels,
            floor,
            budget: 1 << 30,
        });
    }
    let scan = Arc::new(scan);
    match RenderThread::start(scan.clone(), RendererKind::Raster) {
        Ok(thread) => Some((thread, scan)),
        Err(ServeError::Resident(ResidentError::Raster(e @ RasterError::NoAdapter))) => {
            gpu::require_or_skip(&format!("serve has no adapter: {e}"));
            None
        }
        Err(e) => panic!("serve could not start: {e}"),
    }
}

/// Cameras on a walk past the statue, 1.5 m to 3 m from it, heights given.
fn clicks(scan: &LiveScan) -> Vec<RenderRequest> {
    let first = RenderRequest::default_at(&scan.limits);
    let at = |x: f64, y: f64, z: f64, seq: u64| RenderRequest {
        xy: DVec2::new(x, y),
        z: Some(z),
        seq,
        ..first.clone()
    };
    vec![
        at(-4.8, 1.2, 0.3, 1),
        at(-4.6, 6.5, 0.6, 2),
        at(-4.5, 6.4, 0.6, 3),
        at(-1.0, 6.5, 0.3, 4),
    ]
}

/// Each request's pair, as `/api/render` answers it (PNG, decoded) and as the live stream
/// takes it (raw).
fn served(thread: &RenderThread, requests: &[RenderRequest]) -> (Vec<Frame>, Vec<Frame>) {
    let clicked = requests
        .iter()
        .map(|r| {
            let png = thread.render(r.clone()).unwrap().png;
            Frame::from_rgba8(image::load_from_memory(&png).unwrap().to_rgba8())
        })
        .collect();
    let queue = thread.queue();
    let live = requests
        .iter()
        .map(|r| {
            let live = RenderRequest {
                client: "live".into(),
                ..r.clone()
            };
            queue.submit(live, WIDTH).recv().unwrap().unwrap().frame
        })
        .collect();
    (clicked, live)
}

/// Covered pixels in both over covered pixels in either, over all frames.
fn coverage_iou(a: &[Frame], b: &[Frame]) -> f64 {
    let (mut both, mut either) = (0u64, 0u64);
    for (fa, fb) in a.iter().zip(b) {
        for (ca, cb) in fa.color.iter().zip(&fb.color) {
            let (ia, ib) = (ca[3] != 0, cb[3] != 0);
            both += u64::from(ia && ib);
            either += u64::from(ia || ib);
        }
    }
    both as f64 / either.max(1) as f64
}

#[test]
fn every_node_serves_the_resident_pairs_and_a_pixel_alone_nearly_the_same_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let copc = indexed(dir.path());
    let Some((off, scan)) = start(&copc, None) else {
        return;
    };
    let requests = clicks(&scan);
    let (want_clicked, want_live) = served(&off, &requests);
    drop(off);
    for frame in &want_clicked {
        assert!(frame.coverage_count() > (WIDTH * WIDTH / 20) as usize);
    }

    // Every node (a zero threshold), and a pixel with the default floor, which holds the
    // whole statue.
    for lod in [(0.0, 0), (1.0, omnicloud::prepare::lod::LOD_FLOOR_POINTS)] {
        let (every, _) = start(&copc, Some(lod)).unwrap();
        let (clicked, live) = served(&every, &requests);
        drop(every);
        for (i, (got, want)) in clicked.iter().zip(&want_clicked).enumerate() {
            assert!(
                got.color == want.color,
                "{lod:?}: click {i} differs from --lod off"
            );
        }
        for (i, (got, want)) in live.iter().zip(&want_live).enumerate() {
            assert!(
                got.color == want.color,
                "{lod:?}: live frame {i} differs from --lod off"
            );
        }
    }

    let (default, _) = start(&copc, Some((1.0, 0))).unwrap();
    let (clicked, live) = served(&default, &requests);
    let clicks_iou = coverage_iou(&clicked, &want_clicked);
    let live_iou = coverage_iou(&live, &want_live);
    eprintln!("coverage IoU at 1 px: clicks {clicks_iou:.4}, live {live_iou:.4}");
    // Measured 0.906 for both: at 256 px a pixel spans the root's spacing 1.5 m away, so the
    // walk reads the top of the octree only.
    assert!(clicks_iou > 0.89, "clicks: coverage IoU {clicks_iou}");
    assert!(live_iou > 0.89, "live: coverage IoU {live_iou}");
    assert!(clicks_iou < 1.0, "the level of detail read every node");
}
