//! The `omnicloud render` command that draws one frame of a tour again, generated from the
//! tour's parsed command line: every option `render` also takes, with the value the person
//! gave (or its default), read from clap's matches. An option added to both commands is
//! carried without code here; one that only `tour` reads is listed in [`TOUR_ONLY`].

use clap::{ArgAction, ArgMatches, Args};

use super::render_args::RenderArgs;

/// Options of `tour` that `render` also has but that do not pass to a frame's render: the
/// frame places its own camera (`--camera`, `--yaw`, `--pitch`, `--roll` are per pose, and
/// `--height` would refuse a given camera), names its own output, reports nothing, and is
/// one frame of whatever shard it belonged to.
pub const TOUR_ONLY: [&str; 12] = [
    "file",
    "output",
    "camera",
    "yaw",
    "pitch",
    "roll",
    "height",
    "quiet",
    "max_memory",
    "video",
    "shard",
    "shards",
];

/// `omnicloud render SCAN` and `--long=value` for every option of `render` that `tour`
/// matched (given or defaulted), in `render`'s order, then the tour's `--lod`: a COPC file
/// read per camera through the same node selection.
pub fn render_command(scan: &str, tour: &ArgMatches) -> Vec<String> {
    let render = RenderArgs::augment_args(clap::Command::new("render"));
    let mut argv = vec![
        "omnicloud".to_string(),
        "render".to_string(),
        scan.to_string(),
    ];
    for arg in render.get_arguments() {
        let id = arg.get_id().as_str();
        let Some(long) = arg.get_long() else {
            continue;
        };
        if TOUR_ONLY.contains(&id) || id == "lod" {
            continue;
        }
        match arg.get_action() {
            ArgAction::SetTrue => {
                if tour.try_get_one::<bool>(id).ok().flatten() == Some(&true) {
                    argv.push(format!("--{long}"));
                }
            }
            _ => {
                let Ok(Some(raw)) = tour.try_get_raw(id) else {
                    continue;
                };
                let values: Vec<String> = raw.map(|v| v.to_string_lossy().into_owned()).collect();
                argv.push(format!("--{long}={}", values.join(",")));
            }
        }
    }
    // The tour's level of detail (`off` where a caller's options have none).
    let lod = tour
        .try_get_raw("lod")
        .ok()
        .flatten()
        .and_then(|mut v| v.next())
        .map_or("off".into(), |v| v.to_string_lossy().into_owned());
    argv.push(format!("--lod={lod}"));
    argv
}
