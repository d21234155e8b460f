//! Mutation fuzzing of the command line: no argument a user can pass panics the parser, and
//! every rejected value comes back as an error message.

use clap::Parser;
use omnicloud::cli::{Cli, parse};
use proptest::prelude::*;

const OPTIONS: &[&str] = &[
    "--width",
    "--camera",
    "--yaw",
    "--stereo",
    "--ipd",
    "--pole-merge",
    "--pole-merge-north",
    "--pole-merge-south",
    "--radius",
    "--color",
    "--shading",
    "--depth",
    "--anaglyph",
    "--renderer",
    "--proxy",
    "--imposter",
    "--ods-offset",
    "--up",
    "-o",
    "--quiet",
    "--separate-eyes",
];

/// Values near the valid ones, so mutations reach deep into the parsers.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("3840".to_string()),
        Just("marrinan:45,0,3".to_string()),
        Just("cycles:60,75".to_string()),
        Just("static:16".to_string()),
        Just("1,2,3".to_string()),
        Just("NaN".to_string()),
        Just("-inf".to_string()),
        Just("1e400".to_string()),
        Just("static:4294967296".to_string()),
        Just("marrinan:,,".to_string()),
        Just("cycles:90,90".to_string()),
        "[-a-z0-9:,.eE+ ]{0,24}",
        any::<String>(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(5000))]

    #[test]
    fn value_parsers_never_panic(s in value()) {
        let _ = parse::vec3(&s);
        let _ = parse::width(&s);
        let _ = parse::ipd(&s);
        let _ = parse::degrees(&s);
        let _ = parse::radius(&s);
        let _ = parse::pole_merge(&s);
        let _ = parse::proxy(&s);
        let _ = parse::imposter(&s);
        let _ = parse::renderer(&s);
        let _ = parse::color(&s);
        let _ = parse::shading(&s);
    }

    #[test]
    fn parsed_pole_merges_give_factors_in_range(s in value()) {
        if let Ok(p) = parse::pole_merge(&s) {
            for k in 0..=90 {
                let f = p.factor((k as f64).to_radians());
                prop_assert!((0.0..=1.0).contains(&f), "{s}: factor {f} at {k}°");
            }
        }
    }

    #[test]
    fn render_command_lines_never_panic(
        picks in proptest::collection::vec((0..OPTIONS.len(), value()), 0..8)
    ) {
        let mut argv = vec!["omnicloud".to_string(), "render".into(), "in.laz".into(), "-o".into(), "out.png".into()];
        for (k, v) in picks {
            argv.push(OPTIONS[k].to_string());
            argv.push(v);
        }
        match Cli::try_parse_from(&argv) {
            Ok(_) => {}
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
