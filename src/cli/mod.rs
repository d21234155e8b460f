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

/// The message of `error` and its causes, joined by `: ` as anyhow's `{:#}` joins them, but
/// without a cause whose text the message already holds: many errors name their source in
/// their own text, and the line would otherwise say it twice.
pub fn error_message(error: &anyhow::Error) -> String {
    let mut message = error.to_string();
    for cause in error.chain().skip(1) {
        let text = cause.to_string();
        if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
    }
    message
}

/// Says, through `say`, what the load of `file` means for the user: the units note of its
/// coordinate system ([`crate::prepare::units_note`]) and the points dropped for NaN/inf
/// coordinates.
fn say_load_notes(file: &std::path::Path, report: &crate::io::LoadReport, say: &impl Fn(String)) {
    if let Some(note) = crate::prepare::units_note(&report.info) {
        say(format!("note: {note}"));
    }
    if report.dropped_nonfinite > 0 {
        say(format!(
            "warning: dropped {} points with NaN/inf coordinates from {}",
            report.dropped_nonfinite,
            file.display()
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("reading {path}: {source}")]
    struct Quoting {
        path: &'static str,
        #[source]
        source: std::io::Error,
    }

    #[test]
    fn a_cause_is_said_once() {
        let io = || std::io::Error::other("disk on fire");
        let quoting = anyhow::Error::new(Quoting {
            path: "a.las",
            source: io(),
        });
        assert_eq!(
            format!("{quoting:#}"),
            "reading a.las: disk on fire: disk on fire"
        );
        assert_eq!(error_message(&quoting), "reading a.las: disk on fire");
        // A context that does not quote its cause keeps it.
        let wrapped = anyhow::Error::new(io()).context("loading the scan");
        assert_eq!(error_message(&wrapped), "loading the scan: disk on fire");
    }
}
