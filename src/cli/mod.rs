//! The command-line edge: parses arguments, runs a subcommand, reports errors with `anyhow`.

pub mod args;
pub mod parse;

use anyhow::{Result, bail};

pub use args::{Cli, Command};

/// Runs one parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Info { .. } | Command::Render(_) => {
            bail!("this command is not available yet: the renderers are being built")
        }
        Command::Compare(args) => {
            let report = crate::compare::compare_files(
                &args.reference,
                &args.test,
                args.report.as_deref(),
                args.heatmap.as_deref(),
            )?;
            println!("{report}");
            Ok(())
        }
    }
}
