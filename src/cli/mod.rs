//! The command-line edge: parses arguments, runs a subcommand, reports errors with `anyhow`.

mod bench;
pub mod command;
mod compare;
pub mod index;
pub mod info;
mod interrupt;
mod notes;
pub mod options;
pub mod parse;
mod progress;
mod render;
pub mod render_args;
mod render_command;
mod render_guard;
mod render_stream;
mod serve;
mod tour;
mod video;
mod view;

use anyhow::Result;

pub use command::{Cli, Command};
pub use serve::ServeArgs;
pub use tour::TourArgs;
pub use view::ViewerArgs;

/// Runs one command line, as clap matched it against [`Cli`].
///
/// # Errors
/// The command's; the matches not being [`Cli`]'s.
pub fn run(matches: &clap::ArgMatches) -> Result<()> {
    use clap::FromArgMatches;
    let cli = Cli::from_arg_matches(matches)?;
    match cli.command.resolved()? {
        Command::Info(args) => info::run(&args),
        Command::Index(args) => index::run(&args),
        Command::Render(args)
            if args.view.camera
                == Some(crate::prepare::CameraChoice::Station(
                    crate::prepare::StationPick::All,
                )) =>
        {
            tour::run_stations(
                &args,
                matches
                    .subcommand_matches("render")
                    .expect("the render command's matches"),
            )
        }
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::View(args) => view::run(&args),
        Command::Tour(args) => tour::run(
            &args,
            matches
                .subcommand_matches("tour")
                .expect("the tour command's matches"),
        ),
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
