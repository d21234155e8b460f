//! Writes a large synthetic LAS (or LAZ) scan for out-of-core tests and measurements
//! ([`omnicloud::synthetic::write_ground_las`]).
//!
//! `cargo run --release --example gen_big_las -- OUT.las|OUT.laz POINTS`

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressDrawTarget};

/// Writes a large synthetic LAS (or LAZ) scan.
#[derive(Parser)]
struct Args {
    /// The file to write; `.laz` compresses.
    out: PathBuf,
    /// Points to write (`_` separators allowed: 50_000_000).
    #[arg(value_parser = point_count)]
    points: u64,
}

fn point_count(s: &str) -> Result<u64, String> {
    s.replace('_', "")
        .parse()
        .map_err(|_| format!("'{s}' is not a point count"))
}

fn main() -> Result<()> {
    let Args { out, points } = Args::parse();
    let progress = ProgressBar::with_draw_target(Some(points), ProgressDrawTarget::stderr());
    omnicloud::synthetic::write_ground_las(&out, points, &progress)
        .with_context(|| format!("writing {}", out.display()))?;
    eprintln!(
        "wrote {points} points to {} (sphere radius for a closed surface: {:.4} m)",
        out.display(),
        omnicloud::synthetic::ground_radius(points)
    );
    Ok(())
}
