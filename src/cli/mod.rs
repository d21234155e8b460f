//! The command-line edge: parses arguments, runs a subcommand, reports errors with `anyhow`.

pub mod args;
mod bench;
pub mod parse;
mod progress;
mod render;
mod render_guard;
mod render_stream;
mod video;
mod view;

use anyhow::{Context, Result};

use crate::prepare::radius;

pub use args::{Cli, Command};
pub use view::ViewerArgs;

/// Runs one parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Info { file } => info(&file),
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

fn info(file: &std::path::Path) -> Result<()> {
    let reader = crate::io::open(file)?;
    println!("{}", reader.info());
    let (scene, report) = crate::io::load_scene(file, &crate::io::LoadOptions::default())
        .with_context(|| format!("reading the points of {}", file.display()))?;
    if let Some(scale) = report.color_scale {
        let how = match scale {
            crate::io::ColorScale::Direct8 => "8-bit values",
            crate::io::ColorScale::Low8In16 => {
                "0-255 values stored in 16-bit fields (used as they are)"
            }
            crate::io::ColorScale::Full16 => "full 0-65535 range (scaled by 1/256)",
        };
        println!("colour scale:  {how}");
    }
    if report.dropped_nonfinite > 0 {
        println!(
            "dropped:       {} points with NaN/inf coordinates",
            report.dropped_nonfinite
        );
    }
    match radius::median_spacing(&scene) {
        Some(s) => println!(
            "spacing:       {s:.4} m median nearest-neighbour (auto radius {:.4} m)",
            radius::radius_for_spacing(Some(s))
        ),
        None => println!("spacing:       n/a (fewer than two distinct points)"),
    }
    Ok(())
}
