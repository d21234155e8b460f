//! Command lines (NUL-separated arguments) and every option value parser.
#![no_main]

use clap::Parser;
use omnicloud::cli::{Cli, parse};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for value in text.split('\0') {
        let _ = parse::vec3(value);
        let _ = parse::positive_metres(value);
        let _ = parse::ipd(value);
        let _ = parse::degrees(value);
        let _ = parse::width(value);
        let _ = parse::radius(value);
        let _ = parse::pole_merge(value);
        let _ = parse::proxy(value);
        let _ = parse::imposter(value);
        let _ = parse::renderer(value);
        let _ = parse::color(value);
        let _ = parse::shading(value);
    }
    let args = std::iter::once("omnicloud").chain(text.split('\0'));
    if let Ok(cli) = Cli::try_parse_from(args) {
        // Parsing succeeded: rendering it would touch files, so only format it.
        let _ = format!("{cli:?}");
    }
});
