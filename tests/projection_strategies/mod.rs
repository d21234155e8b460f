//! Proptest strategies shared by the projection property tests.

use omnicloud::projection::PoleMerge;
use proptest::prelude::*;

/// Any pole-merge profile: off, the presets, or random Marrinan and Cycles parameters.
pub fn profile() -> impl Strategy<Value = PoleMerge> {
    prop_oneof![
        Just(PoleMerge::Off),
        Just(PoleMerge::COMFORTABLE),
        Just(PoleMerge::CYCLES_DEFAULT),
        (1.0..90.0f64, 0.0..1.0f64, 0.5..4.0f64).prop_map(|(s, f, k)| PoleMerge::Marrinan {
            start_deg: s,
            end_deg: s * f,
            exponent: k,
        }),
        (0.0..89.0f64, 0.01..1.0f64).prop_map(|(from, f)| PoleMerge::Cycles {
            from_deg: from,
            to_deg: from + (90.0 - from) * f,
        }),
    ]
}
