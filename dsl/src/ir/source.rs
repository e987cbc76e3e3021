//! Where a piece of IR came from in the Rust source. Every statement carries one, and the WGSL
//! printer keeps a table from output byte ranges back to these, so a naga error can name the
//! DSL function and the Rust line that produced it instead of `Expression [12]`.

use std::fmt;

/// A Rust source location, captured with `file!()`, `line!()` and `column!()` at the statement.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct SourceLoc {
    pub file: &'static str,
    pub line: u32,
    pub column: u32,
}

impl SourceLoc {
    /// A location for IR made by library code rather than a user's `#[shader_fn]`.
    pub const fn new(file: &'static str, line: u32, column: u32) -> Self {
        Self { file, line, column }
    }
}

impl fmt::Display for SourceLoc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// Captures the current Rust source location as a [`SourceLoc`].
#[macro_export]
macro_rules! loc {
    () => {
        $crate::ir::SourceLoc::new(::core::file!(), ::core::line!(), ::core::column!())
    };
}
