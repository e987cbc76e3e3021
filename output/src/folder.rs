//! A folder of outputs (an emitted package), replaced whole: the new folder is written beside
//! the destination under a temporary name, then the old one is moved aside, the new one moved
//! in, and the old one deleted. At every instant the destination is the complete old folder or
//! the complete new one, or (between the two renames) missing with the complete new folder
//! beside it, which the next run moves in.

use std::path::{Path, PathBuf};

use crate::Overwrite;
use crate::destination::{Found, existing_folder, found_at};
use crate::error::OutputError;
use crate::leftovers::{alive, pid_of_folder};
use crate::ownership::{owned, record};

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

/// Checks that `dir` can take a folder of outputs: it is not a file, a link or anything but a
/// plain folder; if it exists and is not empty, Nimbus wrote exactly what it holds (its
/// [`OWNERSHIP_FILE`](crate::OWNERSHIP_FILE) lists every file, unchanged) or `overwrite` is forced; the nearest
/// existing folder above it is writable. Call it before the work; [`replace_folder`] checks
/// again.
pub fn check_folder(dir: &Path, overwrite: Overwrite) -> Result<(), OutputError> {
    // `.`, `..` or `/` cannot be moved aside and replaced: an output folder needs a name.
    if dir.file_name().is_none() {
        return Err(OutputError::NoName {
            path: dir.to_path_buf(),
        });
    }
    match found_at(dir)? {
        Found::File => {
            return Err(OutputError::IsFile {
                path: dir.to_path_buf(),
            });
        }
        Found::Folder if overwrite != Overwrite::Force => {
            let empty = std::fs::read_dir(dir)
                .map_err(OutputError::io("read", dir))?
                .next()
                .is_none();
            if !empty {
                owned(dir).map_err(|why| OutputError::NotOurs {
                    path: dir.to_path_buf(),
                    why,
                })?;
            }
        }
        Found::Folder | Found::Nothing => {}
    }
    let (parent, _) = parent_and_leaf(dir);
    let existing = existing_folder(dir, &parent, false)?;
    tempfile::Builder::new()
        .prefix(&format!(".nimbus-{}-", std::process::id()))
        .suffix(".probe")
        .tempdir_in(&existing)
        .map_err(|e| OutputError::NotWritable {
            path: dir.to_path_buf(),
            folder: existing.clone(),
            reason: e.to_string(),
        })?;
    Ok(())
}

/// Leftovers of dead runs beside `dir`. An old folder moved aside is always deleted, never put
/// back: the run that moved it meant to replace it, and a user who removed `dir` since meant it
/// gone. A new folder is moved in only when `dir` is missing and the new one is complete (its
/// ownership record, written last, is there): the run died between its two renames. Any other
/// new folder is half-written and deleted.
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
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let path = e.path();
        let dead = [&old, &new, &tmp]
            .into_iter()
            .find_map(|prefix| pid_of_folder(&name, prefix))
            .is_some_and(|pid| !alive(pid));
        if !dead {
            continue;
        }
        let complete_new = pid_of_folder(&name, &new).is_some() && owned(&path).is_ok();
        if complete_new && found_at(dir)? == Found::Nothing {
            std::fs::rename(&path, dir)
                .map_err(OutputError::io("move in the complete output of", &path))?;
        } else {
            std::fs::remove_dir_all(&path)
                .map_err(OutputError::io("remove the leftover", &path))?;
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

/// Replaces the folder `dir` by what `fill` writes into the (empty) folder it is given, with
/// the record of what was written ([`OWNERSHIP_FILE`](crate::OWNERSHIP_FILE)) added last. Nothing changes at `dir`
/// when `fill` fails, or when `dir` holds anything Nimbus did not write and `overwrite` is not
/// forced.
pub fn replace_folder<T, E: From<OutputError>>(
    dir: &Path,
    overwrite: Overwrite,
    fill: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, E> {
    check_folder(dir, overwrite)?;
    recover(dir)?;
    check_folder(dir, overwrite)?;
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
        record(&new)?;
        sync_tree(&new)?;
        Ok(v)
    }) {
        Ok(v) => v,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&new);
            return Err(e);
        }
    };
    let had_old = found_at(dir)? != Found::Nothing;
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
