//! Shared by the reader targets: save the input under a name, read it every way.

use std::path::{Path, PathBuf};

/// A per-process scratch folder, on a memory file system when there is one (the readers
/// take paths, and a write to `/dev/shm` costs microseconds, not a disk flush).
pub fn scratch_dir() -> PathBuf {
    let base = Path::new("/dev/shm");
    let base = if base.is_dir() {
        base.to_path_buf()
    } else {
        std::env::temp_dir()
    };
    let dir = base.join(format!("omnicloud-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// Writes `data` to the scratch file `name`; `None` when it cannot.
#[allow(dead_code)]
pub fn scratch_file(name: &str, data: &[u8]) -> Option<PathBuf> {
    let path = scratch_dir().join(name);
    std::fs::write(&path, data).ok().map(|()| path)
}

/// Writes `data` to a scratch file named `name` and reads it through `open`, the chunk
/// stream and `load_scene`; errors are fine, panics are findings.
#[allow(dead_code)]
pub fn read_everything(name: &str, data: &[u8]) {
    if let Some(path) = scratch_file(name, data) {
        read(&path);
    }
}

fn read(path: &Path) {
    let _ = omnicloud::io::read_info(path);
    if let Ok(reader) = omnicloud::io::open(path) {
        for chunk in reader.chunks(4096) {
            if chunk.is_err() {
                break;
            }
        }
    }
    let _ = omnicloud::io::load_scene(path, &omnicloud::io::LoadOptions::default());
}
