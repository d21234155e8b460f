//! The stability suite's guarantees, on every suite scene against the ray-traced reference:
//! `bounds` + `raycast` meets the rasterizer's thresholds (≤ 0.1 % coverage mismatch, depth
//! relative error p99 ≤ 1e-4, unlit colour identical where both hit), and the paper's
//! untessellated `quad` fails them where the suite says it should (poles, seam).

mod raster_common;

use std::path::Path;

use omnicloud::bench::{BenchConfig, BenchMode, SuiteReport, run_suite};
use omnicloud::render::{Imposter, Proxy};

const COVERAGE_MAX: f64 = 1e-3;
const DEPTH_P99_MAX: f64 = 1e-4;

fn suite_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/scenes"))
}

const EXACT: BenchMode = BenchMode {
    proxy: Proxy::Bounds,
    imposter: Imposter::Raycast,
};
const QUAD: BenchMode = BenchMode {
    proxy: Proxy::Quad,
    imposter: Imposter::Sprite,
};

/// The largest quad+sprite coverage mismatch over the entries tagged `tag`, measured in the
/// region where that failure lives (`pole`: the worse polar band; `seam`: the seam columns).
fn worst_quad(report: &SuiteReport, tag: &str) -> (f64, String) {
    report
        .entries
        .iter()
        .filter(|e| e.entry.tags.iter().any(|t| t == tag))
        .map(|e| {
            let a = &e.report.mode(QUAD).unwrap().accuracy;
            let region = match tag {
                "pole" => a.polar_mismatch(),
                _ => a.seam.fraction(),
            };
            (region, e.entry.name.clone())
        })
        .fold((0.0, String::new()), |a, b| if b.0 > a.0 { b } else { a })
}

#[test]
fn bounds_raycast_is_exact_and_quad_fails_at_poles_and_seam() {
    if raster_common::rasterizer().is_none() {
        return;
    }
    let config = BenchConfig {
        modes: vec![EXACT, QUAD],
        warmup_frames: 0,
        timed_frames: 1,
        ..BenchConfig::default()
    };
    let report = run_suite(suite_dir(), &config, &indicatif::ProgressBar::hidden()).unwrap();
    assert!(report.entries.len() >= 13);
    let mut failures = Vec::new();
    for e in &report.entries {
        let a = &e.report.mode(EXACT).unwrap().accuracy;
        let q = &e.report.mode(QUAD).unwrap().accuracy;
        eprintln!(
            "{:<24} bounds+raycast: coverage {:.2e} depth p99 {:.2e} colour {:.2e} | quad+sprite coverage {:.2e} polar {:.2e} seam {:.2e}",
            e.entry.name,
            a.coverage_mismatch,
            a.depth_rel_p99,
            a.color_mismatch,
            q.coverage_mismatch,
            q.polar_mismatch(),
            q.seam.fraction(),
        );
        if a.coverage_mismatch > COVERAGE_MAX
            || a.depth_rel_p99 > DEPTH_P99_MAX
            || a.color_mismatch > 0.0
        {
            failures.push(format!(
                "{}: coverage {:.3e}, depth p99 {:.3e}, colour mismatch {:.3e}",
                e.entry.name, a.coverage_mismatch, a.depth_rel_p99, a.color_mismatch
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "bounds+raycast outside thresholds:\n{}",
        failures.join("\n")
    );

    for tag in ["pole", "seam"] {
        let (worst, name) = worst_quad(&report, tag);
        assert!(
            worst > COVERAGE_MAX,
            "quad+sprite should fail the {tag} scenes, worst is {name} at {worst:.3e}"
        );
    }
}
