//! A recorded function: its signature, locals, expression arena and body.

use super::expr::{Expr, ExprId, LocalId};
use super::source::SourceLoc;
use super::stmt::Block;
use super::types::Type;

/// A named local value.
#[derive(Clone, PartialEq, Debug)]
pub struct Local {
    /// Unique within the function (the recorder renames shadowed Rust bindings).
    pub name: String,
    pub ty: Type,
    pub mutable: bool,
}

/// A function parameter.
#[derive(Clone, PartialEq, Debug)]
pub struct Param {
    pub name: String,
    pub ty: Type,
}

/// One function of a module.
#[derive(Clone, PartialEq, Debug)]
pub struct Function {
    /// The WGSL name (the Rust name, plus a suffix per generation-time specialisation).
    pub name: String,
    /// The Rust name of the `#[shader_fn]` this came from.
    pub rust_name: String,
    /// Doc comment lines of the Rust function.
    pub doc: Vec<String>,
    /// Generation-time values this copy was specialised for (`name = value`).
    pub specialised: Vec<String>,
    pub params: Vec<Param>,
    pub result: Option<Type>,
    pub locals: Vec<Local>,
    pub exprs: Vec<Expr>,
    pub body: Block,
    pub loc: SourceLoc,
}

impl Function {
    pub fn expr(&self, id: ExprId) -> &Expr {
        &self.exprs[id.0 as usize]
    }

    pub fn local(&self, id: LocalId) -> &Local {
        &self.locals[id.0 as usize]
    }
}
