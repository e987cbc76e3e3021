//! A folder of outputs (an emitted package), replaced whole: the new folder is written beside
//! the destination under a temporary name, then the old one is moved aside, the new one moved
//! in, and the old one deleted. At every instant the destination is the complete old folder or
//! the complete new one, or (between the two renames) missing with the complete old folder
//! aside, which the next run puts back.

use std::path::{Path, PathBuf};

use crate::Overwrite;
use crate::error::OutputError;
use crate::leftovers::{alive, pid_of_folder};

fn parent_and_leaf(dir: &Path) -> (PathBuf, String) {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let leaf = dir
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    (parent, leaf)
}

/// Checks that `dir` can take a folder of outputs: it is not a file; if it exists and is not
/// empty, it holds `marker` (Nimbus wrote it) or `overwrite` is forced; the nearest existing
/// folder above it is writable. Call it before the work; [`replace_folder`] checks again.
pub fn check_folder(dir: &Path, marker: &str, overwrite: Overwrite) -> Result<(), OutputError> {
    // `.`, `..` or `/` cannot be moved aside and replaced: an output folder needs a name.
    if dir.file_name().is_none() {
        return Err(OutputError::NoName {
            path: dir.to_path_buf(),
        });
    }
    if dir.exists() && !dir.is_dir() {
        return Err(OutputError::IsFile {
            path: dir.to_path_buf(),
        });
    }
    if dir.is_dir() && overwrite != Overwrite::Force {
        let empty = std::fs::read_dir(dir)
            .map_err(OutputError::io("read", dir))?
            .next()
            .is_none();
        if !empty && !dir.join(marker).is_file() {
            return Err(OutputError::NotOurs {
                path: dir.to_path_buf(),
                why: format!("a folder that is not empty and has no {marker}"),
            });
        }
    }
    let (parent, _) = parent_and_leaf(dir);
    let mut existing = parent.as_path();
    while !existing.exists() {
        existing = match existing.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
    }
    if !existing.is_dir() {
        return Err(OutputError::NoFolder {
            path: dir.to_path_buf(),
            folder: existing.to_path_buf(),
        });
    }
    tempfile::Builder::new()
        .prefix(&format!(".nimbus-{}-", std::process::id()))
        .suffix(".probe")
        .tempdir_in(existing)
        .map_err(|e| OutputError::NotWritable {
            path: dir.to_path_buf(),
            folder: existing.to_path_buf(),
            reason: e.to_string(),
        })?;
    Ok(())
}

/// Leftovers of dead runs beside `dir`: new folders never moved in are deleted; an old folder
/// moved aside is put back when `dir` is missing (the run died between its two renames), and
/// deleted otherwise.
fn recover(dir: &Path) -> Result<(), OutputError> {
    let (parent, leaf) = parent_and_leaf(dir);
    let Ok(entries) = std::fs::read_dir(&parent) else {
        return Ok(());
    };
    let (new, old, tmp) = (
        format!(".{leaf}.nimbus-new-"),
        format!(".{leaf}.nimbus-old-"),
        format!(".{leaf}.nimbus-tmp-"),
    );
    let mut olds = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let path = e.path();
        if let Some(pid) = pid_of_folder(&name, &old) {
            if !alive(pid) {
                olds.push(path);
            }
        } else if let Some(pid) = pid_of_folder(&name, &new).or_else(|| pid_of_folder(&name, &tmp))
            && !alive(pid)
        {
            std::fs::remove_dir_all(&path)
                .map_err(OutputError::io("remove the leftover", &path))?;
        }
    }
    for path in olds {
        if dir.exists() {
            std::fs::remove_dir_all(&path)
                .map_err(OutputError::io("remove the leftover", &path))?;
        } else {
            std::fs::rename(&path, dir)
                .map_err(OutputError::io("restore the previous output from", &path))?;
        }
    }
    Ok(())
}

/// Flushes every file under `dir` to disk, so the folder moved into place is complete on disk
/// and not only in the page cache.
fn sync_tree(dir: &Path) -> Result<(), OutputError> {
    for e in std::fs::read_dir(dir)
        .map_err(OutputError::io("read", dir))?
        .flatten()
    {
        let path = e.path();
        if path.is_dir() {
            sync_tree(&path)?;
        } else {
            // Write access: Windows refuses to flush a file opened for reading only.
            std::fs::OpenOptions::new()
                .write(true)
                .open(&path)
                .and_then(|f| f.sync_all())
                .map_err(OutputError::io("flush", &path))?;
        }
    }
    Ok(())
}

/// Replaces the folder `dir` by what `fill` writes into the (empty) folder it is given, which
/// must include `marker`. Nothing changes at `dir` when `fill` fails, or when `dir` is a
/// folder Nimbus did not write and `overwrite` is not forced.
pub fn replace_folder<T, E: From<OutputError>>(
    dir: &Path,
    marker: &str,
    overwrite: Overwrite,
    fill: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, E> {
    check_folder(dir, marker, overwrite)?;
    recover(dir)?;
    check_folder(dir, marker, overwrite)?;
    let (parent, leaf) = parent_and_leaf(dir);
    std::fs::create_dir_all(&parent).map_err(OutputError::io("create", &parent))?;
    let pid = std::process::id();
    let new = parent.join(format!(".{leaf}.nimbus-new-{pid}"));
    let old = parent.join(format!(".{leaf}.nimbus-old-{pid}"));
    if new.exists() {
        std::fs::remove_dir_all(&new).map_err(OutputError::io("remove", &new))?;
    }
    std::fs::create_dir(&new).map_err(OutputError::io("create", &new))?;
    let value = match fill(&new).and_then(|v| {
        sync_tree(&new)?;
        Ok(v)
    }) {
        Ok(v) => v,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&new);
            return Err(e);
        }
    };
    let had_old = dir.exists();
    if had_old && let Err(e) = std::fs::rename(dir, &old) {
        let _ = std::fs::remove_dir_all(&new);
        return Err(OutputError::io("move the previous output aside", dir)(e).into());
    }
    if let Err(e) = std::fs::rename(&new, dir) {
        if had_old {
            let _ = std::fs::rename(&old, dir);
        }
        let _ = std::fs::remove_dir_all(&new);
        return Err(OutputError::io("move the new output into place", dir)(e).into());
    }
    if let Ok(d) = std::fs::File::open(&parent) {
        let _ = d.sync_all();
    }
    if had_old {
        // A failure here leaves only a leftover the next run removes.
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(value)
}
