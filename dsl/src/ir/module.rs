//! A whole shader module: globals, functions and entry points.

use super::expr::Literal;
use super::function::Function;
use super::source::SourceLoc;
use super::types::Type;

/// Which kind of resource a global is.
#[derive(Clone, PartialEq, Debug)]
pub enum GlobalKind {
    Uniform {
        group: u32,
        binding: u32,
    },
    /// A storage buffer; `read_write` decides the access mode.
    Storage {
        group: u32,
        binding: u32,
        read_write: bool,
    },
    /// A texture or sampler binding.
    Handle {
        group: u32,
        binding: u32,
    },
    /// A pipeline-overridable constant: kept as `override` for wgpu, baked for other targets.
    Override {
        default: Literal,
    },
    /// A named module constant (`const INV_FOUR_PI: f32 = 0.07957747;`), from a Rust `const`
    /// a `#[shader_fn]` reads.
    Const {
        value: Literal,
    },
    /// A `var<private>`: one copy per invocation. Parity harnesses turn a binding into one to
    /// feed it a value per input record ([`crate::Binding::feed`]).
    Private,
}

/// A module-scope declaration.
#[derive(Clone, PartialEq, Debug)]
pub struct Global {
    pub name: String,
    pub ty: Type,
    pub kind: GlobalKind,
    pub doc: String,
    /// For sampler bindings: the state every consumer creates the sampler with.
    pub sampler: Option<super::SamplerDesc>,
}

impl Global {
    /// `(group, binding)` for resources; `None` for overrides.
    pub fn binding(&self) -> Option<(u32, u32)> {
        match self.kind {
            GlobalKind::Uniform { group, binding }
            | GlobalKind::Storage { group, binding, .. }
            | GlobalKind::Handle { group, binding } => Some((group, binding)),
            GlobalKind::Override { .. } | GlobalKind::Const { .. } | GlobalKind::Private => None,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub enum Stage {
    Vertex,
    Fragment,
    Compute,
}

impl Stage {
    /// The stage's lower-case name (`vertex`, `fragment`, `compute`), as manifests write it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Vertex => "vertex",
            Stage::Fragment => "fragment",
            Stage::Compute => "compute",
        }
    }
}

/// An entry point: a function (in [`Module::functions`]) plus its stage and IO decoration.
#[derive(Clone, PartialEq, Debug)]
pub struct EntryPoint {
    pub stage: Stage,
    /// Name of the function in `functions` that is the entry point.
    pub function: String,
    /// What the pipeline supplies to each parameter.
    pub inputs: Vec<super::io::Io>,
    /// What the pipeline takes the result as, if any.
    pub output: Option<super::io::Io>,
    pub workgroup_size: [u32; 3],
}

/// A recorded module, ready for specialisation and printing.
#[derive(Clone, PartialEq, Debug)]
pub struct Module {
    pub name: String,
    pub doc: Vec<String>,
    pub globals: Vec<Global>,
    /// Struct types used by the module, in first-use order.
    pub structs: Vec<&'static super::types::StructDef>,
    /// Callees before callers, entry points last.
    pub functions: Vec<Function>,
    pub entry_points: Vec<EntryPoint>,
    pub loc: SourceLoc,
}

impl Module {
    pub fn function(&self, name: &str) -> Option<&Function> {
        self.functions.iter().find(|f| f.name == name)
    }

    pub fn entry_point(&self, name: &str) -> Option<&EntryPoint> {
        self.entry_points.iter().find(|e| e.function == name)
    }
}
