//! The DSL's own typed IR, in no target's spelling. It is small on purpose: just enough
//! structure to print readable WGSL for people and to lower straight to naga's module for every
//! backend (codegen's `wgsl` printer and `lower`).

mod expr;
mod function;
mod io;
mod module;
mod sampler;
mod source;
mod stmt;
mod types;

pub use expr::{
    BinaryOp, Builtin, Expr, ExprId, ExprKind, GlobalId, Literal, LocalId, SampleKind, UnaryOp,
};
pub use function::{Function, Local, Param};
pub use io::Io;
pub use module::{EntryPoint, Global, GlobalKind, Module, Stage};
pub use sampler::{AddressMode, FilterMode, SamplerDesc};
pub use source::SourceLoc;
pub use stmt::{Block, Stmt, leaves_loop};
pub use types::{FieldDef, Scalar, StructDef, Type};
