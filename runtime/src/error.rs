//! Runtime errors.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum RuntimeError {
    #[error(
        "no GPU adapter found (tried Vulkan and GL, including software ones). On Debian, install a \
         software driver: `apt-get install mesa-vulkan-drivers` (lavapipe)"
    )]
    NoAdapter,
    #[error("could not open a device on {adapter}: {reason}")]
    Device { adapter: String, reason: String },
    #[error("the GPU rejected {what}: {reason}")]
    Pipeline { what: String, reason: String },
    #[error("reading results back from the GPU failed: {0}")]
    Readback(String),
    #[error(transparent)]
    Codegen(#[from] nimbus_codegen::CodegenError),
    #[error(transparent)]
    Dsl(#[from] nimbus_dsl::DslError),
    /// Uniform bytes that do not fit their buffer: a layout disagreeing with its writer.
    #[error(transparent)]
    Layout(#[from] nimbus_dsl::layout::LayoutError),
    #[error("this adapter cannot: {0}")]
    Limit(String),
    /// A phase function no table Mitsuba is given can represent faithfully.
    #[error(
        "genus `{genus}`: its phase function {phase} cannot be exported for Mitsuba: even {entries} \
         evenly spaced cosines (Mitsuba's tabulated phase) integrate to {integral:.4} over the \
         sphere instead of 1, so Mitsuba would render every direction {integral:.3}× too dim \
         (its forward peak is narrower than one step); compare a genus with a broader phase \
         (smaller droplets, a lower g)"
    )]
    PhaseTable {
        genus: String,
        phase: String,
        entries: usize,
        integral: f64,
    },
    /// A genus a scene's timeline names that the library it was given lacks.
    #[error(
        "scene `{scene}`: its weather names the genus `{genus}`, which the library does not hold"
    )]
    UnknownGenus { scene: String, genus: String },
    /// A picture (or texture) larger than the device holds, found before any work.
    #[error("{what} needs {needs}, beyond the {allows} of this adapter ({adapter}); {way_out}")]
    DeviceLimit {
        what: String,
        needs: String,
        allows: String,
        adapter: String,
        way_out: String,
    },
    #[error("cannot use texture {file}: {reason}")]
    Texture {
        file: std::path::PathBuf,
        reason: String,
    },
    #[error("the rendered frame is unusable: {0}")]
    BadFrame(String),
    #[error("cannot write {file}: {reason}")]
    Output {
        file: std::path::PathBuf,
        reason: String,
    },
    #[error(transparent)]
    Destination(#[from] nimbus_output::OutputError),
    /// A frame value outside its accepted range.
    #[error(transparent)]
    Value(#[from] nimbus_clouds::DataError),
    /// A frame that cannot be drawn (`Frame::validate`); its numbers out of range are
    /// [`RuntimeError::Value`], as everywhere else.
    #[error(transparent)]
    Frame(nimbus_clouds::frame::FrameError),
    #[error("Frame::genus `{genus}`: {field}: {reason}")]
    Genus {
        genus: String,
        field: String,
        reason: String,
    },
    #[error("density export: {field} {reason}")]
    Region { field: &'static str, reason: String },
    #[error("parity kernel: {0}")]
    Kernel(String),
}

impl From<nimbus_clouds::frame::FrameError> for RuntimeError {
    fn from(e: nimbus_clouds::frame::FrameError) -> Self {
        match e {
            nimbus_clouds::frame::FrameError::Value(v) => RuntimeError::Value(v),
            other => RuntimeError::Frame(other),
        }
    }
}
