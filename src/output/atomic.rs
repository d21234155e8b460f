//! Atomic file writes: write to a temporary file in the destination's directory, then rename.
//!
//! A rename within one directory replaces the destination in one step, so a render that is
//! interrupted (killed, out of disk, encoder error) leaves either the old file or none, never
//! a truncated one. This protects against the process stopping, not against power loss (no
//! fsync).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use super::OutputError;

/// Distinguishes temporary files of one process written at the same time.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Temporary files that exist right now, so that an interrupt handler can remove them
/// ([`remove_staged_files`]).
static LIVE_TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live_temps() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves a valid Vec: keep using it.
    LIVE_TEMPS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn forget_temp(temp: &Path) {
    live_temps().retain(|t| t != temp);
}

/// Deletes every temporary output file this process has staged and not yet committed, for an
/// interrupt (Ctrl-C) handler that exits right after. Returns how many were removed.
///
/// The registry stays locked afterwards, so no thread can stage a new file between this call
/// and the exit (a writer that tries blocks until the process ends).
pub fn remove_staged_files() -> usize {
    let mut temps = live_temps();
    let removed = temps
        .drain(..)
        .filter(|t| std::fs::remove_file(t).is_ok())
        .count();
    std::mem::forget(temps);
    removed
}

/// A fully written temporary file waiting to be renamed onto its destination.
///
/// Dropping it without [`StagedFile::commit`] deletes the temporary file.
#[derive(Debug)]
pub struct StagedFile {
    temp: PathBuf,
    dest: PathBuf,
    committed: bool,
}

/// The temporary name for `dest`: hidden, in the same directory, unique per process and call.
fn temp_path(dest: &Path) -> PathBuf {
    let name = dest
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_owned());
    let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    dest.with_file_name(format!(".{name}.{}-{n}.tmp", std::process::id()))
}

impl StagedFile {
    /// Writes a temporary file next to `dest` with `write`; on any error the temporary file is
    /// removed and the error returned.
    pub fn create(
        dest: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
    ) -> Result<StagedFile, OutputError> {
        let temp = temp_path(dest);
        // Registered before it exists, so an interrupt at any point finds it.
        live_temps().push(temp.clone());
        let file = File::create(&temp).map_err(|source| {
            forget_temp(&temp);
            OutputError::Io {
                path: dest.to_path_buf(),
                action: "creating temporary file",
                source,
            }
        })?;
        // From here on, Drop removes the temporary file on every early return.
        let staged = StagedFile {
            temp,
            dest: dest.to_path_buf(),
            committed: false,
        };
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        writer.flush().map_err(|source| OutputError::Io {
            path: dest.to_path_buf(),
            action: "writing",
            source,
        })?;
        Ok(staged)
    }

    /// The final file name.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Renames the temporary file onto the destination and returns the destination.
    pub fn commit(mut self) -> Result<PathBuf, OutputError> {
        std::fs::rename(&self.temp, &self.dest).map_err(|source| OutputError::Io {
            path: self.dest.clone(),
            action: "renaming temporary file onto",
            source,
        })?;
        self.committed = true;
        forget_temp(&self.temp);
        Ok(self.dest.clone())
    }
}

impl Drop for StagedFile {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the file may already be gone, and Drop cannot report errors.
            let _ = std::fs::remove_file(&self.temp);
            forget_temp(&self.temp);
        }
    }
}

/// Writes `dest` atomically (see the module docs).
pub fn write_atomically(
    dest: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    StagedFile::create(dest, write)?.commit().map(|_| ())
}

/// Commits files that were all staged first, so that an error while writing any of them
/// leaves none of them behind. Returns the destinations in order.
pub fn commit_all(staged: Vec<StagedFile>) -> Result<Vec<PathBuf>, OutputError> {
    staged.into_iter().map(StagedFile::commit).collect()
}
