//! Speed against accuracy (issue 5): renders a scene once with the ray tracer (the reference)
//! and with every rasterizer mode, times the rasterizer (warm-up, then the median of several
//! frames; GPU timestamps where the adapter has them, wall clock otherwise), measures each
//! mode's error against the reference, and writes `bench.json`, `bench.csv`, `bench.md` and a
//! speed/accuracy chart (PNG and SVG). [`run_suite`] does the same for every scene of the
//! stability suite (`data/scenes/suite.json`).

pub mod accuracy;
pub mod chart;
pub mod config;
pub mod mode;
pub mod report;

pub use accuracy::measure;
pub use chart::{ChartError, ChartSummary, pareto_front, speed_accuracy_points};
pub use config::BenchConfig;
pub use mode::BenchMode;
pub use report::{Accuracy, BandAccuracy, BenchReport, ModeResult, ModeStats, TimingKind};
