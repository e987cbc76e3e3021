//! What is at an output path before Nimbus writes there. Outputs are written beside their
//! destination and renamed over it, so only a plain file (or, for a folder of outputs, a plain
//! folder) can be replaced that way: a symbolic link would be replaced itself rather than what
//! it points to, and a FIFO or a device is not a file at all (reading one to look for Nimbus's
//! signature would block). Each is refused up front with the reason.

use std::io::ErrorKind;
use std::path::{Path, PathBuf};

use crate::error::OutputError;

/// What an output path holds now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Found {
    Nothing,
    File,
    Folder,
}

/// What is at `path`, without following a link there; a link, FIFO, socket or device is
/// refused.
pub(crate) fn found_at(path: &Path) -> Result<Found, OutputError> {
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        // A file where a folder above should be: nothing is here; the folder check says why.
        Err(e) if missing(&e) => return Ok(Found::Nothing),
        Err(e) => return Err(OutputError::io("inspect", path)(e)),
    };
    let kind = meta.file_type();
    if kind.is_symlink() {
        let target = std::fs::read_link(path).unwrap_or_default();
        let state = match std::fs::metadata(path) {
            Ok(_) => "",
            Err(e) if e.kind() == ErrorKind::NotFound => ", which does not exist",
            Err(_) => ", which cannot be reached (a loop of links?)",
        };
        return Err(OutputError::IsLink {
            path: path.to_path_buf(),
            target,
            state,
        });
    }
    if kind.is_dir() {
        return Ok(Found::Folder);
    }
    if kind.is_file() {
        return Ok(Found::File);
    }
    Err(OutputError::NotPlain {
        path: path.to_path_buf(),
        kind: special_kind(&kind),
    })
}

#[cfg(unix)]
fn special_kind(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a FIFO (named pipe)"
    } else if kind.is_socket() {
        "a socket"
    } else if kind.is_block_device() || kind.is_char_device() {
        "a device"
    } else {
        "not a plain file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "not a plain file"
}

/// The nearest folder at or above `folder` that exists (following links, as writing into it
/// will), for an output at `path`: `folder` itself when `must_exist`. A file where a folder
/// should be, or a path that cannot be reached, is refused.
pub(crate) fn existing_folder(
    path: &Path,
    folder: &Path,
    must_exist: bool,
) -> Result<PathBuf, OutputError> {
    let mut at = folder.to_path_buf();
    loop {
        match std::fs::metadata(&at) {
            Ok(m) if m.is_dir() => return Ok(at),
            Ok(_) => {
                return Err(OutputError::NotAFolder {
                    path: path.to_path_buf(),
                    folder: at,
                });
            }
            Err(e) if missing(&e) && !must_exist => {
                at = match at.parent() {
                    Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                    _ => PathBuf::from("."),
                };
            }
            Err(e) if missing(&e) => {
                return Err(OutputError::NoFolder {
                    path: path.to_path_buf(),
                    folder: at,
                });
            }
            Err(e) => return Err(OutputError::io("reach the folder of", path)(e)),
        }
    }
}

/// Nothing at the path: it does not exist, or a file stands where one of its folders should.
fn missing(e: &std::io::Error) -> bool {
    matches!(e.kind(), ErrorKind::NotFound | ErrorKind::NotADirectory)
}
