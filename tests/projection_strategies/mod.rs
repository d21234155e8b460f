//! Proptest strategies shared by the projection property tests: views, pole-merge profiles
//! and spheres in the places where bounds and projections break.
#![allow(dead_code)]

use glam::DVec3;
use omnicloud::projection::{Camera, Eye, OdsOffset, PoleMerge, PoleMerging, Stereo, View};
use proptest::prelude::*;

/// The camera centre C of every property test.
pub const CENTRE: DVec3 = DVec3::new(3.0, -2.0, 1.5);

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

/// Mono (`None`) or either eye.
pub fn eye() -> impl Strategy<Value = Option<Eye>> {
    prop_oneof![Just(None), Just(Some(Eye::Left)), Just(Some(Eye::Right))]
}

/// The mono view of `camera` for `None`, else that eye of an exact ODS rig with the given
/// per-pole profiles and ipd.
pub fn eye_view(
    camera: Camera,
    eye: Option<Eye>,
    north: PoleMerge,
    south: PoleMerge,
    ipd: f64,
) -> View {
    match eye {
        None => View::mono(camera),
        Some(eye) => {
            let stereo = Stereo::Ods {
                ipd,
                merging: PoleMerging { north, south },
                offset: OdsOffset::Exact,
            };
            View::eye(camera, &stereo, eye)
        }
    }
}

/// A sphere whose centre lies in direction `lam_deg` (longitude from +y towards +x), `phi_deg`
/// (latitude) of the caller's frame at distance `dist`, radius `rel` times the distance.
pub fn sphere_at(lam_deg: f64, phi_deg: f64, dist: f64, rel: f64) -> (DVec3, f64) {
    let (l, p) = (lam_deg.to_radians(), phi_deg.to_radians());
    let dir = DVec3::new(p.cos() * l.sin(), p.cos() * l.cos(), p.sin());
    (dist * dir, dist * rel)
}

/// Uniform over directions, 5 cm to 50 m away, radius 0.3 % to 100 % of the distance.
pub fn anywhere() -> impl Strategy<Value = (DVec3, f64)> {
    (-180.0..180.0f64, -1.0..1.0f64, -1.3..1.7f64, -2.5..0.0f64).prop_map(|(l, z, ld, lr)| {
        sphere_at(l, z.asin().to_degrees(), 10f64.powf(ld), 10f64.powf(lr))
    })
}

/// Within 20° of either pole, 10 cm to 20 m away.
pub fn near_a_pole() -> impl Strategy<Value = (DVec3, f64)> {
    (
        -180.0..180.0f64,
        70.0..90.0f64,
        prop::bool::ANY,
        -1.0..1.3f64,
        -2.0..-0.3f64,
    )
        .prop_map(|(l, p, south, ld, lr)| {
            let p = if south { -p } else { p };
            sphere_at(l, p, 10f64.powf(ld), 10f64.powf(lr))
        })
}

/// Centres between longitudes `lam_lo` and `lam_hi` (degrees), within 60° of the equator,
/// 10 cm to 20 m away.
pub fn between_longitudes(lam_lo: f64, lam_hi: f64) -> impl Strategy<Value = (DVec3, f64)> {
    (lam_lo..lam_hi, -60.0..60.0f64, -1.0..1.3f64, -2.0..-0.5f64)
        .prop_map(|(l, p, ld, lr)| sphere_at(l, p, 10f64.powf(ld), 10f64.powf(lr)))
}

/// 2 cm to 60 cm from the centre: some enclose the eye's circle, some meet the viewing
/// cylinder, most sit where the offset term is largest.
pub fn near_the_eye() -> impl Strategy<Value = (DVec3, f64)> {
    (-180.0..180.0f64, -1.0..1.0f64, 0.02..0.6f64, -1.5..-0.2f64)
        .prop_map(|(l, z, d, lr)| sphere_at(l, z.asin().to_degrees(), d, 10f64.powf(lr)))
}
