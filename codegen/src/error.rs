//! Codegen errors. Each names what is wrong and where: the module and variant, the
//! `#[shader_fn]` and Rust line behind a rejected line of WGSL, the target, or the output path.

use std::path::PathBuf;

use nimbus_dsl::ir::SourceLoc;
use thiserror::Error;

use crate::target::Target;

/// Where in the Rust source a generated line came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    /// The Rust name of the `#[shader_fn]` or entry point.
    pub function: String,
    pub loc: SourceLoc,
    /// The offending WGSL line, for context.
    pub wgsl_line: String,
}

impl std::fmt::Display for Origin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "in `{}` at {} (generated WGSL: `{}`)",
            self.function,
            self.loc,
            self.wgsl_line.trim()
        )
    }
}

fn origin_text(origin: &Option<Box<Origin>>) -> String {
    match origin {
        Some(o) => o.to_string(),
        None => "(naga gave no location)".to_string(),
    }
}

#[derive(Debug, Error)]
pub enum CodegenError {
    #[error(transparent)]
    Dsl(#[from] nimbus_dsl::DslError),

    #[error(
        "`{function}` ({loc}) contains a non-finite literal (NaN or infinity), which WGSL cannot spell"
    )]
    NonFiniteLiteral { function: String, loc: SourceLoc },

    #[error("`{function}` has no JavaScript twin: it {reason}")]
    Host { function: String, reason: String },

    #[error("unknown target `{given}`; known targets: {known}")]
    UnknownTarget { given: String, known: String },

    #[error("module `{module}` variant `{variant}`: naga could not parse the generated WGSL {}: {message}", origin_text(.origin))]
    Parse {
        module: String,
        variant: String,
        origin: Option<Box<Origin>>,
        message: String,
    },

    #[error("module `{module}` variant `{variant}`: naga rejected the generated WGSL {}: {message}", origin_text(.origin))]
    Validation {
        module: String,
        variant: String,
        origin: Option<Box<Origin>>,
        message: String,
    },

    /// The IR could not be built into naga's module although its printed WGSL is valid: a bug
    /// of the lowering, not of the user's shader.
    #[error(
        "module `{module}` variant `{variant}`: lowering to naga failed although the printed WGSL is valid (a Nimbus bug): {message}"
    )]
    Lowering {
        module: String,
        variant: String,
        message: String,
    },

    #[error(
        "module `{module}` variant `{variant}`: the {target} backend failed for entry point `{entry_point}`: {message}"
    )]
    Backend {
        module: String,
        variant: String,
        target: Target,
        entry_point: String,
        message: String,
    },

    #[error("module `{module}` variant `{variant}`: the HLSL printer refused it: {message}")]
    Hlsl {
        module: String,
        variant: String,
        message: String,
    },

    #[error(
        "module `{module}` variant `{variant}`: baking the overrides for entry point `{entry_point}` failed: {message}"
    )]
    Bake {
        module: String,
        variant: String,
        entry_point: String,
        message: String,
    },

    #[error("cannot {action} `{}`: {source}", path.display())]
    Output {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The destination folder: a file, not Nimbus's, not writable, or a failed replace.
    #[error(transparent)]
    Destination(#[from] nimbus_output::OutputError),
}
