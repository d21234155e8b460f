//! Interrupting a render once its work has started: with `OMNICLOUD_PROGRESS=lines` the CLI
//! prints its progress bar as lines on stderr, and the first line of the given stage is the
//! cue for Ctrl-C, so the signal lands mid-render on a machine of any speed.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// What an interrupted run printed and how it ended.
#[derive(Debug)]
pub struct Interrupted {
    /// Exit status.
    pub status: ExitStatus,
    /// Every stderr line.
    pub lines: Vec<String>,
    /// Index in `lines` of the progress line that cued the signal (`None`: it never came and
    /// no signal was sent).
    pub cue: Option<usize>,
    /// Time from the signal to the process's exit.
    pub exit_after: Duration,
}

impl Interrupted {
    /// All of stderr.
    pub fn stderr(&self) -> String {
        self.lines.join("\n")
    }
}

/// True for a line of the progress bar (`{msg:>12} [{bar:40}] {pos}/{len} ({eta})`) of the
/// stage named `stage`, or of any stage when `stage` is empty.
pub fn is_progress(line: &str, stage: &str) -> bool {
    let Some((msg, rest)) = line.trim().split_once(" [") else {
        return false;
    };
    let bar_ok = rest
        .split_once("] ")
        .is_some_and(|(bar, count)| bar.len() == 40 && count.contains('/'));
    let msg_ok = if stage.is_empty() {
        msg.chars().all(|c| c.is_ascii_lowercase() || c == ' ')
    } else {
        msg == stage
    };
    bar_ok && msg_ok
}

/// Runs `command` with progress lines on stderr, sends SIGINT right after the first progress
/// line of `stage`, and waits for the process to end.
pub fn interrupt_at_progress(mut command: Command, stage: &str) -> Interrupted {
    let mut child = command
        .env("OMNICLOUD_PROGRESS", "lines")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("omnicloud starts");
    let stderr = BufReader::new(child.stderr.take().expect("stderr is piped"));
    let mut lines = Vec::new();
    let mut cue = None;
    let mut signalled = Instant::now();
    for line in stderr.lines() {
        let line = line.expect("stderr is text");
        if cue.is_none() && is_progress(&line, stage) {
            let killed = Command::new("kill")
                .args(["-INT", &child.id().to_string()])
                .status()
                .expect("kill runs");
            assert!(killed.success(), "kill -INT failed");
            signalled = Instant::now();
            cue = Some(lines.len());
        }
        lines.push(line);
    }
    let status = child.wait().expect("omnicloud ends");
    Interrupted {
        status,
        lines,
        cue,
        exit_after: signalled.elapsed(),
    }
}

/// The run was interrupted mid-render: the signal was sent, the process stopped promptly
/// with status 130, and after the cue it printed nothing but progress and one line saying it
/// was interrupted.
pub fn assert_interrupted(run: &Interrupted) {
    let stderr = run.stderr();
    let cue = run
        .cue
        .unwrap_or_else(|| panic!("no progress line came before the end: {stderr}"));
    assert_eq!(run.status.code(), Some(130), "stderr: {stderr}");
    assert!(
        run.exit_after < Duration::from_secs(10),
        "the render did not stop promptly ({:.1?})",
        run.exit_after
    );
    let after: Vec<&String> = run.lines[cue..]
        .iter()
        .filter(|l| !is_progress(l, ""))
        .collect();
    assert_eq!(after.len(), 1, "one line after the interrupt: {stderr}");
    assert!(after[0].contains("interrupted"), "{stderr}");
}
