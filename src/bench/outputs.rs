//! Writes a benchmark's files: `bench.json`, `bench.csv`, `bench.md`, and the speed/accuracy
//! chart `bench_speed_accuracy.{png,svg}`.

use std::path::{Path, PathBuf};

use super::BenchError;
use super::chart::{ChartSummary, write_speed_accuracy_chart};
use super::report::{BenchReport, markdown, write_csv};

/// The files one benchmark wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchFiles {
    /// Full report as JSON.
    pub json: PathBuf,
    /// One row per mode.
    pub csv: PathBuf,
    /// The Table-1-shaped Markdown table.
    pub markdown: PathBuf,
    /// Speed/accuracy chart, PNG.
    pub chart_png: PathBuf,
    /// Speed/accuracy chart, SVG.
    pub chart_svg: PathBuf,
    /// What the chart drew.
    pub chart: ChartSummary,
}

/// Writes `bytes` to `path`, naming the file on failure.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<(), BenchError> {
    std::fs::write(path, bytes).map_err(|source| BenchError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes the CSV of `reports` to `path`, naming the file on failure.
pub(crate) fn write_csv_file<'a>(
    path: &Path,
    reports: impl IntoIterator<Item = &'a BenchReport>,
) -> Result<(), BenchError> {
    std::fs::File::create(path)
        .and_then(|file| write_csv(file, reports))
        .map_err(|source| BenchError::Write {
            path: path.to_path_buf(),
            source,
        })
}

/// Creates `dir` if needed, naming it on failure.
pub(crate) fn create_dir(dir: &Path) -> Result<(), BenchError> {
    std::fs::create_dir_all(dir).map_err(|source| BenchError::Write {
        path: dir.to_path_buf(),
        source,
    })
}

/// Writes every output of `report` into `dir` (created if missing).
pub fn write_outputs(report: &BenchReport, dir: &Path) -> Result<BenchFiles, BenchError> {
    create_dir(dir)?;
    let json = dir.join("bench.json");
    let text = serde_json::to_vec_pretty(report).map_err(|e| BenchError::Json {
        path: json.clone(),
        source: e,
    })?;
    write_file(&json, &text)?;
    let csv_path = dir.join("bench.csv");
    write_csv_file(&csv_path, [report])?;
    let md = dir.join("bench.md");
    write_file(&md, markdown(report).as_bytes())?;
    let chart_png = dir.join("bench_speed_accuracy.png");
    let chart_svg = dir.join("bench_speed_accuracy.svg");
    let chart = write_speed_accuracy_chart(report, &chart_png, &chart_svg)?;
    Ok(BenchFiles {
        json,
        csv: csv_path,
        markdown: md,
        chart_png,
        chart_svg,
        chart,
    })
}
