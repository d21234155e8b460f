//! `omnicloud serve`'s live server on the sample scan, started in process on a free port for
//! the HTTP and browser tests.
#![allow(dead_code)]

#[path = "../raster_common/gpu.rs"]
mod gpu;

use std::path::{Path, PathBuf};

use omnicloud::Scene;
use omnicloud::raster::RasterError;
use omnicloud::renderer::ResidentError;
use omnicloud::web::Running;
use omnicloud::web::serve::{LiveOptions, LiveScan, LiveServer, ServeError, StreamOptions};

/// Under the tree canopy west of the bridge, where much of the scan lies above 45° latitude.
pub const UNDER_TREES: (f64, f64) = (636291.76, 849305.2);

/// The sample scan the server shows.
pub fn sample() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz")
}

/// The sample counts in international feet.
pub const FEET_PER_METRE: f64 = 1.0 / 0.3048;

/// A live server of `scene` (the sample, prepared) at panorama `width` with a 256-pixel map,
/// reading the page's IPD in metres as `serve` does for the sample's feet; `None` (after the
/// GPU rule's notice) without an adapter.
pub fn start_live(scene: Scene, width: u32) -> Option<Running> {
    start_live_streaming(scene, width, StreamOptions::default())
}

/// [`start_live`] with the live stream run as `stream` says.
pub fn start_live_streaming(scene: Scene, width: u32, stream: StreamOptions) -> Option<Running> {
    let options = LiveOptions {
        width,
        map_size: 256,
        per_metre: FEET_PER_METRE,
        metres_per_unit: Some(0.3048),
        ..LiveOptions::default()
    };
    let scan = LiveScan::new(&sample(), scene, options).unwrap();
    match LiveServer::bind("127.0.0.1", 0, scan) {
        Ok(server) => Some(server.with_stream(stream).spawn()),
        Err(ServeError::Resident(ResidentError::Raster(e @ RasterError::NoAdapter))) => {
            gpu::require_or_skip(&format!("serve has no adapter: {e}"));
            None
        }
        Err(e) => panic!("serve could not start: {e}"),
    }
}
