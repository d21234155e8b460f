//! The command-line edge: parses arguments, runs a subcommand, reports errors with `anyhow`.

pub mod args;
pub mod parse;

use anyhow::{Result, bail};

pub use args::{Cli, Command};

/// Runs one parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Info { .. } | Command::Render(_) | Command::Compare(_) => {
            bail!("this command is not available yet: the renderers are being built")
        }
    }
}
