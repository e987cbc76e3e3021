//! Errors for cloud data files: each names the file, the field (a path such as
//! `layers[1].height`) and the reason, and nothing is emitted for a file that has one.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Error, PartialEq)]
pub enum DataError {
    #[error("{}: cannot read: {reason}", file.display())]
    Read { file: PathBuf, reason: String },
    #[error("{}: {field}: {reason}", file.display())]
    Invalid {
        file: PathBuf,
        /// Dotted path to the offending value, e.g. `layers[1].coverage_filter_width`.
        field: String,
        reason: String,
    },
    #[error("{}: unknown {kind} `{name}` (known: {known})", file.display())]
    UnknownReference {
        file: PathBuf,
        kind: &'static str,
        name: String,
        known: String,
    },
    #[error("{}: {kind} `{name}` is defined twice (also in {})", file.display(), other.display())]
    Duplicate {
        file: PathBuf,
        kind: &'static str,
        name: String,
        other: PathBuf,
    },
}

impl DataError {
    pub(crate) fn invalid(
        file: &std::path::Path,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        DataError::Invalid {
            file: file.to_path_buf(),
            field: field.into(),
            reason: reason.into(),
        }
    }
}
