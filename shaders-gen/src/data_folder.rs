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

/// The user's data directory: `$XDG_DATA_HOME`, else `~/.local/share`, else the temporary
/// directory.
fn user_data_dir() -> PathBuf {
    std::env::var_os("XDG_DATA_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".local/share"))
        })
        .unwrap_or_else(std::env::temp_dir)
}

/// The embedded examples as a folder, written on first use: into a temporary folder beside
/// it, then renamed into place. A concurrent first use that renamed first wins; the other copy
/// is dropped (the contents are the same: the name is their hash).
fn extract_embedded() -> Result<PathBuf, CliError> {
    let dir = user_data_dir().join(format!(
        "nimbus/examples-{}-{:016x}",
        env!("CARGO_PKG_VERSION"),
        embedded_hash()
    ));
    if dir.join(EXTRACTED_MARKER).is_file() {
        return Ok(dir);
    }
    let parent = dir.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| io(parent, e))?;
    let tmp = tempfile::Builder::new()
        .prefix(".nimbus-examples-")
        .tempdir_in(parent)
        .map_err(|e| io(parent, e))?;
    for (name, text) in EXAMPLES {
        let path = tmp.path().join(name);
        if let Some(p) = path.parent() {
            std::fs::create_dir_all(p).map_err(|e| io(&path, e))?;
        }
        std::fs::write(&path, text).map_err(|e| io(&path, e))?;
    }
    let marker = tmp.path().join(EXTRACTED_MARKER);
    std::fs::write(
        &marker,
        "The example genera, scenes and views built into nimbus, written here on first use. \
         Point --data or NIMBUS_DATA at a copy to edit them.\n",
    )
    .map_err(|e| io(&marker, e))?;
    let tmp = tmp.keep();
    if let Err(e) = std::fs::rename(&tmp, &dir) {
        let _ = std::fs::remove_dir_all(&tmp);
        if !dir.join(EXTRACTED_MARKER).is_file() {
            return Err(io(&dir, e));
        }
    }
    Ok(dir)
}

fn io(path: &Path, e: std::io::Error) -> CliError {
    CliError::from(nimbus_output::OutputError::Io {
        action: "write the built-in examples to",
        path: path.to_path_buf(),
        source: e,
    })
}
