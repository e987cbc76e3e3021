//! Specialisation: what a variant fixes is folded, and what it leaves unreachable is removed.
//!
//! Most specialisation already happened while recording (an `if` on a `#[spec]` value records
//! only the taken branch). This pass finishes the job on the IR: literal arithmetic is folded,
//! an `if` whose condition folded to a literal keeps only the taken arm, statements after a
//! `return`/`break` are dropped, and functions, globals and structs that no entry point reaches
//! are removed, so a branch decided at generation time leaves no code, binding or helper behind.

use std::collections::BTreeSet;

use nimbus_dsl::ir::{
    BinaryOp, Block, Builtin, ExprId, ExprKind, Function, Literal, LocalId, Module, Stmt, Type,
    UnaryOp, leaves_loop,
};

/// Specialises a recorded module in place.
pub fn specialise(module: &mut Module) {
    module.functions.iter_mut().for_each(specialise_function);
    remove_unused_params(module);
    remove_unreachable(module);
}

/// [`specialise`], its functions on every core (rayon): each function's folding and pruning
/// reads nothing of the others.
pub fn specialise_on_every_core(module: &mut Module) {
    use rayon::prelude::*;
    module
        .functions
        .par_iter_mut()
        .for_each(specialise_function);
    remove_unused_params(module);
    remove_unreachable(module);
}

/// What specialisation does within one function.
fn specialise_function(f: &mut Function) {
    // Folding a `let` to a literal can make further reads literal: fold to the fixed point.
    fold_to_fixed_point(f);
    let body = std::mem::take(&mut f.body);
    f.body = prune_block(f, body);
    // Unrolled loops leave their counter a literal `let`: fold it away before tidying.
    fold_to_fixed_point(f);
    // Pruned branches can leave a `var` never assigned again: as a `let` it may be a literal
    // that folds further.
    tidy(f);
    drop_unread_lets(f);
    fold_to_fixed_point(f);
    let body = std::mem::take(&mut f.body);
    f.body = prune_block(f, body);
}

/// `stmt` with the blocks nested in it (an `if`'s arms, a loop's body) passed through `f`.
pub(crate) fn map_nested(stmt: Stmt, f: &mut impl FnMut(Block) -> Block) -> Stmt {
    match stmt {
        Stmt::If {
            cond,
            then,
            otherwise,
            loc,
        } => Stmt::If {
            cond,
            then: f(then),
            otherwise: f(otherwise),
            loc,
        },
        Stmt::For {
            counter,
            start,
            end,
            body,
            loc,
        } => Stmt::For {
            counter,
            start,
            end,
            body: f(body),
            loc,
        },
        other => other,
    }
}

/// Folds literal arithmetic and propagates literal `let`s until nothing changes (each round
/// that continues removed at least one `let`, so this ends).
fn fold_to_fixed_point(f: &mut Function) {
    loop {
        fold_constants(f);
        if !propagate_literal_lets(f) {
            break;
        }
    }
}

/// Says what the code does: a `var` never assigned after its declaration becomes a `let`, and a
/// `let` returned by the very next statement is returned directly (`let c = f(); return c;`
/// prints as `return f();`).
fn tidy(f: &mut Function) {
    merge_first_assignment(f);
    fn assigned(block: &Block, out: &mut BTreeSet<LocalId>) {
        for stmt in block {
            match stmt {
                Stmt::Assign { local, .. } => {
                    out.insert(*local);
                }
                Stmt::If {
                    then, otherwise, ..
                } => {
                    assigned(then, out);
                    assigned(otherwise, out);
                }
                Stmt::For { body, .. } => assigned(body, out),
                _ => {}
            }
        }
    }
    fn rewrite(f: &Function, block: Block, written: &BTreeSet<LocalId>) -> Block {
        let mut out: Block = Vec::with_capacity(block.len());
        for stmt in block {
            let stmt = match stmt {
                Stmt::Var {
                    local,
                    init: Some(value),
                    loc,
                } if !written.contains(&local) => Stmt::Let { local, value, loc },
                Stmt::Return {
                    value: Some(r),
                    loc,
                } => match out.last() {
                    Some(Stmt::Let { local, value, .. })
                        if f.expr(r).kind == ExprKind::Local(*local) =>
                    {
                        let value = *value;
                        out.pop();
                        Stmt::Return {
                            value: Some(value),
                            loc,
                        }
                    }
                    _ => Stmt::Return {
                        value: Some(r),
                        loc,
                    },
                },
                other => map_nested(other, &mut |b| rewrite(f, b, written)),
            };
            out.push(stmt);
        }
        out
    }
    let mut written = BTreeSet::new();
    assigned(&f.body, &mut written);
    let body = std::mem::take(&mut f.body);
    f.body = rewrite(f, body, &written);
    for (i, l) in f.locals.iter_mut().enumerate() {
        if l.mutable && !written.contains(&LocalId(i as u32)) {
            l.mutable = false;
        }
    }
}

/// Removes each `let` that nothing reads and whose value calls no function (so dropping it
/// drops no effect): what a branch specialisation removed leaves behind (`let second =
/// vec4(0.0);` once the second layer group is gone). Repeats, since a removed `let` may have
/// been the only reader of another.
fn drop_unread_lets(f: &mut Function) {
    fn drop(block: Block, gone: &BTreeSet<LocalId>) -> Block {
        block
            .into_iter()
            .filter(|s| !matches!(s, Stmt::Let { local, .. } if gone.contains(local)))
            .map(|s| map_nested(s, &mut |b| drop(b, gone)))
            .collect()
    }
    fn lets(block: &Block, out: &mut Vec<(LocalId, ExprId)>) {
        for stmt in block {
            match stmt {
                Stmt::Let { local, value, .. } => out.push((*local, *value)),
                Stmt::If {
                    then, otherwise, ..
                } => {
                    lets(then, out);
                    lets(otherwise, out);
                }
                Stmt::For { body, .. } => lets(body, out),
                _ => {}
            }
        }
    }
    loop {
        let mut read = BTreeSet::new();
        walk_block(f, &f.body, &mut |id| {
            if let ExprKind::Local(l) = f.expr(id).kind {
                read.insert(l);
            }
        });
        let mut declared = Vec::new();
        lets(&f.body, &mut declared);
        let gone: BTreeSet<LocalId> = declared
            .into_iter()
            .filter(|(local, value)| {
                let mut calls = false;
                walk_expr(f, *value, &mut |id| {
                    calls |= matches!(f.expr(id).kind, ExprKind::Call(..));
                });
                !read.contains(local) && !calls
            })
            .map(|(local, _)| local)
            .collect();
        if gone.is_empty() {
            return;
        }
        let body = std::mem::take(&mut f.body);
        f.body = drop(body, &gone);
    }
}

/// `var x = a; x = f(x);` with no other assignment of `x` is `var x = f(a);` (then a `let`),
/// when `a` is cheap to repeat (a literal, a parameter, a `let`, or a place in a uniform): what
/// a loop over one layer group leaves once unrolled (`var inside = 0.0; inside = inside +
/// layers_containing(h, 0u);`), and a toggle's `sun *= attenuation` on a copied uniform.
fn merge_first_assignment(f: &mut Function) {
    fn count(block: &Block, out: &mut std::collections::BTreeMap<LocalId, usize>) {
        for stmt in block {
            match stmt {
                Stmt::Assign { local, .. } => *out.entry(*local).or_default() += 1,
                Stmt::If {
                    then, otherwise, ..
                } => {
                    count(then, out);
                    count(otherwise, out);
                }
                Stmt::For { body, .. } => count(body, out),
                _ => {}
            }
        }
    }
    fn cheap(f: &Function, id: ExprId) -> bool {
        match &f.expr(id).kind {
            ExprKind::Literal(_) | ExprKind::Arg(_) | ExprKind::Global(_) => true,
            ExprKind::Local(l) => !f.local(*l).mutable,
            ExprKind::Member(base, _) | ExprKind::Swizzle(base, _) => cheap(f, *base),
            _ => false,
        }
    }
    fn merge(f: &mut Function, block: Block, once: &BTreeSet<LocalId>) -> Block {
        let mut out: Block = Vec::with_capacity(block.len());
        for stmt in block {
            // The declaration, possibly behind `let`s that do not read the variable.
            let declaration = match &stmt {
                Stmt::Assign { local, .. } if once.contains(local) => {
                    let reads = |e: ExprId| {
                        let mut hit = false;
                        walk_expr(f, e, &mut |x| {
                            hit |= f.expr(x).kind == ExprKind::Local(*local)
                        });
                        hit
                    };
                    out.iter()
                        .rposition(|s| !matches!(s, Stmt::Let { value, .. } if !reads(*value)))
                        .and_then(|at| match &out[at] {
                            Stmt::Var {
                                local: l,
                                init: Some(i),
                                ..
                            } if l == local && cheap(f, *i) => Some((at, *i)),
                            _ => None,
                        })
                }
                _ => None,
            };
            if let (Some((at, init)), Stmt::Assign { local, value, loc }) = (declaration, &stmt) {
                let (local, value, loc) = (*local, *value, *loc);
                out.remove(at);
                let mut reads = Vec::new();
                walk_expr(f, value, &mut |e| {
                    if f.expr(e).kind == ExprKind::Local(local) {
                        reads.push(e);
                    }
                });
                let kind = f.expr(init).kind.clone();
                for e in reads {
                    f.exprs[e.0 as usize].kind = kind.clone();
                }
                out.push(Stmt::Var {
                    local,
                    init: Some(value),
                    loc,
                });
                continue;
            }
            let stmt = map_nested(stmt, &mut |b| merge(f, b, once));
            out.push(stmt);
        }
        out
    }
    let mut counts = std::collections::BTreeMap::new();
    count(&f.body, &mut counts);
    let once: BTreeSet<LocalId> = counts
        .into_iter()
        .filter(|(_, n)| *n == 1)
        .map(|(l, _)| l)
        .collect();
    let body = std::mem::take(&mut f.body);
    f.body = merge(f, body, &once);
}

/// Replaces reads of `let` locals bound to a literal by the literal and drops those `let`s.
/// Returns whether anything changed.
fn propagate_literal_lets(f: &mut Function) -> bool {
    fn collect(f: &Function, block: &Block, out: &mut Vec<(nimbus_dsl::ir::LocalId, Literal)>) {
        for stmt in block {
            match stmt {
                Stmt::Let { local, value, .. } => {
                    if let Some(l) = lit(f, *value) {
                        out.push((*local, l));
                    }
                }
                Stmt::If {
                    then, otherwise, ..
                } => {
                    collect(f, then, out);
                    collect(f, otherwise, out);
                }
                Stmt::For { body, .. } => collect(f, body, out),
                _ => {}
            }
        }
    }
    fn drop_lets(block: Block, gone: &[nimbus_dsl::ir::LocalId]) -> Block {
        block
            .into_iter()
            .filter(|s| !matches!(s, Stmt::Let { local, .. } if gone.contains(local)))
            .map(|s| map_nested(s, &mut |b| drop_lets(b, gone)))
            .collect()
    }
    let mut found = Vec::new();
    collect(f, &f.body, &mut found);
    if found.is_empty() {
        return false;
    }
    let mut values = std::collections::HashMap::new();
    for &(local, value) in &found {
        values.entry(local).or_insert(value);
    }
    for e in &mut f.exprs {
        if let ExprKind::Local(l) = e.kind
            && let Some(value) = values.get(&l)
        {
            e.kind = ExprKind::Literal(*value);
        }
    }
    let gone: Vec<_> = found.iter().map(|(l, _)| *l).collect();
    let body = std::mem::take(&mut f.body);
    f.body = drop_lets(body, &gone);
    true
}

/// Removes parameters a (non-entry) function never reads, and the matching arguments at every
/// call. A texture passed only to a branch that specialisation removed thus stops being passed,
/// and its binding becomes unreachable.
fn remove_unused_params(module: &mut Module) {
    loop {
        let mut changed = false;
        for i in 0..module.functions.len() {
            if module.entry_point(&module.functions[i].name).is_some() {
                continue;
            }
            let f = &module.functions[i];
            let mut used = vec![false; f.params.len()];
            walk_block(f, &f.body, &mut |id| {
                if let ExprKind::Arg(a) = f.expr(id).kind {
                    used[a as usize] = true;
                }
            });
            if used.iter().all(|u| *u) {
                continue;
            }
            changed = true;
            let name = f.name.clone();
            let mut new_index = Vec::with_capacity(used.len());
            let mut next = 0u32;
            for u in &used {
                new_index.push(if *u {
                    next += 1;
                    Some(next - 1)
                } else {
                    None
                });
            }
            let f = &mut module.functions[i];
            f.params = f
                .params
                .drain(..)
                .zip(&used)
                .filter_map(|(p, u)| u.then_some(p))
                .collect();
            for e in &mut f.exprs {
                if let ExprKind::Arg(a) = &mut e.kind
                    && let Some(Some(n)) = new_index.get(*a as usize)
                {
                    *a = *n;
                }
            }
            for caller in &mut module.functions {
                for e in &mut caller.exprs {
                    if let ExprKind::Call(callee, args) = &mut e.kind
                        && *callee == name
                        && args.len() == used.len()
                    {
                        *args = args
                            .drain(..)
                            .zip(&used)
                            .filter_map(|(a, u)| u.then_some(a))
                            .collect();
                    }
                }
            }
        }
        if !changed {
            return;
        }
    }
}

fn lit(f: &Function, id: ExprId) -> Option<Literal> {
    match f.expr(id).kind {
        ExprKind::Literal(l) => Some(l),
        _ => None,
    }
}

fn fold_binary(op: BinaryOp, a: Literal, b: Literal) -> Option<Literal> {
    use Literal::*;
    Some(match (a, b) {
        (F32(x), F32(y)) => {
            let (x, y) = (f32::from_bits(x), f32::from_bits(y));
            let r = match op {
                BinaryOp::Add => Literal::f32(x + y),
                BinaryOp::Sub => Literal::f32(x - y),
                BinaryOp::Mul => Literal::f32(x * y),
                BinaryOp::Div => Literal::f32(x / y),
                BinaryOp::Lt => Bool(x < y),
                BinaryOp::Le => Bool(x <= y),
                BinaryOp::Gt => Bool(x > y),
                BinaryOp::Ge => Bool(x >= y),
                BinaryOp::Eq => Bool(x == y),
                BinaryOp::Ne => Bool(x != y),
                _ => return None,
            };
            // Never fold into a value WGSL cannot spell; naga reports the expression instead.
            if let F32(bits) = r
                && !f32::from_bits(bits).is_finite()
            {
                return None;
            }
            r
        }
        (I32(x), I32(y)) => match op {
            BinaryOp::Add => I32(x.wrapping_add(y)),
            BinaryOp::Sub => I32(x.wrapping_sub(y)),
            BinaryOp::Mul => I32(x.wrapping_mul(y)),
            BinaryOp::Lt => Bool(x < y),
            BinaryOp::Le => Bool(x <= y),
            BinaryOp::Gt => Bool(x > y),
            BinaryOp::Ge => Bool(x >= y),
            BinaryOp::Eq => Bool(x == y),
            BinaryOp::Ne => Bool(x != y),
            // Division and remainder are left to naga, which reports division by zero.
            _ => return None,
        },
        (U32(x), U32(y)) => match op {
            BinaryOp::Add => U32(x.wrapping_add(y)),
            BinaryOp::Sub => U32(x.wrapping_sub(y)),
            BinaryOp::Mul => U32(x.wrapping_mul(y)),
            BinaryOp::BitAnd => U32(x & y),
            BinaryOp::BitOr => U32(x | y),
            BinaryOp::BitXor => U32(x ^ y),
            // Unsigned division and remainder by a non-zero literal are exact; by zero they
            // are left to naga, which reports them.
            BinaryOp::Div if y != 0 => U32(x / y),
            BinaryOp::Rem if y != 0 => U32(x % y),
            BinaryOp::Lt => Bool(x < y),
            BinaryOp::Le => Bool(x <= y),
            BinaryOp::Gt => Bool(x > y),
            BinaryOp::Ge => Bool(x >= y),
            BinaryOp::Eq => Bool(x == y),
            BinaryOp::Ne => Bool(x != y),
            _ => return None,
        },
        (Bool(x), Bool(y)) => match op {
            BinaryOp::And | BinaryOp::BitAnd => Bool(x && y),
            BinaryOp::Or | BinaryOp::BitOr => Bool(x || y),
            BinaryOp::Eq => Bool(x == y),
            BinaryOp::Ne | BinaryOp::BitXor => Bool(x != y),
            _ => return None,
        },
        _ => return None,
    })
}

/// Folds literal-only expressions. Children are always recorded before their parents, so one
/// pass in index order sees folded children.
fn fold_constants(f: &mut Function) {
    for i in 0..f.exprs.len() {
        let id = ExprId(i as u32);
        // Only the kinds folded here are copied out (a call's or a built-in's arguments are a
        // `Vec`: cloning every expression's kind each round was most of this pass's time).
        let kind = match &f.expr(id).kind {
            k @ (ExprKind::Unary(..)
            | ExprKind::Binary(..)
            | ExprKind::Convert(..)
            | ExprKind::Select { .. }) => k.clone(),
            k @ ExprKind::Builtin(Builtin::Max | Builtin::Min, args) if args.len() == 2 => {
                k.clone()
            }
            _ => continue,
        };
        let folded = match kind {
            ExprKind::Unary(op, a) => match (op, lit(f, a)) {
                (UnaryOp::Neg, Some(Literal::F32(x))) => Some(Literal::f32(-f32::from_bits(x))),
                (UnaryOp::Neg, Some(Literal::I32(x))) if x != i32::MIN => Some(Literal::I32(-x)),
                (UnaryOp::Not, Some(Literal::Bool(x))) => Some(Literal::Bool(!x)),
                _ => None,
            },
            ExprKind::Binary(op, a, b) => match (lit(f, a), lit(f, b)) {
                (Some(x), Some(y)) => fold_binary(op, x, y),
                // `x * 1.0`, `1.0 * x` and `x / 1.0` are `x` exactly (NaN and infinities
                // included), when `x` already has the result's type.
                (_, Some(one)) if is_one(one) && matches!(op, BinaryOp::Mul | BinaryOp::Div) => {
                    identity(f, i, a);
                    None
                }
                (Some(one), _) if is_one(one) && op == BinaryOp::Mul => {
                    identity(f, i, b);
                    None
                }
                // `0 + x` and `x ± 0` are `x` (for floats, but for the sign of a zero sum).
                (Some(zero), _) if is_zero(zero) && op == BinaryOp::Add => {
                    identity(f, i, b);
                    None
                }
                (_, Some(zero)) if is_zero(zero) && matches!(op, BinaryOp::Add | BinaryOp::Sub) => {
                    identity(f, i, a);
                    None
                }
                _ => None,
            },
            ExprKind::Convert(s, a) => match lit(f, a) {
                Some(Literal::I32(x)) if s == nimbus_dsl::ir::Scalar::F32 => {
                    Some(Literal::f32(x as f32))
                }
                Some(Literal::U32(x)) if s == nimbus_dsl::ir::Scalar::F32 => {
                    Some(Literal::f32(x as f32))
                }
                _ => None,
            },
            // `max`/`min` of two integer literals (an unrolled loop's counter against a count
            // the key fixes): the lanes an octave reads become fixed.
            ExprKind::Builtin(op @ (Builtin::Max | Builtin::Min), args) if args.len() == 2 => {
                match (lit(f, args[0]), lit(f, args[1])) {
                    (Some(Literal::U32(x)), Some(Literal::U32(y))) => {
                        Some(Literal::U32(if op == Builtin::Max {
                            x.max(y)
                        } else {
                            x.min(y)
                        }))
                    }
                    (Some(Literal::I32(x)), Some(Literal::I32(y))) => {
                        Some(Literal::I32(if op == Builtin::Max {
                            x.max(y)
                        } else {
                            x.min(y)
                        }))
                    }
                    _ => None,
                }
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => match lit(f, cond) {
                Some(Literal::Bool(c)) => {
                    let pick = if c { if_true } else { if_false };
                    f.exprs[i].kind = f.expr(pick).kind.clone();
                    None
                }
                _ => None,
            },
            _ => None,
        };
        if let Some(l) = folded
            && l.ty() == f.exprs[i].ty
        {
            f.exprs[i].kind = ExprKind::Literal(l);
        }
    }
}

fn is_one(l: Literal) -> bool {
    l == Literal::f32(1.0)
}

fn is_zero(l: Literal) -> bool {
    matches!(l, Literal::U32(0) | Literal::I32(0)) || l == Literal::f32(0.0)
}

/// Makes expression `i` the expression `operand` when their types agree.
fn identity(f: &mut Function, i: usize, operand: ExprId) {
    if f.expr(operand).ty == f.exprs[i].ty {
        f.exprs[i].kind = f.expr(operand).kind.clone();
    }
}

/// Drops arms decided by a literal condition and statements after one that diverges.
fn prune_block(f: &Function, block: Block) -> Block {
    let mut out = Block::new();
    for stmt in block {
        let stmts = match stmt {
            Stmt::If {
                cond,
                then,
                otherwise,
                loc,
            } => match lit(f, cond) {
                Some(Literal::Bool(true)) => prune_block(f, then),
                Some(Literal::Bool(false)) => prune_block(f, otherwise),
                _ => vec![Stmt::If {
                    cond,
                    then: prune_block(f, then),
                    otherwise: prune_block(f, otherwise),
                    loc,
                }],
            },
            Stmt::For {
                counter,
                start,
                end,
                body,
                loc,
            } => match trip_count(f, start, end) {
                // A loop over a generation-time range of one (one layer group) is its body, with
                // the counter a `let` that folding then turns into the literal; of none, nothing.
                Some(0) => vec![],
                Some(1) if !leaves_loop(&body) => {
                    let mut unrolled = vec![Stmt::Let {
                        local: counter,
                        value: start,
                        loc,
                    }];
                    unrolled.extend(prune_block(f, body));
                    unrolled
                }
                _ => vec![Stmt::For {
                    counter,
                    start,
                    end,
                    body: prune_block(f, body),
                    loc,
                }],
            },
            other => vec![other],
        };
        for s in stmts {
            let diverges = s.diverges();
            out.push(s);
            if diverges {
                return out;
            }
        }
    }
    out
}

/// Iterations of `for i in start..end` when both bounds are literals.
fn trip_count(f: &Function, start: ExprId, end: ExprId) -> Option<i64> {
    let value = |l: Literal| match l {
        Literal::U32(v) => Some(i64::from(v)),
        Literal::I32(v) => Some(i64::from(v)),
        _ => None,
    };
    Some((value(lit(f, end)?)? - value(lit(f, start)?)?).max(0))
}

/// Calls `visit` on every expression reachable from the statements of `block`.
pub fn walk_block(f: &Function, block: &Block, visit: &mut impl FnMut(ExprId)) {
    for stmt in block {
        match stmt {
            Stmt::Let { value, .. } | Stmt::Assign { value, .. } => walk_expr(f, *value, visit),
            Stmt::Var { init, .. } => {
                if let Some(i) = init {
                    walk_expr(f, *i, visit);
                }
            }
            Stmt::Store { target, value, .. } => {
                walk_expr(f, *target, visit);
                walk_expr(f, *value, visit);
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                walk_expr(f, *cond, visit);
                walk_block(f, then, visit);
                walk_block(f, otherwise, visit);
            }
            Stmt::For {
                start, end, body, ..
            } => {
                walk_expr(f, *start, visit);
                walk_expr(f, *end, visit);
                walk_block(f, body, visit);
            }
            Stmt::Return { value, .. } => {
                if let Some(v) = value {
                    walk_expr(f, *v, visit);
                }
            }
            Stmt::Break { .. } | Stmt::Continue { .. } => {}
        }
    }
}

/// Calls `visit` on `id` and every expression it depends on.
pub fn walk_expr(f: &Function, id: ExprId, visit: &mut impl FnMut(ExprId)) {
    visit(id);
    f.expr(id)
        .kind
        .for_each_operand(|operand| walk_expr(f, operand, visit));
}

fn collect_struct(ty: Type, out: &mut BTreeSet<&'static str>) {
    match ty {
        Type::Struct(def) if out.insert(def.name) => {
            for field in def.fields {
                collect_struct(field.ty, out);
            }
        }
        Type::Array(elem, _) => collect_struct(*elem, out),
        _ => {}
    }
}

/// Removes functions, globals and structs that no entry point reaches.
fn remove_unreachable(module: &mut Module) {
    let mut live_fns: BTreeSet<String> = module
        .entry_points
        .iter()
        .map(|e| e.function.clone())
        .collect();
    let mut live_globals = BTreeSet::new();
    let mut live_structs = BTreeSet::new();
    // Callees are recorded before callers, so walking from the back reaches a fixed point.
    for f in module.functions.iter().rev() {
        if !live_fns.contains(&f.name) {
            continue;
        }
        for p in &f.params {
            collect_struct(p.ty, &mut live_structs);
        }
        if let Some(r) = f.result {
            collect_struct(r, &mut live_structs);
        }
        let mut visit = |id: ExprId| {
            let e = f.expr(id);
            collect_struct(e.ty, &mut live_structs);
            match &e.kind {
                ExprKind::Call(name, _) => {
                    live_fns.insert(name.clone());
                }
                ExprKind::Global(g) => {
                    live_globals.insert(g.0);
                }
                _ => {}
            }
        };
        walk_block(f, &f.body, &mut visit);
        for l in &f.locals {
            collect_struct(l.ty, &mut live_structs);
        }
    }
    module.functions.retain(|f| live_fns.contains(&f.name));
    for (i, g) in module.globals.iter().enumerate() {
        if live_globals.contains(&(i as u32)) {
            collect_struct(g.ty, &mut live_structs);
        }
    }
    // Globals are referenced by index; keep indices stable by renumbering through a map.
    let mut remap = vec![None; module.globals.len()];
    let mut kept = Vec::new();
    for (i, g) in module.globals.drain(..).enumerate() {
        if live_globals.contains(&(i as u32)) {
            remap[i] = Some(kept.len() as u32);
            kept.push(g);
        }
    }
    module.globals = kept;
    for f in &mut module.functions {
        for e in &mut f.exprs {
            if let ExprKind::Global(g) = &mut e.kind
                && let Some(Some(new)) = remap.get(g.0 as usize)
            {
                g.0 = *new;
            }
        }
    }
    module.structs.retain(|s| live_structs.contains(s.name));
}
