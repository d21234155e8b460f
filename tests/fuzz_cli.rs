//! Mutation fuzzing of the command line: no argument a user can pass panics the parser, and
//! every rejected value comes back as an error message.

use clap::Parser;
use clap::error::ErrorKind;
use omnicloud::cli::{Cli, parse};
use omnicloud::prepare::{RadiusChoice, Subsample};
use omnicloud::projection::PoleMerge;
use omnicloud::render::{ColorMode, Imposter, Proxy, RendererKind, Shading};
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
    "--max-memory",
    "--subsample",
    "--modes",
    "--suite",
    "--frames",
    "--warmup",
    "--report",
    "--heatmap",
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
        Just("1.5GiB".to_string()),
        Just("quad+sprite,bounds".to_string()),
        Just("18446744073709551616".to_string()),
        Just("cycles:90,90".to_string()),
        "[-a-z0-9:,.eE+ ]{0,24}",
        any::<String>(),
    ]
}

/// A fixed seed so CI runs the same cases every time (`FUZZ_SEED=<u64>` picks others);
/// 5,000 cases unless `PROPTEST_CASES` says otherwise.
fn config() -> ProptestConfig {
    let seed = std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x6f6d_6e69_636c_6f75);
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5000);
    ProptestConfig {
        cases,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        ..ProptestConfig::default()
    }
}

/// Runs `check` on [`config`]'s cases and prints how many ran (`-- --nocapture` shows it).
fn property<S: Strategy>(test: &str, strategy: S, check: impl Fn(S::Value)) {
    let config = config();
    let cases = config.cases;
    proptest::test_runner::TestRunner::new(config)
        .run(&strategy, |value| {
            check(value);
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{test}: {e}"));
    println!("{test}: {cases} cases, no panic");
}

#[test]
fn value_parsers_never_panic() {
    property("value_parsers_never_panic", value(), |s| {
        let _ = parse::vec3(&s);
        let _ = parse::width(&s);
        let _ = parse::ipd(&s);
        let _ = parse::degrees(&s);
        let _ = s.parse::<RadiusChoice>();
        let _ = s.parse::<PoleMerge>();
        let _ = s.parse::<Proxy>();
        let _ = s.parse::<Imposter>();
        let _ = s.parse::<RendererKind>();
        let _ = s.parse::<ColorMode>();
        let _ = s.parse::<Shading>();
        let _ = omnicloud::memory::parse_size(&s);
        let _ = s.parse::<Subsample>();
        let _ = omnicloud::bench::BenchMode::parse(&s);
    });
}

#[test]
fn parsed_pole_merges_give_factors_in_range() {
    property("parsed_pole_merges_give_factors_in_range", value(), |s| {
        if let Ok(p) = s.parse::<PoleMerge>() {
            for k in 0..=90 {
                let f = p.factor((k as f64).to_radians());
                assert!((0.0..=1.0).contains(&f), "{s}: factor {f} at {k}°");
            }
        }
    });
}

/// Fixed leading arguments of each subcommand: the options follow them.
const PREFIXES: &[&[&str]] = &[
    &["render", "in.laz", "-o", "out.png"],
    &["bench", "scene.laz"],
    &["compare", "ref.exr", "test.exr"],
];

#[test]
fn command_lines_never_panic() {
    let strategy = (
        0..PREFIXES.len(),
        proptest::collection::vec((0..OPTIONS.len(), value()), 0..8),
    );
    property("command_lines_never_panic", strategy, |(prefix, picks)| {
        let mut argv = vec!["omnicloud".to_string()];
        argv.extend(PREFIXES[prefix].iter().map(|s| s.to_string()));
        for (k, v) in picks {
            argv.push(OPTIONS[k].to_string());
            argv.push(v);
        }
        if let Err(e) = Cli::try_parse_from(&argv) {
            // A rejection is a usage error that says so; help and version are not rejections.
            let text = e.to_string();
            match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {}
                kind => {
                    assert!(text.starts_with("error: "), "{kind:?}: {text}");
                    assert_eq!(e.exit_code(), 2, "{kind:?}: {text}");
                }
            }
        }
    });
}
