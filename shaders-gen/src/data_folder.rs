//! Where the genera, scenes and views come from: `--data`, else `$NIMBUS_DATA`, else the
//! examples embedded in the binary when it was built (`build.rs`; a build after an edit of
//! `examples/` embeds the edit), written once to a folder of the user's data directory named
//! by their hash. So an installed `nimbus` never looks for the source tree it was built from.
//! When the folder is the problem, the error says which of these chose it.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::error::CliError;

include!(concat!(env!("OUT_DIR"), "/examples.rs"));

/// The marker of an extracted copy of the embedded examples.
const EXTRACTED_MARKER: &str = "nimbus-examples.txt";

/// How the data folder was chosen.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum DataSource {
    Flag,
    Env,
    Embedded,
}

impl fmt::Display for DataSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DataSource::Flag => "--data",
            DataSource::Env => "$NIMBUS_DATA",
            DataSource::Embedded => "the examples built into nimbus",
        })
    }
}

/// The data folder and how it was chosen.
#[derive(Clone, Debug)]
pub(crate) struct DataFolder {
    pub dir: PathBuf,
    pub source: DataSource,
}

impl DataFolder {
    /// The folder `--data` (`flag`), `$NIMBUS_DATA` or the defaults name. A folder the user
    /// named must exist and hold `genera/`; the error names the flag or variable.
    pub(crate) fn find(flag: Option<&Path>) -> Result<DataFolder, CliError> {
        let named = flag
            .map(|p| (p.to_path_buf(), DataSource::Flag))
            .or_else(|| {
                std::env::var_os("NIMBUS_DATA")
                    .filter(|v| !v.is_empty())
                    .map(|v| (PathBuf::from(v), DataSource::Env))
            });
        if let Some((dir, source)) = named {
            if !dir.join("genera").is_dir() {
                let reason = if dir.is_dir() {
                    "it has no genera/ folder".to_string()
                } else {
                    "it is not a folder".to_string()
                };
                return Err(CliError::DataFolder {
                    dir,
                    source_name: source.to_string(),
                    reason,
                });
            }
            return Ok(DataFolder { dir, source });
        }
        Ok(DataFolder {
            dir: extract_embedded()?,
            source: DataSource::Embedded,
        })
    }
}

/// FNV-1a over the embedded files: names the extracted copy, so a newer binary with other
/// examples writes its own.
fn embedded_hash() -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for (name, text) in EXAMPLES {
        for b in name.bytes().chain([0]).chain(text.bytes()).chain([0]) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// The user's data directory: `$XDG_DATA_HOME`, else `~/.local/share`; `None` without a home
/// (a shared temporary folder could be planted by another user).
fn user_data_dir() -> Option<PathBuf> {
    std::env::var_os("XDG_DATA_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".local/share"))
        })
}

/// Writes the embedded files and the marker into `dir`, each flushed to disk, so a marker is
/// never there beside truncated files.
fn write_examples(dir: &Path) -> Result<(), CliError> {
    let files = EXAMPLES.iter().copied().chain([(
        EXTRACTED_MARKER,
        "The example genera, scenes and views built into nimbus, written here on first use. \
         Point --data or NIMBUS_DATA at a copy to edit them.\n",
    )]);
    for (name, text) in files {
        let path = dir.join(name);
        if let Some(p) = path.parent() {
            std::fs::create_dir_all(p).map_err(|e| io(&path, e))?;
        }
        std::fs::File::create(&path)
            .and_then(|mut f| {
                std::io::Write::write_all(&mut f, text.as_bytes())?;
                f.sync_all()
            })
            .map_err(|e| io(&path, e))?;
    }
    Ok(())
}

/// The private copy of the examples this run wrote (no home folder), removed when it ends.
static PRIVATE: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();

/// Removes the private copy of the examples this run wrote, if any: called as `main` returns.
pub(crate) fn remove_private_examples() {
    if let Some(dir) = PRIVATE.get() {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// The embedded examples as a folder, written on first use: into a temporary folder beside
/// it (named after this process, so a killed run's is recognised and removed), then renamed
/// into place. A concurrent first use that renamed first wins; the other copy is dropped (the
/// contents are the same: the name is their hash). Without a home folder, a private temporary
/// folder (a random name, so no other user can plant it) is written once for this run and
/// removed when it ends; a killed run's is removed by the next.
fn extract_embedded() -> Result<PathBuf, CliError> {
    let Some(data) = user_data_dir() else {
        if let Some(dir) = PRIVATE.get() {
            return Ok(dir.clone());
        }
        let temp = std::env::temp_dir();
        remove_dead_extractions(&temp, "nimbus-examples-");
        let tmp = tempfile::Builder::new()
            .prefix(&format!("nimbus-examples-{}-", std::process::id()))
            .tempdir()
            .map_err(|e| io(&temp, e))?;
        write_examples(tmp.path())?;
        let dir = tmp.keep();
        let _ = PRIVATE.set(dir.clone());
        return Ok(dir);
    };
    let dir = data.join(format!(
        "nimbus/examples-{}-{:016x}",
        env!("CARGO_PKG_VERSION"),
        embedded_hash()
    ));
    if dir.join(EXTRACTED_MARKER).is_file() {
        return Ok(dir);
    }
    let parent = dir.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| io(parent, e))?;
    remove_dead_extractions(parent, ".nimbus-examples-");
    let tmp = parent.join(format!(".nimbus-examples-{}", std::process::id()));
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(|e| io(&tmp, e))?;
    }
    let written = write_examples(&tmp);
    let moved = written.and_then(|()| match std::fs::rename(&tmp, &dir) {
        Ok(()) => Ok(()),
        Err(_) if dir.join(EXTRACTED_MARKER).is_file() => Ok(()),
        Err(e) => Err(io(&dir, e)),
    });
    let _ = std::fs::remove_dir_all(&tmp);
    moved.map(|()| dir)
}

/// Removes `<prefix><pid>` and `<prefix><pid>-…` folders of processes that are no longer
/// running (where `/proc` tells; elsewhere they are left).
fn remove_dead_extractions(parent: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(prefix)
            .and_then(|p| p.split('-').next())
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
        if is_dir
            && Path::new("/proc").is_dir()
            && !Path::new("/proc").join(pid.to_string()).exists()
        {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

fn io(path: &Path, e: std::io::Error) -> CliError {
    CliError::from(nimbus_output::OutputError::Io {
        action: "write the built-in examples to",
        path: path.to_path_buf(),
        source: e,
    })
}
