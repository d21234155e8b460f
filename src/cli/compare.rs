//! `omnicloud compare`: a test render against a reference, metrics and a heatmap.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

/// Options of `omnicloud compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Reference render (EXR with Z, e.g. from --renderer raytrace, or PNG), or an E57
    /// file's image as FILE.e57#image:N: the scanner's panorama resampled to the test's size
    /// as seen from its station (compare a `render --camera station:N` of that scan).
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
    let (file, parts) = crate::io::e57::select::split(&args.reference)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.reference.display()))?;
    // The scanner's image, resampled, is written where compare_files reads a reference.
    let staged = tempfile::tempdir()?;
    let reference = match parts.image {
        Some(index) => {
            let test = crate::output::read_image(&args.test)?;
            let image = crate::compare::photo::station_reference(&file, index, test.width)?;
            let stem = file.file_stem().unwrap_or_default().to_string_lossy();
            let path = staged.path().join(format!("{stem}_image_{index}.png"));
            image.save(&path)?;
            path
        }
        None => args.reference.clone(),
    };
    let report = crate::compare::compare_files(
        &reference,
        &args.test,
        args.report.as_deref(),
        args.heatmap.as_deref(),
    )?;
    println!("{report}");
    Ok(())
}
