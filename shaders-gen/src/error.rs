//! The command line's errors: codegen's, the cloud data's, and flags that name nothing known.

use nimbus_clouds::DataError;
use nimbus_codegen::CodegenError;

#[derive(Debug, thiserror::Error)]
pub(crate) enum CliError {
    #[error(transparent)]
    Codegen(#[from] CodegenError),

    #[error(transparent)]
    Data(#[from] DataError),

    #[error("unknown {kind} `{given}`; known: {known}")]
    Unknown {
        kind: &'static str,
        given: String,
        known: String,
    },
}

impl From<nimbus_dsl::DslError> for CliError {
    fn from(e: nimbus_dsl::DslError) -> Self {
        CliError::Codegen(e.into())
    }
}
