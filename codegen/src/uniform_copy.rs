//! Uniform blocks read through one private copy per invocation: a tuning for compilers that
//! inline every function but do not hoist uniform loads out of loops.
//!
//! The generated code reads its uniform block where it needs a value (`clouds.march.min_step`
//! in the helper that uses it), as a hand-written shader does; GPUs serve those reads from a
//! constant cache. llvmpipe and lavapipe (Mesa's CPU drivers) inline the whole shader and then
//! load, bounds-checked, at every read, so a helper called at every step of a ray march re-reads
//! its uniforms at every step: the cloud shaders ran 33–40 % slower that way than when every
//! function received the block by value from the entry point. This pass restores the by-value
//! cost without changing the source: each uniform block `u` becomes `u_buffer` (same slot) and a
//! `var<private> u` that every entry point which reads it fills first (`u = u_buffer;`); the
//! driver then keeps the copy in registers. The runtime applies it on CPU adapters only; emitted
//! files never have it.

use std::collections::{BTreeMap, BTreeSet};

use nimbus_dsl::ir::{Expr, ExprId, ExprKind, Global, GlobalId, GlobalKind, Module, Stmt, Type};

/// Rewrites `module` so that every struct uniform block is read through a per-invocation copy.
pub fn copy_uniforms_per_invocation(module: &mut Module) {
    let blocks: Vec<usize> = module
        .globals
        .iter()
        .enumerate()
        .filter(|(_, g)| {
            matches!(g.kind, GlobalKind::Uniform { .. }) && matches!(g.ty, Type::Struct(_))
        })
        .map(|(i, _)| i)
        .collect();
    for block in blocks {
        let buffer = GlobalId(block as u32);
        let copy = GlobalId(module.globals.len() as u32);
        let original = module.globals[block].clone();
        module.globals[block].name = format!("{}_buffer", original.name);
        module.globals.push(Global {
            kind: GlobalKind::Private,
            doc: format!("Per-invocation copy of `{}_buffer`.", original.name),
            sampler: None,
            ..original.clone()
        });
        // Every read now reads the copy; which functions read it decides where it is filled.
        let mut readers = BTreeSet::new();
        for f in &mut module.functions {
            for e in &mut f.exprs {
                if e.kind == ExprKind::Global(buffer) {
                    e.kind = ExprKind::Global(copy);
                    readers.insert(f.name.clone());
                }
            }
        }
        let calls: BTreeMap<String, BTreeSet<String>> = module
            .functions
            .iter()
            .map(|f| {
                let callees = f
                    .exprs
                    .iter()
                    .filter_map(|e| match &e.kind {
                        ExprKind::Call(callee, _) => Some(callee.clone()),
                        _ => None,
                    })
                    .collect();
                (f.name.clone(), callees)
            })
            .collect();
        let entries: Vec<String> = module
            .entry_points
            .iter()
            .map(|e| e.function.clone())
            .collect();
        for f in &mut module.functions {
            if !entries.contains(&f.name) || !reaches(&f.name, &readers, &calls) {
                continue;
            }
            let value = ExprId(f.exprs.len() as u32);
            f.exprs.push(Expr {
                kind: ExprKind::Global(buffer),
                ty: original.ty,
            });
            let target = ExprId(f.exprs.len() as u32);
            f.exprs.push(Expr {
                kind: ExprKind::Global(copy),
                ty: original.ty,
            });
            f.body.insert(
                0,
                Stmt::Store {
                    target,
                    value,
                    loc: f.loc,
                },
            );
        }
    }
}

/// Whether `from` or a function it calls, directly or not, is in `readers`.
fn reaches(
    from: &str,
    readers: &BTreeSet<String>,
    calls: &BTreeMap<String, BTreeSet<String>>,
) -> bool {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from.to_string()];
    while let Some(f) = stack.pop() {
        if readers.contains(&f) {
            return true;
        }
        if seen.insert(f.clone())
            && let Some(callees) = calls.get(&f)
        {
            stack.extend(callees.iter().cloned());
        }
    }
    false
}
