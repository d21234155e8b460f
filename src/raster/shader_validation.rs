//! Every pipeline's composed WGSL parses and validates as the device would take it (a test
//! here, above the pipelines, since each pipeline composes its source from `shaders`).

use wgpu::naga::valid::{Capabilities, ValidationFlags, Validator};

/// Parses and validates `source` as the device would (every capability allowed, so the
/// 64-bit splat validates too).
fn validate(name: &str, source: &str) {
    let module = wgpu::naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
}

#[test]
fn every_composed_shader_parses_and_validates() {
    validate("expand + splat", &super::expand::source(true));
    validate("expand", &super::expand::source(false));
    validate("imposter", &super::imposter::source(false));
    validate("imposter + keyed", &super::imposter::source(true));
    validate("deferred shading", &super::splat_shade::source());
    validate("tile resolve", &super::tile_resolve::source());
    validate("probe", &super::probe::source());
}
