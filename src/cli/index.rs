//! `omnicloud index`: scans written once as a COPC file with stored sphere radii.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::ProgressStyle;

use crate::index::{self, IndexOptions};
use crate::memory::{format_size, parse_size, peak_resident};
use crate::prepare::{RadiusChoice, Units};

use super::progress;

/// Options of `omnicloud index`.
#[derive(Debug, Args)]
pub struct IndexArgs {
    /// LAS, LAZ or PLY files (tiles of one survey are indexed together).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The COPC file to write (`.copc.laz`).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Memory the index may use (e.g. `2G`, `512M`).
    #[arg(long, value_name = "SIZE", value_parser = parse_size, default_value = "2G")]
    pub max_memory: u64,
    /// Sphere radius stored with each point: a length (see --units), or `adaptive[:K]` (from
    /// each point's K nearest neighbours); default: the files' own radii, else `adaptive`.
    #[arg(long, value_name = "R")]
    pub radius: Option<RadiusChoice>,
    /// What a --radius length is in: metres, converted to the unit the first file's
    /// coordinate system declares (feet, US survey feet), or the file's own unit.
    #[arg(long, value_enum, ignore_case = true, default_value = "metres")]
    pub units: Units,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `omnicloud index`.
pub fn run(args: &IndexArgs) -> Result<()> {
    super::interrupt::install_interrupt_handler();
    if args.files.iter().any(|f| f == &args.output) {
        bail!(
            "{}: the output is also an input; choose another name",
            args.output.display()
        );
    }
    let bar = progress::bar(args.quiet, 0, "reading");
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:>9} [{bar:40}] {human_pos}/{human_len} points ({per_sec}, {eta} left)",
        )
        .expect("the template is valid")
        .progress_chars("=> "),
    );
    let options = IndexOptions {
        max_memory: args.max_memory,
        radius: args.radius,
        units: args.units,
    };
    let report = index::index(&args.files, &args.output, &options, &bar)
        .with_context(|| format!("indexing into {}", args.output.display()))?;
    bar.finish_and_clear();
    let seconds = report.spill_seconds + report.build_seconds;
    eprintln!(
        "{}: {} points in {} nodes (depth {}), point format {}, {} ({} buckets, largest {} points); \
         {:.1} s ({:.2} M points/s: read {:.1} s, build {:.1} s){}",
        args.output.display(),
        report.points,
        report.nodes,
        report.depth,
        report.point_format,
        format_size(report.bytes),
        report.buckets,
        report.largest_bucket,
        seconds,
        report.points as f64 / seconds.max(1e-9) / 1e6,
        report.spill_seconds,
        report.build_seconds,
        peak_resident()
            .map(|b| format!(", peak memory {}", format_size(b)))
            .unwrap_or_default()
    );
    if report.dropped > 0 {
        eprintln!(
            "{} points left out: a NaN or infinite coordinate",
            report.dropped
        );
    }
    Ok(())
}
