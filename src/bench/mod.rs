//! Speed against accuracy: renders a scene once with the ray tracer (the reference)
//! and with every rasterizer mode, times the rasterizer (warm-up, then the median of several
//! frames; GPU timestamps where the adapter has them, wall clock otherwise), measures each
//! mode's error against the reference, and writes `bench.json`, `bench.csv`, `bench.md` and a
//! speed/accuracy chart (PNG and SVG). [`run_suite`] does the same for every scene of the
//! stability suite (`data/scenes/suite.json`).

pub mod accuracy;
pub mod chart;
pub mod config;
pub mod disparity_chart;
pub mod mode;
pub mod outputs;
pub mod report;
pub mod runner;
pub mod stereo_methods;
pub mod suite_run;

use std::path::PathBuf;

pub use accuracy::measure;
pub use chart::{ChartError, ChartSummary, pareto_front, speed_accuracy_points};
pub use config::BenchConfig;
pub use mode::BenchMode;
pub use outputs::{BenchFiles, write_outputs};
pub use report::{
    Accuracy, BandAccuracy, BenchReport, ModeResult, ModeStats, RegionCount, TimingKind,
};
pub use runner::{bench_settings, run_bench, run_bench_with};
pub use suite_run::{
    SuiteEntryResult, SuiteFiles, SuiteReport, band_series, load_entry, run_suite, suite_markdown,
    write_suite_outputs,
};

/// What can stop a benchmark; every variant names what failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The configuration cannot be run.
    #[error("bad benchmark configuration: {0}")]
    Config(String),
    /// The reference render failed.
    #[error("ray-traced reference failed: {0}")]
    Raytrace(#[from] crate::raytrace::RaytraceError),
    /// The rasterizer failed (including: no GPU adapter).
    #[error("rasterizer failed: {0}")]
    Raster(#[from] crate::raster::RasterError),
    /// A render could not be compared with the reference.
    #[error(transparent)]
    Shape(#[from] accuracy::ShapeMismatch),
    /// A suite scene could not be loaded.
    #[error("cannot load {path}: {source}")]
    Load {
        /// The scene file.
        path: PathBuf,
        /// The cause.
        source: crate::io::LoadError,
    },
    /// The suite manifest is unreadable or invalid.
    #[error(transparent)]
    Suite(#[from] crate::suite::SuiteError),
    /// An output could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A report could not be serialised.
    #[error("cannot write {path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
    /// A chart could not be drawn.
    #[error(transparent)]
    Chart(#[from] ChartError),
}
