//! The command-line edge: parses arguments, runs a subcommand, reports errors with `anyhow`.

pub mod args;
mod bench;
pub mod info;
pub mod parse;
mod progress;
mod render;
mod render_guard;
mod render_stream;
mod serve;
mod tour;
mod video;
mod view;

use anyhow::Result;

pub use args::{Cli, Command};
pub use serve::ServeArgs;
pub use tour::TourArgs;
pub use view::ViewerArgs;

/// Runs one parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args),
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
        Command::View(args) => view::run(&args),
        Command::Tour(args) => tour::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Video(args) => video::run(&args),
    }
}

/// Warns, through `say`, of points loading dropped for NaN/inf coordinates.
fn warn_dropped(file: &std::path::Path, report: &crate::io::LoadReport, say: &impl Fn(String)) {
    if report.dropped_nonfinite > 0 {
        say(format!(
            "warning: dropped {} points with NaN/inf coordinates from {}",
            report.dropped_nonfinite,
            file.display()
        ));
    }
}
