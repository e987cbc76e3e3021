//! Errors for cloud data files: each names the file, the field (a path such as
//! `layers[1].height`) and the reason, and nothing is emitted for a file that has one.

use std::path::PathBuf;

use thiserror::Error;

use crate::limits::Origin;

#[derive(Clone, Debug, Error, PartialEq)]
pub enum DataError {
    /// A number outside its accepted range ([`crate::limits`]), from a file, a flag or code.
    #[error("{origin}: {value} is out of range; allowed: {allowed} ({hint})")]
    OutOfRange {
        origin: Origin,
        value: String,
        allowed: String,
        hint: &'static str,
    },
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
    /// The data file the error is about, if it is about one.
    pub fn file(&self) -> Option<&std::path::Path> {
        match self {
            DataError::Read { file, .. }
            | DataError::Invalid { file, .. }
            | DataError::UnknownReference { file, .. }
            | DataError::Duplicate { file, .. } => Some(file),
            DataError::OutOfRange {
                origin: Origin::File { file, .. },
                ..
            } => Some(file),
            DataError::OutOfRange { .. } => None,
        }
    }

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
