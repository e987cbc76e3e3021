//! Writing an output file all or nothing: into a temporary file beside it, renamed into place
//! only when the write succeeded, and removed otherwise, so a failure never leaves a partial
//! file under the real name.

use std::path::{Path, PathBuf};

use crate::error::RuntimeError;

/// Calls `write` with a temporary path in `path`'s folder, then renames it to `path`.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), RuntimeError> {
    let err = |reason: String| RuntimeError::Output {
        file: path.to_path_buf(),
        reason,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(err(format!("folder {} does not exist", dir.display())));
    }
    let name = path.file_name().ok_or_else(|| err("no file name".into()))?;
    let tmp: PathBuf = dir.join(format!(".{}.partial", name.to_string_lossy()));
    let result = write(&tmp)
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| e.to_string()))
        .map_err(err);
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
