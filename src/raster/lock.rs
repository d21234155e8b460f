//! Locking the rasterizer's shared state.

use std::sync::{Mutex, MutexGuard};

/// `m` locked; a panic elsewhere while it was held leaves nothing half-written in the
/// rasterizer's maps or its kept buffers.
pub(super) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}
