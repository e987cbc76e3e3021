//! Repeated sub-expressions bound once.
//!
//! The recorder builds expressions as a graph: a DSL helper such as `mix(a, b, t)` on vectors
//! records `a + (b - a) * t` with one `a`, and a printer that walks the graph as a tree prints
//! `a` (and computes it, on a driver that does not merge the copies) at every use. This pass
//! finds, within each statement, every expression the statement reaches more than once and binds
//! it to a `let` just before the statement, so it is written and evaluated once, as a careful
//! hand-written shader would.
//!
//! Only uses within one statement are merged: all of them are evaluated at the same moment, so
//! they have the same value (expressions have no side effects). The same expression reached
//! from two statements may read a `var` that changed in between and is left alone, as are a
//! loop's bounds (the header is printed once per loop, and moving its `end` out would change
//! when it is read). Cheap accesses (`u.march.radius`, `v.x`, `a[i]` on names, literals,
//! constant vectors) are re-read rather than named: naming them would make the code longer, not
//! clearer.

use naga::{FastHashMap, FastHashSet};
use nimbus_dsl::ir::{Block, Expr, ExprId, ExprKind, Function, Local, LocalId, Stmt};

use crate::specialise::map_nested;

/// Binds, in every function of the module, what a statement computes more than once.
pub fn share_repeated_subexpressions(module: &mut nimbus_dsl::ir::Module) {
    let mut seen = FastHashSet::default();
    for f in &mut module.functions {
        share_in_function(f, &mut seen);
    }
}

/// [`share_repeated_subexpressions`], its functions on every core (rayon): a function's values
/// are its own.
pub fn share_on_every_core(module: &mut nimbus_dsl::ir::Module) {
    use rayon::prelude::*;
    module
        .functions
        .par_iter_mut()
        .for_each_init(FastHashSet::default, |seen, f| share_in_function(f, seen));
}

/// Binds what a statement of `f` computes more than once (`seen`: scratch space).
fn share_in_function(f: &mut Function, seen: &mut FastHashSet<ExprId>) {
    let mut reached_by = FastHashMap::default();
    count_statements(f, &f.body, &mut reached_by, seen);
    let body = std::mem::take(&mut f.body);
    f.body = share_block(f, body, &reached_by, &mut Numbering::default());
}

/// How many statements reach each expression (a loop or an `if` counts for its header only).
/// `seen` is scratch space, reused from statement to statement.
fn count_statements(
    f: &Function,
    block: &Block,
    out: &mut FastHashMap<ExprId, u32>,
    seen: &mut FastHashSet<ExprId>,
) {
    for stmt in block {
        seen.clear();
        let mut visit = |root: ExprId| reach(f, root, seen);
        match stmt {
            Stmt::Let { value, .. } | Stmt::Assign { value, .. } => visit(*value),
            Stmt::Var { init, .. } => init.iter().for_each(|i| visit(*i)),
            Stmt::Store { target, value, .. } => {
                visit(*target);
                visit(*value);
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                visit(*cond);
                count_seen(seen, out);
                count_statements(f, then, out, seen);
                count_statements(f, otherwise, out, seen);
                continue;
            }
            Stmt::For {
                start, end, body, ..
            } => {
                visit(*start);
                visit(*end);
                count_seen(seen, out);
                count_statements(f, body, out, seen);
                continue;
            }
            Stmt::Return { value, .. } => value.iter().for_each(|v| visit(*v)),
            Stmt::Break { .. } | Stmt::Continue { .. } => {}
        }
        count_seen(seen, out);
    }
}

/// One more statement reaches each expression in `seen`.
fn count_seen(seen: &FastHashSet<ExprId>, out: &mut FastHashMap<ExprId, u32>) {
    for &id in seen {
        *out.entry(id).or_insert(0) += 1;
    }
}

fn reach(f: &Function, id: ExprId, seen: &mut FastHashSet<ExprId>) {
    if seen.insert(id) {
        f.expr(id).kind.for_each_operand(|c| reach(f, c, seen));
    }
}

fn share_block(
    f: &mut Function,
    block: Block,
    reached_by: &FastHashMap<ExprId, u32>,
    numbering: &mut Numbering,
) -> Block {
    let mut out = Vec::with_capacity(block.len());
    for stmt in block {
        let stmt = map_nested(stmt, &mut |b| share_block(f, b, reached_by, numbering));
        // The statement's roots, and what names the values bound for it (a local's name is
        // looked up only when something is bound: most statements repeat nothing).
        let none = ExprId(0);
        let (roots, count, base): ([ExprId; 2], usize, Result<LocalId, &str>) = match &stmt {
            Stmt::Let { local, value, .. } | Stmt::Assign { local, value, .. } => {
                ([*value, none], 1, Ok(*local))
            }
            Stmt::Var {
                local,
                init: Some(i),
                ..
            } => ([*i, none], 1, Ok(*local)),
            Stmt::Store { target, value, .. } => ([*target, *value], 2, Err("stored")),
            Stmt::If { cond, .. } => ([*cond, none], 1, Err("cond")),
            Stmt::Return { value: Some(v), .. } => ([*v, none], 1, Err("result")),
            _ => ([none, none], 0, Err("")),
        };
        if count == 0 {
            out.push(stmt);
            continue;
        }
        let shared = repeated(f, &roots[..count], reached_by, numbering);
        let base = match base {
            Ok(local) if !shared.is_empty() => f.local(local).name.clone(),
            Ok(_) => String::new(),
            Err(name) => name.to_string(),
        };
        for ids in shared {
            let local = bind(f, &ids, &base);
            out.push(Stmt::Let {
                local: local.0,
                value: local.1,
                loc: stmt.loc(),
            });
        }
        out.push(stmt);
    }
    out
}

/// The values the statement rooted at `roots` computes more than once and that are worth a
/// name, each as the expressions that compute it, innermost first (so an outer one, bound
/// later, prints with the inner one's name). Two expressions are one value when they have the
/// same operation on the same operand values: `Vec4::splat(w)` written twice is one value.
fn repeated(
    f: &Function,
    roots: &[ExprId],
    reached_by: &FastHashMap<ExprId, u32>,
    numbering: &mut Numbering,
) -> Vec<Vec<ExprId>> {
    numbering.clear();
    let roots: Vec<ExprId> = roots.iter().map(|&r| numbering.number(f, r)).collect();
    // Uses are counted on the graph of values: `f(g(x))` written twice uses `f(..)` twice and
    // `g(x)` once (inside the one `f(..)`), so only `f(..)` is named.
    for r in roots {
        numbering.count_uses(r);
    }
    let Numbering {
        order,
        uses,
        members,
        ..
    } = numbering;
    order
        .iter()
        .filter(|rep| uses.get(*rep).copied().unwrap_or(0) > 1)
        .filter_map(|rep| members.get(rep))
        .filter(|ids| ids.iter().all(|id| reached_by.get(id) == Some(&1)))
        .filter(|ids| !is_cheap(f, ids[0]))
        .cloned()
        .collect()
}

/// Value numbering of one statement's expressions (the maps are reused from statement to
/// statement).
#[derive(Default)]
struct Numbering {
    /// Each expression's representative: the first expression of its value.
    rep: FastHashMap<ExprId, ExprId>,
    /// Representatives by their operation over representative operands. The type is not part
    /// of the key: the operation and its operands decide it (a constructor names its type).
    by_value: FastHashMap<ExprKind, ExprId>,
    /// Per representative: its operation over representative operands.
    canonical: FastHashMap<ExprId, ExprKind>,
    /// Per representative: the expressions that compute its value.
    members: FastHashMap<ExprId, Vec<ExprId>>,
    /// Per representative: how many times the statement uses the value.
    uses: FastHashMap<ExprId, u32>,
    /// Representatives in post-order of first use.
    order: Vec<ExprId>,
}

impl Numbering {
    fn clear(&mut self) {
        self.rep.clear();
        self.by_value.clear();
        self.canonical.clear();
        self.members.clear();
        self.uses.clear();
        self.order.clear();
    }

    fn number(&mut self, f: &Function, id: ExprId) -> ExprId {
        if let Some(&rep) = self.rep.get(&id) {
            return rep;
        }
        let mut kind = f.expr(id).kind.clone();
        kind.for_each_operand_mut(|op| *op = self.number(f, *op));
        let rep = match self.by_value.get(&kind) {
            Some(&rep) => rep,
            None => {
                self.by_value.insert(kind.clone(), id);
                self.canonical.insert(id, kind);
                id
            }
        };
        self.rep.insert(id, rep);
        self.members.entry(rep).or_default().push(id);
        rep
    }

    /// Counts each value's uses, and lists the values in post-order of first use.
    fn count_uses(&mut self, rep: ExprId) {
        let n = self.uses.entry(rep).or_insert(0);
        *n += 1;
        if *n > 1 {
            return;
        }
        let mut operands = Vec::new();
        if let Some(kind) = self.canonical.get(&rep) {
            kind.for_each_operand(|op| operands.push(op));
        }
        for op in operands {
            self.count_uses(op);
        }
        self.order.push(rep);
    }
}

/// Whether re-reading `id` costs nothing worth a name: a name, a literal, a field, component or
/// element of one, or a constant vector.
fn is_cheap(f: &Function, id: ExprId) -> bool {
    match &f.expr(id).kind {
        ExprKind::Literal(_) | ExprKind::Arg(_) | ExprKind::Local(_) | ExprKind::Global(_) => true,
        ExprKind::Member(a, _) | ExprKind::Swizzle(a, _) => is_cheap(f, *a),
        ExprKind::Index(a, i) => is_cheap(f, *a) && is_cheap(f, *i),
        ExprKind::Construct(_, args) => args
            .iter()
            .all(|a| matches!(f.expr(*a).kind, ExprKind::Literal(_))),
        _ => false,
    }
}

/// Moves the computation of `ids` (one value) into a new `let` local and makes each of them
/// read it; returns the local and the expression the `let` binds.
fn bind(f: &mut Function, ids: &[ExprId], base: &str) -> (LocalId, ExprId) {
    let original = f.expr(ids[0]).clone();
    let ty = original.ty;
    let value = ExprId(f.exprs.len() as u32);
    f.exprs.push(original);
    let name = unique_name(f, base);
    let local = LocalId(f.locals.len() as u32);
    f.locals.push(Local {
        name,
        ty,
        mutable: false,
    });
    for id in ids {
        f.exprs[id.0 as usize] = Expr {
            kind: ExprKind::Local(local),
            ty,
        };
    }
    (local, value)
}

fn unique_name(f: &Function, base: &str) -> String {
    let taken = |n: &str| f.locals.iter().any(|l| l.name == n);
    (1..)
        .map(|i| format!("{base}_part{i}"))
        .find(|n| !taken(n))
        .unwrap_or_else(|| format!("{base}_part"))
}
