//! What can go wrong writing an output: each error names the path, and what to do.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Error)]
pub enum OutputError {
    #[error(
        "{}: exists and was not written by Nimbus ({why}); pass --force to replace it, or \
         choose another path",
        path.display()
    )]
    NotOurs { path: PathBuf, why: String },

    #[error(
        "{}: is a symbolic link to {}{state}; Nimbus writes a complete file beside it and renames \
         it into place, which would replace the link, not what it points to: give the target's \
         own path, or remove the link",
        path.display(),
        target.display()
    )]
    IsLink {
        path: PathBuf,
        target: PathBuf,
        state: &'static str,
    },

    #[error("{}: is {kind}, not a file Nimbus can replace; give the path of a plain file", path.display())]
    NotPlain { path: PathBuf, kind: &'static str },

    #[error(
        "{}: {} is a file, not a folder; give a path inside a folder",
        path.display(),
        folder.display()
    )]
    NotAFolder { path: PathBuf, folder: PathBuf },

    #[error("{}: is a folder; give the path of a file", path.display())]
    IsFolder { path: PathBuf },

    #[error("{}: is a file; give the path of a folder", path.display())]
    IsFile { path: PathBuf },

    #[error(
        "{}: an output folder needs a name of its own (it is replaced whole); give one, e.g. \
         `out`",
        path.display()
    )]
    NoName { path: PathBuf },

    #[error(
        "{}: its folder {} does not exist; create it first",
        path.display(),
        folder.display()
    )]
    NoFolder { path: PathBuf, folder: PathBuf },

    #[error("{}: cannot write in {}: {reason}", path.display(), folder.display())]
    NotWritable {
        path: PathBuf,
        folder: PathBuf,
        reason: String,
    },

    #[error("{}: cannot {action}: {source}", path.display())]
    Io {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl OutputError {
    pub(crate) fn io<'a>(
        action: &'static str,
        path: &'a std::path::Path,
    ) -> impl FnOnce(std::io::Error) -> OutputError + 'a {
        move |source| OutputError::Io {
            action,
            path: path.to_path_buf(),
            source,
        }
    }
}
