//! Host functions: `#[shader_fn]`s that a host runs on the CPU each frame (per-frame parameters,
//! a light's position, a timeline), recorded into a module of their own so that printers for host
//! languages (`nimbus_codegen::print_js`) can give other hosts the same function. Nothing
//! else roots them: such a module has no entry point.

use crate::ir::{ExprId, Param, SourceLoc, Type};
use crate::module::ModuleBuilder;
use crate::record::{self, FunctionHeader};

/// A `#[shader_fn]` as a host function: its name, its parameters and a recorder of a call to
/// it. Made by [`host_fn!`](crate::host_fn) from the function's path.
#[derive(Clone, Copy, Debug)]
pub struct HostFn {
    pub name: &'static str,
    pub params: &'static [(&'static str, Type)],
    pub result: Type,
    pub call: fn(&[ExprId]) -> ExprId,
}

/// The [`HostFn`] of a `#[shader_fn]` without generation-time parameters: `host_fn!(my_fn)`.
#[macro_export]
macro_rules! host_fn {
    ($($f:ident)::+) => {
        $crate::HostFn {
            name: $($f)::+::NAME,
            params: $($f)::+::PARAMS,
            result: $($f)::+::RESULT,
            call: $($f)::+::call_ids,
        }
    };
}

impl ModuleBuilder {
    /// Records `f` and everything it calls. The function is reached through a caller of the
    /// same signature, `host_<name>`, which only forwards its arguments: recording a call
    /// needs a function to record it in, and an entry point would give the module a stage and
    /// bindings that a host function has no use for.
    pub fn host(&mut self, f: HostFn, loc: SourceLoc) {
        let header = FunctionHeader {
            name: record::sanitize(&format!("host_{}", f.name)),
            rust_name: format!("host_{}", f.name),
            doc: vec![format!("Calls `{}` (roots it in a host module).", f.name)],
            specialised: Vec::new(),
            params: f
                .params
                .iter()
                .map(|(name, ty)| Param {
                    name: record::sanitize(name),
                    ty: *ty,
                })
                .collect(),
            result: Some(f.result),
            loc,
        };
        record::ensure_function(header, |args| Some((f.call)(args)));
    }
}
