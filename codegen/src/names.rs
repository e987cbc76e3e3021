//! Identifiers WGSL will not take, renamed just before printing. The recorder keeps the Rust
//! names (made into valid identifiers); a name changes only where WGSL requires it, by naga's
//! own lists (`naga::keywords::wgsl`):
//! - any function, global, parameter or local named like a keyword or reserved word (`active`,
//!   `target`, `loop`); struct members keep their Rust names (a Rust field cannot be a WGSL
//!   keyword; a reserved word there would be refused by naga, at the struct's Rust line);
//! - a module-scope function or global named like a predeclared identifier (`step`, `vec3`),
//!   which would shadow it for the whole module;
//! - a local or parameter named like a predeclared type or enumerant, or like a built-in
//!   function *that its own function calls* (it would shadow the call). Otherwise `step`,
//!   `distance` and `length` stay as written: WGSL lets a local shadow a built-in it never uses.
//!
//! - a local or parameter named like a global or function its own function uses.
//!
//! A renamed identifier gets a trailing `_` (more if that name is taken).

use crate::wgsl_spelling::wgsl_builtin;
use std::collections::{BTreeMap, BTreeSet};

use naga::keywords::wgsl::{BUILTIN_IDENTIFIER_SET, RESERVED_SET};
use nimbus_dsl::ir::{Builtin, ExprKind, Module};

fn reserved(name: &str) -> bool {
    RESERVED_SET.contains(name)
}

fn predeclared(name: &str) -> bool {
    BUILTIN_IDENTIFIER_SET.contains(name)
}

/// `name_`, `name__`, ... whichever is not `taken`.
fn fresh(name: &str, taken: impl Fn(&str) -> bool) -> String {
    let mut n = format!("{name}_");
    while taken(&n) || reserved(&n) || predeclared(&n) {
        n.push('_');
    }
    n
}

/// Renames what WGSL requires in `module`, consistently at every use.
pub(crate) fn rename_for_wgsl(module: &mut Module) {
    let builtin_fns: BTreeSet<&str> = Builtin::ALL.iter().map(|b| wgsl_builtin(*b)).collect();
    // Module scope: functions and globals share one namespace with the predeclared names. A
    // new module-scope name must not be taken by any local either (it would hide the callee).
    let declared: BTreeSet<String> = module
        .functions
        .iter()
        .map(|f| f.name.clone())
        .chain(module.globals.iter().map(|g| g.name.clone()))
        .collect();
    let mut taken: BTreeSet<String> = declared.clone();
    for f in &module.functions {
        taken.extend(f.params.iter().map(|p| p.name.clone()));
        taken.extend(f.locals.iter().map(|l| l.name.clone()));
    }
    let mut renamed: BTreeMap<String, String> = BTreeMap::new();
    for name in declared {
        if reserved(&name) || predeclared(&name) {
            let new = fresh(&name, |n| taken.contains(n));
            taken.insert(new.clone());
            renamed.insert(name, new);
        }
    }
    for g in &mut module.globals {
        if let Some(n) = renamed.get(&g.name) {
            g.name = n.clone();
        }
    }
    for ep in &mut module.entry_points {
        if let Some(n) = renamed.get(&ep.function) {
            ep.function = n.clone();
        }
    }
    let global_names: Vec<String> = module.globals.iter().map(|g| g.name.clone()).collect();
    for f in &mut module.functions {
        if let Some(n) = renamed.get(&f.name) {
            f.name = n.clone();
        }
        let mut called = BTreeSet::new();
        // Module-scope names this function reads: a parameter or local of the same name would
        // hide them (`clouds: MarchResult` beside the `clouds` uniform block).
        let mut referenced: BTreeSet<String> = BTreeSet::new();
        for e in &mut f.exprs {
            match &mut e.kind {
                ExprKind::Call(callee, _) => {
                    if let Some(n) = renamed.get(callee) {
                        *callee = n.clone();
                    }
                    referenced.insert(callee.clone());
                }
                ExprKind::Global(g) => {
                    // Nodes in the arena that no statement reaches may name a global that
                    // specialisation removed.
                    if let Some(name) = global_names.get(g.0 as usize) {
                        referenced.insert(name.clone());
                    }
                }
                ExprKind::Builtin(b, _) => {
                    called.insert(wgsl_builtin(*b));
                }
                ExprKind::Select { .. } => {
                    called.insert("select");
                }
                _ => {}
            }
        }
        let clash = |name: &str| {
            reserved(name)
                || referenced.contains(name)
                || (predeclared(name) && (!builtin_fns.contains(name) || called.contains(name)))
        };
        // Names given here, beside every name of the module (which includes this function's).
        let mut given: BTreeSet<String> = BTreeSet::new();
        for p in &mut f.params {
            if clash(&p.name) {
                p.name = fresh(&p.name, |n| taken.contains(n) || given.contains(n));
                given.insert(p.name.clone());
            }
        }
        for l in &mut f.locals {
            if clash(&l.name) {
                l.name = fresh(&l.name, |n| taken.contains(n) || given.contains(n));
                given.insert(l.name.clone());
            }
        }
    }
}
