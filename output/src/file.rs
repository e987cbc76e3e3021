//! One output file: checked before the work, then written all or nothing.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::destination::{Found, existing_folder, found_at};
use crate::error::OutputError;
use crate::leftovers::{alive, pid_of_file};
use crate::{Overwrite, Signature};

/// The folder a file path writes into (`.` for a bare file name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The prefix of this process's temporary files.
fn temp_prefix() -> String {
    format!(".nimbus-{}-", std::process::id())
}

/// Checks that `path` can take an output of this kind: its folder exists and is writable, it
/// is not a folder, and if it exists Nimbus wrote it (by `signature`) or `overwrite` is forced.
/// Call it before the work that produces the file; [`write_file`] checks again.
pub fn check_file(
    path: &Path,
    signature: Signature,
    overwrite: Overwrite,
) -> Result<(), OutputError> {
    let found = found_at(path)?;
    if found == Found::Folder {
        return Err(OutputError::IsFolder {
            path: path.to_path_buf(),
        });
    }
    let folder = existing_folder(path, &folder_of(path), true)?;
    // Writable: the same kind of temporary file the write will make.
    tempfile::Builder::new()
        .prefix(&temp_prefix())
        .suffix(".probe")
        .tempfile_in(&folder)
        .map_err(|e| OutputError::NotWritable {
            path: path.to_path_buf(),
            folder: folder.clone(),
            reason: e.to_string(),
        })?;
    if found == Found::File && overwrite != Overwrite::Force {
        signature
            .recognises(path)
            .map_err(|why| OutputError::NotOurs {
                path: path.to_path_buf(),
                why,
            })?;
    }
    Ok(())
}

/// Writes `bytes` to `path`: into a unique temporary file in the same folder, flushed to disk,
/// then renamed over `path`, so `path` always holds a complete file (the old or the new one).
/// Refuses, as [`check_file`] does, to replace a file Nimbus did not write. Temporary files of
/// dead runs in that folder are removed.
pub fn write_file(
    path: &Path,
    signature: Signature,
    overwrite: Overwrite,
    bytes: &[u8],
) -> Result<(), OutputError> {
    check_file(path, signature, overwrite)?;
    let existed = found_at(path)? == Found::File;
    let folder = folder_of(path);
    remove_dead_temporaries(&folder);
    let prefix = temp_prefix();
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".partial");
    // An output is as readable as any file the user writes (0666 less the umask), not
    // tempfile's private 0600.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder
        .tempfile_in(&folder)
        .map_err(OutputError::io("create a temporary file beside", path))?;
    tmp.write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .map_err(OutputError::io("write", path))?;
    // A file that did not exist when checked must not be replaced if one appeared since.
    let persisted = if existed {
        tmp.persist(path).map(|_| ())
    } else {
        tmp.persist_noclobber(path).map(|_| ())
    };
    persisted.map_err(|e| {
        if e.error.kind() == std::io::ErrorKind::AlreadyExists {
            OutputError::NotOurs {
                path: path.to_path_buf(),
                why: "another program created it while Nimbus was writing".into(),
            }
        } else {
            OutputError::Io {
                action: "move the written file into place",
                path: path.to_path_buf(),
                source: e.error,
            }
        }
    })?;
    // The rename itself reaches the disk when the folder is flushed (where a folder can be).
    if let Ok(dir) = std::fs::File::open(&folder) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// Removes `.nimbus-<pid>-*.partial` and `.probe` files of processes no longer running.
fn remove_dead_temporaries(folder: &Path) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = name.ends_with(".partial") || name.ends_with(".probe");
        if let Some(pid) = pid_of_file(&name, ".nimbus-")
            && ours
            && !alive(pid)
        {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Writes an 8-bit RGBA image (`width × height`, rows top to bottom) as a PNG signed as
/// Nimbus's ([`crate::signed_png`]), through [`write_file`].
pub fn write_png(
    path: &Path,
    (width, height): (u32, u32),
    rgba: &[u8],
    overwrite: Overwrite,
) -> Result<(), OutputError> {
    let bytes = crate::signed_png(width, height, rgba).map_err(|reason| OutputError::Io {
        action: "encode the PNG for",
        path: path.to_path_buf(),
        source: std::io::Error::other(reason),
    })?;
    write_file(path, Signature::Png, overwrite, &bytes)
}

/// Writes a linear float image (`width × height`, named channels, rows top to bottom) as an
/// OpenEXR signed as Nimbus's ([`crate::signed_exr`]), through [`write_file`].
pub fn write_exr(
    path: &Path,
    (width, height): (u32, u32),
    channels: &[crate::ExrChannel],
    overwrite: Overwrite,
) -> Result<(), OutputError> {
    let bytes = crate::signed_exr(width, height, channels).map_err(|reason| OutputError::Io {
        action: "encode the EXR for",
        path: path.to_path_buf(),
        source: std::io::Error::other(reason),
    })?;
    write_file(path, Signature::Exr, overwrite, &bytes)
}
