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

use tempfile::NamedTempFile;

use super::OutputError;

/// Temporary files that exist right now, so that an interrupt handler can remove them
/// ([`remove_staged_files`]): the handler exits the process, so no destructor runs.
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
        .filter(|t| {
            if t.is_dir() {
                // A worker may add a file while the folder is emptied: try again.
                (0..3).any(|_| std::fs::remove_dir_all(t).is_ok())
            } else {
                std::fs::remove_file(t).is_ok()
            }
        })
        .count();
    std::mem::forget(temps);
    removed
}

/// A fully written temporary file waiting to be renamed onto its destination.
///
/// Dropping it without [`StagedFile::commit`] deletes the temporary file.
#[derive(Debug)]
pub struct StagedFile {
    /// Deletes the file when dropped. Declared before `registered`: fields drop in order, so
    /// the file is gone before the registry forgets it.
    temp: NamedTempFile,
    registered: Registered,
    dest: PathBuf,
}

/// A temporary file's entry in the registry, removed when dropped.
#[derive(Debug)]
struct Registered(PathBuf);

impl Drop for Registered {
    fn drop(&mut self) {
        forget_temp(&self.0);
    }
}

/// Where a temporary for `dest` goes (its folder, `.` for a bare name) and the name it
/// starts from (`dest`'s file name, `output` when it has none).
fn temp_place(dest: &Path) -> (&Path, String) {
    let dir = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = dest
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_owned());
    (dir, name)
}

/// Random characters in a temporary file's name, between `.NAME.` and `.tmp`.
const TEMP_RANDOM: usize = 6;

/// The file name that a temporary file named `temp` (`.NAME.XXXXXX.tmp`) was staged for, or
/// `None` for any other name. A process killed outright (`kill -9`, power loss) leaves its
/// temporary files behind: a caller that knows no live process writes `NAME` removes them.
pub fn staged_for(temp: &str) -> Option<&str> {
    let inner = temp.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (name, random) = inner.rsplit_once('.')?;
    (!name.is_empty()
        && random.len() == TEMP_RANDOM
        && random.bytes().all(|b| b.is_ascii_alphanumeric()))
    .then_some(name)
}

/// A hidden temporary file next to `dest` (same directory, so the rename is atomic), named
/// in the registry before it exists, so an interrupt at any point finds it.
fn create_temp(dest: &Path) -> std::io::Result<NamedTempFile> {
    let (dir, name) = temp_place(dest);
    let prefix = format!(".{name}.");
    tempfile::Builder::new()
        .prefix(&prefix)
        .rand_bytes(TEMP_RANDOM)
        .suffix(".tmp")
        .make_in(dir, |path| {
            live_temps().push(path.to_path_buf());
            // A plain create (not `NamedTempFile::new_in`, which makes the file private to its
            // owner) so that the committed output gets the usual permissions.
            File::create_new(path).inspect_err(|_| forget_temp(path))
        })
}

impl StagedFile {
    /// Writes a temporary file next to `dest` with `write`; on any error the temporary file is
    /// removed and the error returned.
    pub fn create(
        dest: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
    ) -> Result<StagedFile, OutputError> {
        Self::create_with(dest, write)
    }

    /// [`StagedFile::create`] for a writer with its own error type.
    pub fn create_with<E: From<OutputError>>(
        dest: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
    ) -> Result<StagedFile, E> {
        let temp = create_temp(dest).map_err(|source| OutputError::Io {
            path: dest.to_path_buf(),
            action: "creating temporary file",
            source,
        })?;
        // From here on, dropping `staged` removes the temporary file on every early return.
        let staged = StagedFile {
            registered: Registered(temp.path().to_path_buf()),
            temp,
            dest: dest.to_path_buf(),
        };
        let io_error = |source| OutputError::Io {
            path: dest.to_path_buf(),
            action: "writing",
            source,
        };
        let mut writer = BufWriter::new(staged.temp.as_file().try_clone().map_err(io_error)?);
        write(&mut writer)?;
        writer.flush().map_err(io_error)?;
        Ok(staged)
    }

    /// The final file name.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Renames the temporary file onto the destination and returns the destination.
    pub fn commit(self) -> Result<PathBuf, OutputError> {
        let StagedFile {
            temp,
            registered,
            dest,
        } = self;
        // On failure the temporary file comes back in the error and is deleted with it.
        let result = temp.persist(&dest).map_err(|e| e.error);
        drop(registered);
        match result {
            Ok(_) => Ok(dest),
            Err(source) => Err(OutputError::Io {
                path: dest,
                action: "renaming temporary file onto",
                source,
            }),
        }
    }
}

/// A hidden working folder next to a destination (so its files share the destination's
/// disk), removed with its contents when dropped and by [`remove_staged_files`] on an
/// interrupt.
#[derive(Debug)]
pub struct ScratchDir {
    path: PathBuf,
    /// Forgets the folder in the registry once dropped (after [`Drop::drop`] removed it).
    _registered: Registered,
}

impl ScratchDir {
    /// Creates `.NAME.LABEL.XXXXXX.tmp/` in `dest`'s folder.
    ///
    /// # Errors
    /// [`OutputError::Io`] when the folder cannot be created.
    pub fn next_to(dest: &Path, label: &str) -> Result<ScratchDir, OutputError> {
        let (dir, name) = temp_place(dest);
        let made = tempfile::Builder::new()
            .prefix(&format!(".{name}.{label}."))
            .suffix(".tmp")
            .make_in(dir, |path| {
                live_temps().push(path.to_path_buf());
                std::fs::create_dir(path).inspect_err(|_| forget_temp(path))
            })
            .map_err(|source| OutputError::Io {
                path: dest.to_path_buf(),
                action: "creating a working folder next to",
                source,
            })?;
        // Removal is ours (on drop), not tempfile's.
        let path = made.path().to_path_buf();
        std::mem::forget(made);
        Ok(ScratchDir {
            _registered: Registered(path.clone()),
            path,
        })
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_temporary_file_names_what_it_was_staged_for() {
        let dir = tempfile::tempdir().unwrap();
        let dest = dir.path().join("frame_000003.png");
        let staged = StagedFile::create(&dest, |w| {
            w.write_all(b"x").map_err(|source| OutputError::Io {
                path: dest.clone(),
                action: "writing",
                source,
            })
        })
        .unwrap();
        let temp = staged
            .temp
            .path()
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        assert_eq!(staged_for(&temp), Some("frame_000003.png"), "{temp}");
        for other in [
            "frame_000003.png",
            ".frame.png.tmp",
            ".a.b.c.tmp",
            "..abcdef.tmp",
        ] {
            assert_eq!(staged_for(other), None, "{other}");
        }
    }
}
