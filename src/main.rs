use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = omnicloud::cli::Cli::parse();
    match omnicloud::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
