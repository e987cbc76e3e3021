//! How an entry point's parameter or result meets the pipeline, in no target's spelling: each
//! printer (WGSL's `@builtin(position)`, naga's `Binding`) says it its own way.

/// A value the pipeline supplies or takes at an entry point.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Io {
    /// The fragment's window position (fragment input) or the clip-space position (vertex
    /// output).
    Position,
    /// The index of the vertex being drawn (vertex input).
    VertexIndex,
    /// The invocation's index in the whole dispatch (compute input).
    GlobalInvocationId,
    /// A user-defined location: colour attachment `n` of a fragment's result.
    Location(u32),
}
