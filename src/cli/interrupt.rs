//! Ctrl-C during a render or a tour: no partial output left behind.

/// On Ctrl-C (or SIGTERM): delete staged output files and exit with status 130 and one line.
/// Outputs are written to a temporary name and renamed when complete, so after this no
/// partial file remains. Installing twice (tests, library use) is harmless.
pub(super) fn install_interrupt_handler() {
    let _ = ctrlc::set_handler(|| {
        let removed = crate::output::remove_staged_files();
        eprintln!(
            "omnicloud: interrupted; no partial output left ({removed} unfinished file(s) removed)"
        );
        std::process::exit(130);
    });
}
