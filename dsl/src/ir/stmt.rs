//! Statements and blocks. Control flow is structured (if, bounded for, break, return) because
//! that is all WGSL has, and because it keeps the printed code shaped like the Rust source.

use super::expr::{ExprId, LocalId};
use super::source::SourceLoc;

/// A sequence of statements.
pub type Block = Vec<Stmt>;

/// Whether a `break` or `continue` of the loop whose body is `block` occurs in it (those of
/// nested loops do not count).
pub fn leaves_loop(block: &Block) -> bool {
    block.iter().any(|s| match s {
        Stmt::Break { .. } | Stmt::Continue { .. } => true,
        Stmt::If {
            then, otherwise, ..
        } => leaves_loop(then) || leaves_loop(otherwise),
        _ => false,
    })
}

#[derive(Clone, PartialEq, Debug)]
pub enum Stmt {
    /// `let name = value;`
    Let {
        local: LocalId,
        value: ExprId,
        loc: SourceLoc,
    },
    /// `var name: T = init;`
    Var {
        local: LocalId,
        init: Option<ExprId>,
        loc: SourceLoc,
    },
    /// `name = value;`
    Assign {
        local: LocalId,
        value: ExprId,
        loc: SourceLoc,
    },
    /// `target[index] = value;` on a read-write storage buffer.
    Store {
        target: ExprId,
        value: ExprId,
        loc: SourceLoc,
    },
    If {
        cond: ExprId,
        then: Block,
        otherwise: Block,
        loc: SourceLoc,
    },
    /// `for (var i = start; i < end; i++) { body }`: the only loop, so every loop has a bound.
    For {
        counter: LocalId,
        start: ExprId,
        end: ExprId,
        body: Block,
        loc: SourceLoc,
    },
    Break {
        loc: SourceLoc,
    },
    Continue {
        loc: SourceLoc,
    },
    Return {
        value: Option<ExprId>,
        loc: SourceLoc,
    },
}

impl Stmt {
    pub fn loc(&self) -> SourceLoc {
        match self {
            Stmt::Let { loc, .. }
            | Stmt::Var { loc, .. }
            | Stmt::Assign { loc, .. }
            | Stmt::Store { loc, .. }
            | Stmt::If { loc, .. }
            | Stmt::For { loc, .. }
            | Stmt::Break { loc }
            | Stmt::Continue { loc }
            | Stmt::Return { loc, .. } => *loc,
        }
    }

    /// Whether control never falls through this statement.
    pub fn diverges(&self) -> bool {
        matches!(
            self,
            Stmt::Break { .. } | Stmt::Continue { .. } | Stmt::Return { .. }
        )
    }
}
