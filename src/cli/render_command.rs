//! The `omnicloud render` command that draws one frame of a tour again, generated from the
//! tour's parsed command line: every option `render` also takes, with the value the person
//! gave (or its default), read from clap's matches. An option added to both commands is
//! carried without code here; one that only `tour` reads is listed in [`TOUR_ONLY`].

use clap::{ArgAction, ArgMatches, CommandFactory};

use super::command::Cli;

/// Options of `tour` that `render` also has but that do not pass to a frame's render: the
/// frame places its own camera (`--camera`, `--yaw`, `--pitch`, `--roll` are per pose, and
/// `--height` would refuse a given camera), names its own output, and reports nothing.
pub const TOUR_ONLY: [&str; 10] = [
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
];

/// `omnicloud render SCAN` and `--long=value` for every option of `render` that `tour`
/// matched (given or defaulted), in `render`'s order, then `--lod=off`: a tour keeps every
/// point resident, where a COPC file's per-camera level of detail would not.
pub fn render_command(scan: &str, tour: &ArgMatches) -> Vec<String> {
    let cli = Cli::command();
    let render = cli
        .find_subcommand("render")
        .expect("omnicloud has a render command");
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
    argv.push("--lod=off".into());
    argv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::options::ViewArgs;
    use crate::cli::render_args::RenderArgs;
    use crate::cli::{Command, TourArgs};
    use clap::{FromArgMatches, Parser};
    use proptest::prelude::*;

    /// Values each shared option may take, as a person types them (and as both commands
    /// parse them).
    const EXAMPLES: &[(&str, &[&str])] = &[
        ("width", &["256", "1024", "3840"]),
        (
            "color",
            &["auto", "rgb", "elevation", "classification", "flat"],
        ),
        ("shading", &["unlit", "phong", "normal"]),
        ("renderer", &["raster", "raytrace"]),
        ("proxy", &["quad", "static:8", "dynamic", "bounds"]),
        ("imposter", &["raycast", "sprite"]),
        (
            "projection",
            &[
                "equirect",
                "equirect:180,90",
                "hammer",
                "cylindrical:100",
                "fisheye:180",
                "cubemap",
            ],
        ),
        ("stereo", &["none", "ods", "parallel", "cubemap:256"]),
        ("ipd", &["0.064", "0.07", "0.05"]),
        (
            "pole_merge",
            &["off", "comfortable", "cycles:60,75", "marrinan:50,5,2"],
        ),
        ("pole_merge_north", &["off", "cycles:55.5,70"]),
        ("pole_merge_south", &["off", "marrinan:45,0,3"]),
        ("ods_offset", &["exact", "paper"]),
        ("depth_map", &["0.5=1.5,4=6.25", "1=2"]),
        ("radius", &["0.25", "auto", "adaptive:6"]),
        ("up", &["z", "y"]),
        ("classes", &["2,6", "2"]),
        ("drop_classes", &["7,18"]),
        ("returns", &["all", "first", "last"]),
        ("crop", &["-10,5,20,-5", "0,0,1,1"]),
        ("max_distance", &["150", "0.5"]),
        ("units", &["metres", "file"]),
        ("edl", &["1", "0.5"]),
        ("edl_radius", &["2", "1.4"]),
        ("supersample", &["1", "2", "3"]),
        (
            "background",
            &["black", "transparent", "#102030", "10,20,30"],
        ),
        ("quality", &["75", "90"]),
    ];

    /// The options `render_command` carries from a tour: `render`'s long options that
    /// `tour` also has, but for [`TOUR_ONLY`] and `--lod`.
    fn shared_options() -> Vec<String> {
        let cli = Cli::command();
        let tour = cli.find_subcommand("tour").unwrap();
        let render = cli.find_subcommand("render").unwrap();
        render
            .get_arguments()
            .filter(|a| a.get_long().is_some())
            .map(|a| a.get_id().to_string())
            .filter(|id| !TOUR_ONLY.contains(&id.as_str()) && id != "lod")
            .filter(|id| tour.get_arguments().any(|t| t.get_id() == id.as_str()))
            .collect()
    }

    fn tour(extra: &[String]) -> (TourArgs, ArgMatches) {
        let argv = ["omnicloud", "tour", "s.laz", "--path", "p.csv", "-o", "d"]
            .into_iter()
            .map(String::from)
            .chain(extra.iter().cloned());
        let matches = Cli::command().try_get_matches_from(argv).unwrap();
        let tour = matches.subcommand_matches("tour").unwrap().clone();
        match Cli::from_arg_matches_mut(&mut matches.clone())
            .unwrap()
            .command
        {
            Command::Tour(t) => (t, tour),
            _ => panic!("not tour"),
        }
    }

    fn render(argv: &[String]) -> RenderArgs {
        let argv = argv.iter().cloned().chain(["-o".into(), "x.png".into()]);
        match Cli::try_parse_from(argv).unwrap().command {
            Command::Render(r) => r,
            _ => panic!("not render"),
        }
    }

    /// `view` without the options a tour sets per frame.
    fn per_tour(view: &ViewArgs) -> ViewArgs {
        ViewArgs {
            camera: None,
            yaw: 0.0,
            pitch: 0.0,
            roll: 0.0,
            ..view.clone()
        }
    }

    #[test]
    fn every_shared_option_has_examples() {
        let missing: Vec<String> = shared_options()
            .into_iter()
            .filter(|id| !EXAMPLES.iter().any(|(e, _)| e == id))
            .collect();
        assert!(
            missing.is_empty(),
            "render options a tour passes on without examples here: {missing:?}"
        );
        assert!(shared_options().len() >= 25, "{:?}", shared_options());
    }

    #[test]
    fn defaults_are_written_out_and_the_level_of_detail_is_off() {
        let (t, m) = tour(&[]);
        let argv = render_command("s.laz", &m);
        assert_eq!(&argv[..3], ["omnicloud", "render", "s.laz"]);
        assert!(argv.contains(&"--width=3840".to_string()), "{argv:?}");
        assert!(argv.contains(&"--units=metres".to_string()), "{argv:?}");
        assert_eq!(argv.last().map(String::as_str), Some("--lod=off"));
        for tour_only in ["--camera", "--yaw", "--height", "-o", "--output", "--quiet"] {
            assert!(
                !argv.iter().any(|a| a.starts_with(tour_only)),
                "{tour_only} in {argv:?}"
            );
        }
        let r = render(&argv);
        assert_eq!(per_tour(&r.view), per_tour(&t.view));
        assert_eq!(r.lod, crate::prepare::LodChoice::Off);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// parse(serialise(args)) == args: any choice of shared options and values, given to
        /// `tour`, reads back from the generated `render` command as the same settings.
        #[test]
        fn the_render_command_reads_back_as_the_tours_settings(
            options in prop::sample::subsequence(
                (0..EXAMPLES.len()).collect::<Vec<_>>(),
                0..=EXAMPLES.len()
            ),
            values in prop::collection::vec(any::<prop::sample::Index>(), EXAMPLES.len())
        ) {
            let mut extra = Vec::new();
            for (option, value) in options.into_iter().zip(values) {
                let (id, values) = EXAMPLES[option];
                let long = id.replace('_', "-");
                extra.push(format!("--{long}={}", values[value.index(values.len())]));
            }
            let (t, m) = tour(&extra);
            let r = render(&render_command("s.laz", &m));
            prop_assert_eq!(per_tour(&r.view), per_tour(&t.view));
            prop_assert_eq!(&r.draw, &t.draw);
            prop_assert_eq!(&r.look, &t.look);
            prop_assert_eq!(r.quality, t.quality);
        }
    }
}
