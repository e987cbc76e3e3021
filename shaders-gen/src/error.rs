//! The command line's errors: codegen's, the cloud data's, and flags that name nothing known.

use nimbus_clouds::DataError;
use nimbus_codegen::CodegenError;

#[derive(Debug, thiserror::Error)]
pub(crate) enum CliError {
    #[error(transparent)]
    Codegen(#[from] CodegenError),

    #[error(transparent)]
    Data(#[from] DataError),

    #[error(transparent)]
    Output(#[from] nimbus_output::OutputError),

    /// Uniform bytes that do not fit their buffer: a layout disagreeing with its writer.
    #[error(transparent)]
    Layout(#[from] nimbus_dsl::layout::LayoutError),

    #[error("{flag}: {source}")]
    Texture {
        flag: &'static str,
        source: Box<nimbus_runtime::RuntimeError>,
    },

    #[error(
        "data folder {} (from {source_name}): {reason}; point --data or NIMBUS_DATA at a folder \
         holding genera/ (and scenes/), or unset them to use the built-in examples",
        dir.display()
    )]
    DataFolder {
        dir: std::path::PathBuf,
        source_name: String,
        reason: String,
    },

    #[error(
        "an engine package is made for genus × preset pairs: name a genus (--genus, with or \
         without --quality) or a scene (--scene), not a catalogue entry"
    )]
    NoPairs,

    #[error(
        "--engine {engine}: `{pair}` is drawn by the `{path}` path, whose pass this engine's \
         host does not draw yet (the three and webgpu packages do, and `nimbus render --path \
         {path}`); emit the volume (no --path) for this engine"
    )]
    PathWithoutPackage {
        engine: &'static str,
        pair: String,
        path: nimbus_clouds::Path,
    },

    #[error(
        "--engine {engine}: {what} is {size} px, beyond the {limit} px the engine's API \
         guarantees on every device ({basis}); choose a lower --quality"
    )]
    EngineLimit {
        engine: &'static str,
        what: String,
        size: u32,
        limit: u32,
        basis: &'static str,
    },

    #[error("{tool} rejects {file}:\n{output}")]
    External {
        tool: &'static str,
        file: String,
        output: String,
    },

    /// A shader declares a binding its pass's binding enum does not: a bug of Nimbus's, refused
    /// rather than described as something a host could not bind.
    #[error("{shader}: no resource is declared for `{binding}` (group {group}, binding {slot})")]
    UndeclaredBinding {
        shader: String,
        binding: String,
        group: u32,
        slot: u32,
    },
    #[error("the package's noise textures could not be made: {0}")]
    Textures(String),

    /// A value that is well-formed but not accepted here: what gave it, the value, and what
    /// would be.
    #[error("{what}: {given}; {accepted}")]
    Refused {
        what: &'static str,
        given: String,
        accepted: String,
    },

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
