//! What a benchmark run does: which modes, how many frames, what size.

use crate::projection::Stereo;
use crate::projection::depth_map::DepthMap;

use super::mode::BenchMode;

/// Options of `omnicloud bench` that are not render settings.
///
/// The CLI maps `--width W` to [`BenchConfig::width`], `--stereo` (with `--ipd`, the
/// `--pole-merge` options and `--ods-offset`) to [`BenchConfig::stereo`],
/// `--modes a,b` to [`BenchConfig::modes`] (labels as [`BenchMode::parse`] reads them),
/// `--warmup N` / `--frames N` to the frame counts, `--no-mono-baseline` to
/// [`BenchConfig::mono_baseline`], `--out DIR` to the output folder given to
/// `write_outputs`, and `--suite DIR` to `run_suite`.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchConfig {
    /// Image width per eye; `None` keeps the base settings' (or the suite manifest's) width.
    pub width: Option<u32>,
    /// Mono/ODS override, pole merging and ODS offset included; `None` keeps the base
    /// settings' (or the manifest's) stereo.
    pub stereo: Option<Stereo>,
    /// `--depth-map` (with ODS); `None` keeps the base settings' map.
    pub depth_map: Option<DepthMap>,
    /// Rasterizer modes to measure, in table order.
    pub modes: Vec<BenchMode>,
    /// Frames rendered and discarded before timing (pipeline creation, caches, clocks).
    pub warmup_frames: usize,
    /// Frames timed per mode; the report gives their median.
    pub timed_frames: usize,
    /// With a stereo setting, also time a mono frame of the same camera and mode after each
    /// stereo frame (warm-up included), for the stereo / mono ratio measured in one run.
    pub mono_baseline: bool,
}

impl Default for BenchConfig {
    /// All ten modes, 2 warm-up frames, median of 5, stereo timed against mono.
    fn default() -> Self {
        BenchConfig {
            width: None,
            stereo: None,
            depth_map: None,
            modes: BenchMode::all(),
            warmup_frames: 2,
            timed_frames: 5,
            mono_baseline: true,
        }
    }
}

impl BenchConfig {
    /// The small, quick configuration tests use: one warm-up frame, median of 3.
    pub fn quick() -> Self {
        BenchConfig {
            warmup_frames: 1,
            timed_frames: 3,
            ..BenchConfig::default()
        }
    }
}
