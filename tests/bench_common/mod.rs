//! Shared by the bench and suite tests: the GPU-or-skip rule.

use omnicloud::raster::{RasterError, Rasterizer};

/// A rasterizer, or `None` (with a loud message) when this machine has no GPU adapter.
/// Under CI (env `CI` set) a missing adapter fails the test: CI installs lavapipe.
pub fn rasterizer_or_skip(test: &str) -> Option<Rasterizer> {
    match Rasterizer::new() {
        Ok(r) => Some(r),
        Err(RasterError::NoAdapter) if std::env::var_os("CI").is_none() => {
            eprintln!(
                "\n*** SKIPPED {test}: no GPU adapter (install mesa-vulkan-drivers); this test FAILS under CI ***\n"
            );
            None
        }
        Err(e) => panic!("{test}: no rasterizer: {e}"),
    }
}
