//! Shared by the reader targets: save the input under a name, read it every way.

use std::path::Path;

/// Writes `data` to a per-process temporary file named `name` and reads it through `open`,
/// the chunk stream and `load_scene`; errors are fine, panics are findings.
pub fn read_everything(name: &str, data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("omnicloud-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(name);
    if std::fs::write(&path, data).is_err() {
        return;
    }
    read(&path);
}

fn read(path: &Path) {
    if let Ok(reader) = omnicloud::io::open(path) {
        for chunk in reader.chunks(4096) {
            if chunk.is_err() {
                break;
            }
        }
    }
    let _ = omnicloud::io::load_scene(path, &omnicloud::io::LoadOptions::default());
}
