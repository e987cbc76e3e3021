//! Which functions of a host module an export list reaches: what a host-language printer
//! (JavaScript, C#) prints, callees first as the recorder keeps them.

use std::collections::BTreeSet;

use nimbus_dsl::ir::{ExprKind, GlobalKind, Module};

use crate::error::CodegenError;

/// Whether `name` is one of the module's constants (an export may name one).
pub(crate) fn is_constant(module: &Module, name: &str) -> bool {
    module
        .globals
        .iter()
        .any(|g| g.name == name && matches!(g.kind, GlobalKind::Const { .. }))
}

/// The names of the functions `exports` call, directly or not, the exports included. An
/// export that is neither a function nor a constant is refused, naming it.
pub(crate) fn reached(module: &Module, exports: &[&str]) -> Result<BTreeSet<String>, CodegenError> {
    let mut needed = BTreeSet::new();
    let mut stack: Vec<String> = exports
        .iter()
        .filter(|n| !is_constant(module, n))
        .map(|s| s.to_string())
        .collect();
    while let Some(name) = stack.pop() {
        let Some(f) = module.functions.iter().find(|f| f.name == name) else {
            return Err(CodegenError::Host {
                function: name,
                reason: "is neither a function nor a constant of the module".to_string(),
            });
        };
        if needed.insert(name.clone()) {
            for e in &f.exprs {
                if let ExprKind::Call(callee, _) = &e.kind {
                    stack.push(callee.clone());
                }
            }
        }
    }
    Ok(needed)
}
