//! The stability suite as a benchmark: every manifest entry × every mode, one table of error
//! and time, and a chart of error by latitude band per mode.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use indicatif::ProgressBar;
use serde::{Deserialize, Serialize};

use crate::io::{LoadOptions, load_scene};
use crate::raster::Rasterizer;
use crate::suite::{ManifestEntry, load_manifest};

use super::BenchError;
use super::chart::{BandSeries, write_band_chart};
use super::config::BenchConfig;
use super::mode::BenchMode;
use super::outputs::{create_dir, write_csv_file, write_file};
use super::report::{BenchReport, percent};
use super::runner::run_bench_with;

/// One suite entry's benchmark.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SuiteEntryResult {
    /// The manifest entry.
    pub entry: ManifestEntry,
    /// Its benchmark.
    pub report: BenchReport,
}

/// The whole suite's results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SuiteReport {
    /// The adapter every entry ran on.
    pub adapter: String,
    /// One result per manifest entry, in manifest order.
    pub entries: Vec<SuiteEntryResult>,
}

/// Loads one manifest entry's scene with its camera as the local origin, and its settings.
pub fn load_entry(
    dir: &Path,
    entry: &ManifestEntry,
) -> Result<(crate::Scene, crate::render::RenderSettings), BenchError> {
    let path = dir.join(&entry.file);
    let options = LoadOptions {
        origin: Some(entry.camera_world()),
        ..LoadOptions::default()
    };
    let (scene, _) = load_scene(&path, &options).map_err(|source| BenchError::Load {
        path: path.clone(),
        source,
    })?;
    let settings = entry.settings(scene.origin)?;
    Ok((scene, settings))
}

/// Benchmarks every entry of `dir/suite.json` on one rasterizer. `config.width` and
/// `config.stereo` override every entry's when set. `progress` advances once per entry.
pub fn run_suite(
    dir: &Path,
    config: &BenchConfig,
    progress: &ProgressBar,
) -> Result<SuiteReport, BenchError> {
    let manifest = load_manifest(dir)?;
    let rasterizer = Rasterizer::new()?;
    progress.set_length(manifest.scenes.len() as u64);
    progress.set_position(0);
    let hidden = ProgressBar::hidden();
    let mut entries = Vec::with_capacity(manifest.scenes.len());
    for entry in manifest.scenes {
        progress.set_message(entry.name.clone());
        let (scene, settings) = load_entry(dir, &entry)?;
        let report = run_bench_with(&rasterizer, &entry.name, &scene, &settings, config, &hidden)?;
        entries.push(SuiteEntryResult { entry, report });
        progress.inc(1);
    }
    Ok(SuiteReport {
        adapter: rasterizer.adapter_name().to_string(),
        entries,
    })
}

/// Modes present in any entry, in first-seen order.
fn modes_of(report: &SuiteReport) -> Vec<BenchMode> {
    let mut modes: Vec<BenchMode> = Vec::new();
    for e in &report.entries {
        for m in &e.report.modes {
            if !modes.contains(&m.mode) {
                modes.push(m.mode);
            }
        }
    }
    modes
}

/// Coverage mismatch per latitude band summed over every entry, one series per mode.
pub fn band_series(report: &SuiteReport) -> Vec<BandSeries> {
    modes_of(report)
        .into_iter()
        .map(|mode| {
            let mut sums: Vec<(f64, u64, u64)> = Vec::new();
            for m in report.entries.iter().filter_map(|e| e.report.mode(mode)) {
                for (k, b) in m.accuracy.bands.iter().enumerate() {
                    if sums.len() <= k {
                        sums.push((0.5 * (b.lat_lo_deg + b.lat_hi_deg), 0, 0));
                    }
                    sums[k].1 += b.mismatched;
                    sums[k].2 += b.pixels;
                }
            }
            BandSeries {
                label: mode.label(),
                values: sums
                    .into_iter()
                    .map(|(lat, bad, all)| {
                        (
                            lat,
                            if all == 0 {
                                0.0
                            } else {
                                bad as f64 / all as f64
                            },
                        )
                    })
                    .collect(),
            }
        })
        .collect()
}

/// The suite as Markdown: scene × mode → coverage mismatch and median frame time.
pub fn suite_markdown(report: &SuiteReport) -> String {
    let modes = modes_of(report);
    let mut out = String::new();
    let first = report.entries.first().map(|e| &e.report);
    let _ = writeln!(
        out,
        "## Stability suite\n\n- adapter: {}\n- frame time: median of {} frames after {} warm-up frames, measured by {}\n- cell: coverage mismatch against the ray tracer / median frame time\n",
        report.adapter,
        first.map_or(0, |r| r.timed_frames),
        first.map_or(0, |r| r.warmup_frames),
        first.map_or("–", |r| r.timing().describe()),
    );
    out.push_str("| scene | points | size |");
    for m in &modes {
        let _ = write!(out, " {} |", m.label());
    }
    out.push_str("\n|---|---:|---|");
    for _ in &modes {
        out.push_str("---:|");
    }
    out.push('\n');
    for e in &report.entries {
        let r = &e.report;
        let _ = write!(
            out,
            "| {} | {} | {}×{} {} |",
            e.entry.name, r.points, r.width, r.height, r.stereo
        );
        for &m in &modes {
            let text = r.mode(m).map_or_else(
                || "–".to_string(),
                |x| {
                    format!(
                        "{} / {:.2} ms",
                        percent(x.accuracy.coverage_mismatch),
                        x.frame_ms
                    )
                },
            );
            let _ = write!(out, " {text} |");
        }
        out.push('\n');
    }
    out
}

/// The files a suite run wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteFiles {
    /// Full report as JSON.
    pub json: PathBuf,
    /// One row per entry and mode.
    pub csv: PathBuf,
    /// Scene × mode table.
    pub markdown: PathBuf,
    /// Error by latitude band per mode, PNG.
    pub bands_png: PathBuf,
    /// Error by latitude band per mode, SVG.
    pub bands_svg: PathBuf,
}

/// Writes `suite.json`, `suite.csv`, `suite.md` and `suite_bands.{png,svg}` into `dir`.
pub fn write_suite_outputs(report: &SuiteReport, dir: &Path) -> Result<SuiteFiles, BenchError> {
    create_dir(dir)?;
    let json = dir.join("suite.json");
    let text = serde_json::to_vec_pretty(report).map_err(|source| BenchError::Json {
        path: json.clone(),
        source,
    })?;
    write_file(&json, &text)?;
    let csv = dir.join("suite.csv");
    write_csv_file(&csv, report.entries.iter().map(|e| &e.report))?;
    let markdown = dir.join("suite.md");
    write_file(&markdown, suite_markdown(report).as_bytes())?;
    let bands_png = dir.join("suite_bands.png");
    let bands_svg = dir.join("suite_bands.svg");
    write_band_chart(
        &format!(
            "stability suite: error by latitude ({})",
            report.adapter.split(" (").next().unwrap_or(&report.adapter)
        ),
        &band_series(report),
        &bands_png,
        &bands_svg,
    )?;
    Ok(SuiteFiles {
        json,
        csv,
        markdown,
        bands_png,
        bands_svg,
    })
}
