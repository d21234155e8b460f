//! Turns a panic inside a third-party decoder (`las`, `laz`) into a [`LoadError`].
//!
//! The fuzz harness (tests/fuzz_readers.rs) found inputs on which the LAZ decoder trips an
//! internal assertion; a bad file must give an error naming it, not abort the program. The
//! panic message that the default hook would print is suppressed for guarded calls only: a
//! process-wide hook, installed once, skips the message while the current thread is inside
//! [`guarded`] and hands every other panic to the hook that was installed before it.

use super::error::LoadError;
use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Once;

thread_local! {
    /// Depth of [`guarded`] calls on this thread.
    static GUARDED: Cell<u32> = const { Cell::new(0) };
}

static INSTALL: Once = Once::new();

fn install_quiet_hook() {
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if GUARDED.with(Cell::get) == 0 {
                previous(info);
            }
        }));
    });
}

/// Runs `f`, mapping a panic to [`LoadError::DecoderPanic`] for `path` (`what` names the step).
///
/// The decoder's state after a panic is unknown: callers must not use it again.
pub(crate) fn guarded<T>(
    path: &Path,
    what: &'static str,
    f: impl FnOnce() -> Result<T, LoadError>,
) -> Result<T, LoadError> {
    install_quiet_hook();
    GUARDED.with(|g| g.set(g.get() + 1));
    let result = catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(g.get() - 1));
    result.unwrap_or_else(|payload| {
        let detail = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("no message")
            .replace('\n', " ");
        Err(LoadError::DecoderPanic {
            path: path.to_path_buf(),
            what,
            detail,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_error_naming_the_file() {
        let path = Path::new("broken.laz");
        let e = guarded::<()>(path, "decoding points", || panic!("sym < (1 << 16)")).unwrap_err();
        assert_eq!(e.path(), path);
        let text = e.to_string();
        assert!(
            text.contains("broken.laz") && text.contains("sym < (1 << 16)"),
            "{text}"
        );
        assert_eq!(guarded(path, "x", || Ok(3)).unwrap(), 3);
    }
}
