//! Writes a large synthetic LAS (or LAZ) scan for out-of-core tests and measurements
//! ([`omnicloud::synthetic::write_ground_las`]).
//!
//! `cargo run --release --example gen_big_las -- OUT.las|OUT.laz POINTS`

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, points] = args.as_slice() else {
        bail!("usage: gen_big_las OUT.las|OUT.laz POINTS");
    };
    let out = PathBuf::from(out);
    let points: u64 = points
        .replace('_', "")
        .parse()
        .with_context(|| format!("'{points}' is not a point count"))?;
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
