//! Regenerates the stability suite: `cargo run --example gen_scenes -- data/scenes`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

/// Regenerates the stability suite's scenes.
#[derive(Parser)]
struct Args {
    /// Folder to write the scenes into.
    #[arg(default_value = "data/scenes")]
    dir: PathBuf,
}

fn main() -> ExitCode {
    let Args { dir } = Args::parse();
    match omnicloud::suite::write_suite(&dir) {
        Ok(paths) => {
            for p in paths {
                let size = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
                println!("{size:>9}  {}", p.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
