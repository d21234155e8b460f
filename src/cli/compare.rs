//! `omnicloud compare`: a test render against a reference, metrics and a heatmap.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

/// Options of `omnicloud compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Reference render (EXR with Z, e.g. from --renderer raytrace).
    pub reference: PathBuf,
    /// Render under test (EXR with Z).
    pub test: PathBuf,
    /// Write the full report as JSON.
    #[arg(long, value_name = "R.json")]
    pub report: Option<PathBuf>,
    /// Write an error heatmap with a legend.
    #[arg(long, value_name = "H.png")]
    pub heatmap: Option<PathBuf>,
}

/// Runs `omnicloud compare` and prints its report.
pub fn run(args: &CompareArgs) -> Result<()> {
    let report = crate::compare::compare_files(
        &args.reference,
        &args.test,
        args.report.as_deref(),
        args.heatmap.as_deref(),
    )?;
    println!("{report}");
    Ok(())
}
