//! The one rule for tests and benches that need a GPU adapter: with `OMNICLOUD_REQUIRE_GPU`
//! set (CI sets it), a missing adapter fails the test with the reason; without it, the test
//! skips with a loud message. Any other GPU error always fails.
#![allow(dead_code)]

use omnicloud::raster::{RasterError, Rasterizer};

/// Set (to anything but `0` or nothing) to make a missing adapter a failure.
pub const REQUIRE_GPU: &str = "OMNICLOUD_REQUIRE_GPU";

/// True when [`REQUIRE_GPU`] is set.
pub fn gpu_required() -> bool {
    std::env::var_os(REQUIRE_GPU).is_some_and(|v| !v.is_empty() && v != "0")
}

/// Handles a missing adapter (or adapter feature), `missing` saying what is missing: panics
/// with it when [`REQUIRE_GPU`] is set, else prints a loud skip notice (the caller then
/// returns).
pub fn require_or_skip(missing: &str) {
    let icd = std::env::var("VK_ICD_FILENAMES")
        .map(|v| format!(" (VK_ICD_FILENAMES={v})"))
        .unwrap_or_default();
    assert!(!gpu_required(), "{REQUIRE_GPU} is set but {missing}{icd}");
    // Straight to the process's stderr: the harness captures `eprintln!` of passing tests,
    // and a skip must be seen.
    use std::io::Write;
    let _ = writeln!(
        std::io::stderr().lock(),
        "\n!!!!!!!! SKIPPED: {missing}{icd}; set {REQUIRE_GPU}=1 to make this fail !!!!!!!!\n"
    );
}

/// The rasterizer; `None` after [`require_or_skip`] when there is no adapter. Any other error
/// (a shader that does not compile, a refused device) panics.
pub fn rasterizer() -> Option<Rasterizer> {
    match Rasterizer::new() {
        Ok(r) => Some(r),
        Err(e @ RasterError::NoAdapter) => {
            require_or_skip(&format!("the rasterizer has no adapter: {e}"));
            None
        }
        Err(e) => panic!("rasterizer unavailable: {e}"),
    }
}
