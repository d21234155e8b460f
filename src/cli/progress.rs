//! Progress bars on a terminal, silence in scripts; plain lines on request.

use std::io::IsTerminal;
use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle, TermLike};

/// Set to `lines` to print progress as plain lines on stderr even when it is not a terminal
/// (scripts and tests that must see the work start).
pub const PROGRESS_VAR: &str = "OMNICLOUD_PROGRESS";

/// A bar of `len` steps labelled `what`, hidden when `quiet` or stderr is not a terminal
/// (unless [`PROGRESS_VAR`] is `lines`).
pub fn bar(quiet: bool, len: u64, what: &str) -> ProgressBar {
    let lines = std::env::var_os(PROGRESS_VAR).is_some_and(|v| v == "lines");
    if quiet || !(lines || std::io::stderr().is_terminal()) {
        return ProgressBar::hidden();
    }
    let pb = if lines {
        let target = ProgressDrawTarget::term_like_with_hz(Box::new(Lines::default()), 4);
        ProgressBar::with_draw_target(Some(len), target)
    } else {
        ProgressBar::new(len)
    };
    pb.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({eta})")
            .expect("the template is valid")
            .progress_chars("=> "),
    );
    pb.set_message(what.to_string());
    pb
}

/// A draw target that prints each redraw of the bar as one line on stderr.
#[derive(Debug, Default)]
struct Lines(Mutex<String>);

impl TermLike for Lines {
    fn width(&self) -> u16 {
        100
    }
    fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.write_str(s)?;
        self.flush()
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.0.lock().map_or(Ok(()), |mut b| {
            b.push_str(s);
            Ok(())
        })
    }
    fn clear_line(&self) -> std::io::Result<()> {
        Ok(())
    }
    fn flush(&self) -> std::io::Result<()> {
        if let Ok(mut b) = self.0.lock() {
            let line = b.trim();
            if !line.is_empty() {
                eprintln!("{line}");
            }
            b.clear();
        }
        Ok(())
    }
}
