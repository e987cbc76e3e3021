//! Which folders are Nimbus's to replace: a folder of outputs carries a record of every file
//! Nimbus wrote into it (name, size, CRC-32), written last, after the files are complete. A
//! folder is replaced only while it holds exactly those files, unchanged. A file of the same
//! name as one Nimbus writes (a user's own `gallery.md`) proves nothing; a file added to a
//! Nimbus folder, or one edited there, is the user's and makes the folder theirs.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::TEXT_MARKER;
use crate::error::OutputError;

/// The record's name inside every folder Nimbus writes whole.
pub const OWNERSHIP_FILE: &str = "nimbus-output.txt";

/// A file as Nimbus wrote it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Written {
    bytes: u64,
    crc32: u32,
}

/// Every file under `dir` (relative paths with `/`), or the first entry that is not a plain
/// file or folder (a link, a FIFO, a device: never something Nimbus writes).
fn files_under(dir: &Path) -> Result<BTreeMap<String, PathBuf>, OutputError> {
    let mut out = BTreeMap::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    while let Some((folder, prefix)) = stack.pop() {
        for e in std::fs::read_dir(&folder).map_err(OutputError::io("read", &folder))? {
            let e = e.map_err(OutputError::io("read", &folder))?;
            let name = format!("{prefix}{}", e.file_name().to_string_lossy());
            let kind = e.file_type().map_err(OutputError::io("read", &e.path()))?;
            if kind.is_dir() {
                stack.push((e.path(), format!("{name}/")));
            } else {
                out.insert(name, e.path());
            }
        }
    }
    Ok(out)
}

/// Size and CRC-32 of the plain file at `path`.
fn written(path: &Path) -> Result<Written, OutputError> {
    let mut file = std::fs::File::open(path).map_err(OutputError::io("read", path))?;
    let mut hasher = crc32fast::Hasher::new();
    let mut buffer = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file
            .read(&mut buffer)
            .map_err(OutputError::io("read", path))?;
        if n == 0 {
            break;
        }
        bytes += n as u64;
        hasher.update(&buffer[..n]);
    }
    Ok(Written {
        bytes,
        crc32: hasher.finalize(),
    })
}

/// Writes the record of every file now under `dir` (a complete new output folder).
pub(crate) fn record(dir: &Path) -> Result<(), OutputError> {
    let mut text = format!(
        "# {TEXT_MARKER} {}: every file of this folder as Nimbus wrote it (CRC-32, bytes, \
         name). Nimbus replaces this folder only while it holds exactly these files.\n",
        env!("CARGO_PKG_VERSION")
    );
    for (name, path) in files_under(dir)? {
        if name == OWNERSHIP_FILE {
            continue;
        }
        let meta = std::fs::symlink_metadata(&path).map_err(OutputError::io("read", &path))?;
        if !meta.is_file() {
            return Err(OutputError::io("record", &path)(std::io::Error::other(
                "only plain files belong in an output folder",
            )));
        }
        let w = written(&path)?;
        text.push_str(&format!("{:08x} {} {name}\n", w.crc32, w.bytes));
    }
    let path = dir.join(OWNERSHIP_FILE);
    std::fs::write(&path, text).map_err(OutputError::io("write", &path))
}

/// The files the record in `dir` lists, or why there is no valid record.
fn recorded(dir: &Path) -> Result<BTreeMap<String, Written>, String> {
    let path = dir.join(OWNERSHIP_FILE);
    match std::fs::symlink_metadata(&path) {
        Ok(m) if m.is_file() => {}
        Ok(_) => return Err(format!("its {OWNERSHIP_FILE} is not a plain file")),
        Err(_) => return Err(format!("it has no {OWNERSHIP_FILE}")),
    }
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("its {OWNERSHIP_FILE} cannot be read: {e}"))?;
    let mut lines = text.lines();
    if !lines.next().is_some_and(|l| l.contains(TEXT_MARKER)) {
        return Err(format!("its {OWNERSHIP_FILE} was not written by Nimbus"));
    }
    let mut out = BTreeMap::new();
    for line in lines {
        let mut parts = line.splitn(3, ' ');
        let parsed = (|| {
            let crc32 = u32::from_str_radix(parts.next()?, 16).ok()?;
            let bytes = parts.next()?.parse().ok()?;
            Some((parts.next()?.to_string(), Written { bytes, crc32 }))
        })();
        let (name, w) =
            parsed.ok_or_else(|| format!("its {OWNERSHIP_FILE} has a damaged line `{line}`"))?;
        out.insert(name, w);
    }
    Ok(out)
}

/// Whether `dir` (an existing, non-empty folder) holds exactly the files Nimbus recorded, as it
/// wrote them; `Err` names what makes it the user's.
pub(crate) fn owned(dir: &Path) -> Result<(), String> {
    let recorded = recorded(dir)?;
    let present = files_under(dir).map_err(|e| e.to_string())?;
    let foreign: Vec<&String> = present
        .keys()
        .filter(|n| *n != OWNERSHIP_FILE && !recorded.contains_key(*n))
        .collect();
    if let Some(first) = foreign.first() {
        let more = match foreign.len() {
            1 => String::new(),
            n => format!(" and {} more", n - 1),
        };
        return Err(format!(
            "it holds {first}{more}, which Nimbus did not write"
        ));
    }
    for (name, w) in &recorded {
        let Some(path) = present.get(name) else {
            // A file Nimbus wrote and the user deleted: nothing of theirs is at stake.
            continue;
        };
        let plain = std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file());
        if !plain || written(path).ok() != Some(*w) {
            return Err(format!("{name} was changed after Nimbus wrote it"));
        }
    }
    Ok(())
}
