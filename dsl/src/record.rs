//! The recorder: a thread-local stack of functions under construction. DSL values are plain
//! `Copy` handles, so operators (`a + b`) append nodes here without threading a context through
//! user code, and statements (`let`, `if`, `return`) append to the innermost open block.
//!
//! Using the DSL outside [`crate::ModuleBuilder::build`] is a programming error in the shader
//! library (not in user data), and panics with a message that says so.

use std::cell::RefCell;
use std::collections::{BTreeMap, HashSet};

use crate::ir::{
    Block, Expr, ExprId, ExprKind, Function, Global, Local, LocalId, Module, Param, SourceLoc,
    Stmt, StructDef, Type,
};

struct FnFrame {
    function: Function,
    blocks: Vec<Block>,
    used_names: HashSet<String>,
    /// Loop counters: `var`s that only their `for` changes, between iterations.
    counters: HashSet<LocalId>,
}

struct ModuleRecorder {
    module: Module,
    frames: Vec<FnFrame>,
    /// Functions whose recording has started (finished or in progress), by WGSL name, with the
    /// generation-time values they were specialised for.
    started: BTreeMap<String, Vec<String>>,
    next_temp: u32,
    /// Functions recorded again with other generation-time values under the same name.
    clashes: Vec<SpecialisationClash>,
    /// Other problems found while recording a function body (reported by the module builder).
    errors: Vec<String>,
}

thread_local! {
    static RECORDER: RefCell<Option<ModuleRecorder>> = const { RefCell::new(None) };
}

fn with<R>(f: impl FnOnce(&mut ModuleRecorder) -> R) -> R {
    RECORDER.with(|cell| {
        let mut guard = cell.borrow_mut();
        let rec = guard.as_mut().expect(
            "a DSL value was used outside ModuleBuilder::build: shader code can only be recorded inside a module",
        );
        f(rec)
    })
}

fn with_frame<R>(f: impl FnOnce(&mut FnFrame) -> R) -> R {
    with(|rec| {
        let frame = rec
            .frames
            .last_mut()
            .expect("a DSL expression was built outside a function body");
        f(frame)
    })
}

/// Starts recording a module; returns `false` if one is already being recorded on this thread.
pub(crate) fn begin_module(module: Module) -> bool {
    RECORDER.with(|cell| {
        let mut guard = cell.borrow_mut();
        if guard.is_some() {
            return false;
        }
        *guard = Some(ModuleRecorder {
            module,
            frames: Vec::new(),
            started: BTreeMap::new(),
            next_temp: 0,
            clashes: Vec::new(),
            errors: Vec::new(),
        });
        true
    })
}

/// Ends recording and hands back the module, even after a panic in user code (the guard in
/// `ModuleBuilder::build` calls this on unwind so a failed build cannot poison the thread).
/// A function recorded twice in one module with different generation-time values and the same
/// name (its `SpecValue` suffix does not tell the values apart).
#[derive(Clone, Debug, PartialEq)]
pub struct SpecialisationClash {
    pub function: String,
    pub first: String,
    pub second: String,
}

/// The clashes recorded so far in the current module.
pub(crate) fn take_clashes() -> Vec<SpecialisationClash> {
    RECORDER.with(|cell| {
        cell.borrow_mut()
            .as_mut()
            .map(|r| std::mem::take(&mut r.clashes))
            .unwrap_or_default()
    })
}

/// Notes a problem found while recording; the module builder returns it as an error.
pub(crate) fn push_error(message: String) {
    with(|rec| rec.errors.push(message));
}

/// The problems noted so far in the current module.
pub(crate) fn take_errors() -> Vec<String> {
    RECORDER.with(|cell| {
        cell.borrow_mut()
            .as_mut()
            .map(|r| std::mem::take(&mut r.errors))
            .unwrap_or_default()
    })
}

pub(crate) fn end_module() -> Option<Module> {
    RECORDER.with(|cell| cell.borrow_mut().take().map(|r| r.module))
}

/// Appends an expression node to the current function and returns its handle.
pub fn push_expr(kind: ExprKind, ty: Type) -> ExprId {
    with_frame(|frame| {
        let id = ExprId(frame.function.exprs.len() as u32);
        frame.function.exprs.push(Expr { kind, ty });
        id
    })
}

/// The type of an expression of the current function.
pub fn expr_type(id: ExprId) -> Type {
    with_frame(|frame| frame.function.exprs[id.0 as usize].ty)
}

/// The node of an expression of the current function (used by folding helpers).
pub fn expr_kind(id: ExprId) -> ExprKind {
    with_frame(|frame| frame.function.exprs[id.0 as usize].kind.clone())
}

/// The value of an expression known when the shader is generated: a literal, a named module
/// constant's value, or integer arithmetic (`-`, `+`, `-`, `*`) of those (`-TAPS..TAPS + 1`).
pub fn known_value(id: ExprId) -> Option<crate::ir::Literal> {
    use crate::ir::{BinaryOp, Literal, UnaryOp};
    match expr_kind(id) {
        ExprKind::Literal(l) => Some(l),
        ExprKind::Global(g) => with(|rec| match rec.module.globals.get(g.0 as usize)?.kind {
            crate::ir::GlobalKind::Const { value } => Some(value),
            _ => None,
        }),
        ExprKind::Unary(UnaryOp::Neg, a) => match known_value(a)? {
            Literal::I32(v) => v.checked_neg().map(Literal::I32),
            _ => None,
        },
        ExprKind::Binary(op, a, b) => {
            let (a, b) = (known_value(a)?, known_value(b)?);
            match (a, b) {
                (Literal::I32(x), Literal::I32(y)) => match op {
                    BinaryOp::Add => x.checked_add(y),
                    BinaryOp::Sub => x.checked_sub(y),
                    BinaryOp::Mul => x.checked_mul(y),
                    _ => None,
                }
                .map(Literal::I32),
                (Literal::U32(x), Literal::U32(y)) => match op {
                    BinaryOp::Add => x.checked_add(y),
                    BinaryOp::Sub => x.checked_sub(y),
                    BinaryOp::Mul => x.checked_mul(y),
                    _ => None,
                }
                .map(Literal::U32),
                _ => None,
            }
        }
        _ => None,
    }
}

/// Appends a statement to the innermost open block.
pub fn push_stmt(stmt: Stmt) {
    with_frame(|frame| {
        frame
            .blocks
            .last_mut()
            .expect("function frame always has a block")
            .push(stmt);
    });
}

/// Opens a nested block (the body of an `if` arm or a loop).
pub fn begin_block() {
    with_frame(|frame| frame.blocks.push(Block::new()));
}

/// Closes the innermost block and returns its statements.
pub fn end_block() -> Block {
    with_frame(|frame| frame.blocks.pop().expect("end_block without begin_block"))
}

/// Declares a local with a name unique in the current function, derived from `wanted`.
pub fn new_local(wanted: &str, ty: Type, mutable: bool) -> LocalId {
    with_frame(|frame| {
        let base = sanitize(wanted);
        let mut name = base.clone();
        let mut n = 1;
        while frame.used_names.contains(&name) {
            name = format!("{base}_{n}");
            n += 1;
        }
        frame.used_names.insert(name.clone());
        let id = LocalId(frame.function.locals.len() as u32);
        frame.function.locals.push(Local { name, ty, mutable });
        id
    })
}

/// Marks `local` as the counter of a `for` loop.
pub(crate) fn mark_counter(local: LocalId) {
    with_frame(|frame| {
        frame.counters.insert(local);
    });
}

/// Whether `id` names a place in a resource that no statement of the function can change: a
/// uniform, texture, sampler or constant, a member of one, or an element at an index that
/// stays put (a literal, a parameter, a `let`, a loop counter). Naming such a place with `let`
/// aliases it instead of copying it: `let e = LIGHTS.get().exposure;` reads `lights.exposure` where
/// it is used, as a hand-written shader would, and a texture or sampler (which WGSL cannot
/// hold in a `let`) can be named at all.
pub(crate) fn is_resource_place(id: ExprId) -> bool {
    with(|rec| {
        let frame = rec.frames.last().expect("inside a function");
        let f = &frame.function;
        let stable_index = |i: ExprId| match &f.exprs[i.0 as usize].kind {
            ExprKind::Literal(_) | ExprKind::Arg(_) => true,
            ExprKind::Local(l) => !f.locals[l.0 as usize].mutable || frame.counters.contains(l),
            _ => false,
        };
        let mut at = id;
        loop {
            match &f.exprs[at.0 as usize].kind {
                ExprKind::Global(g) => {
                    return !matches!(
                        rec.module.globals[g.0 as usize].kind,
                        crate::ir::GlobalKind::Storage { .. } | crate::ir::GlobalKind::Private
                    );
                }
                ExprKind::Member(base, _) => at = *base,
                ExprKind::Index(base, i) if stable_index(*i) => at = *base,
                _ => return false,
            }
        }
    })
}

/// A fresh name for a compiler-introduced temporary (`branch_0`, ...).
pub fn temp_name(prefix: &str) -> String {
    with(|rec| {
        let n = rec.next_temp;
        rec.next_temp += 1;
        format!("{prefix}_{n}")
    })
}

/// Registers a struct type so the printer declares it once, before its first use.
pub fn use_struct(def: &'static StructDef) {
    with(|rec| push_struct(&mut rec.module.structs, def));
}

fn push_struct(structs: &mut Vec<&'static StructDef>, def: &'static StructDef) {
    if structs.iter().any(|s| s.name == def.name) {
        return;
    }
    // Nested structs are declared before the struct that contains them.
    for field in def.fields {
        let mut ty = field.ty;
        while let Type::Array(elem, _) = ty {
            ty = *elem;
        }
        if let Type::Struct(inner) = ty {
            push_struct(structs, inner);
        }
    }
    structs.push(def);
}

/// The index of a global equal to `global`, if the module has one.
pub(crate) fn find_global(global: &Global) -> Option<crate::ir::GlobalId> {
    with(|rec| {
        rec.module
            .globals
            .iter()
            .position(|g| g == global)
            .map(|i| crate::ir::GlobalId(i as u32))
    })
}

/// Declares a module global and returns its index; a repeated name returns the existing one
/// when it has the same type and kind.
pub(crate) fn add_global(global: Global) -> Result<crate::ir::GlobalId, String> {
    with(|rec| {
        if let Some(i) = rec
            .module
            .globals
            .iter()
            .position(|g| g.name == global.name)
        {
            if rec.module.globals[i] == global {
                return Ok(crate::ir::GlobalId(i as u32));
            }
            return Err(format!(
                "global `{}` is declared twice with different types or bindings",
                global.name
            ));
        }
        if let Some(b) = global.binding()
            && let Some(other) = rec.module.globals.iter().find(|g| g.binding() == Some(b))
        {
            return Err(format!(
                "globals `{}` and `{}` both use @group({}) @binding({})",
                other.name, global.name, b.0, b.1
            ));
        }
        if let Type::Struct(def) = global.ty {
            push_struct(&mut rec.module.structs, def);
        }
        rec.module.globals.push(global);
        Ok(crate::ir::GlobalId(rec.module.globals.len() as u32 - 1))
    })
}

/// Records `name` unless it was already started, by running `record` in a fresh frame.
///
/// `record` receives the parameter expressions and returns the body's result. Returns the WGSL
/// name to call.
pub fn ensure_function(
    header: FunctionHeader,
    record: impl FnOnce(&[ExprId]) -> Option<ExprId>,
) -> String {
    let name = header.name.clone();
    let previous = with(|rec| rec.started.insert(name.clone(), header.specialised.clone()));
    if let Some(previous) = previous {
        if previous != header.specialised {
            // Recording goes on (the first copy is called); the module builder reports it.
            with(|rec| {
                // The copy in the module is the first one: keep comparing against it.
                rec.started.insert(name.clone(), previous.clone());
                rec.clashes.push(SpecialisationClash {
                    function: name.clone(),
                    first: previous.join(", "),
                    second: header.specialised.join(", "),
                })
            });
        }
        return name;
    }
    let params = header.params.clone();
    let function = Function {
        name: header.name,
        rust_name: header.rust_name,
        doc: header.doc,
        specialised: header.specialised,
        params: params.clone(),
        result: header.result,
        locals: Vec::new(),
        exprs: Vec::new(),
        body: Vec::new(),
        loc: header.loc,
    };
    with(|rec| {
        rec.frames.push(FnFrame {
            function,
            blocks: vec![Block::new()],
            used_names: params.iter().map(|p| p.name.clone()).collect(),
            counters: HashSet::new(),
        })
    });
    let args: Vec<ExprId> = params
        .iter()
        .enumerate()
        .map(|(i, p)| push_expr(ExprKind::Arg(i as u32), p.ty))
        .collect();
    if let Some(value) = record(&args) {
        push_stmt(Stmt::Return {
            value: Some(value),
            loc: header.loc,
        });
    }
    with(|rec| {
        let mut frame = rec.frames.pop().expect("frame pushed above");
        frame.function.body = frame.blocks.pop().expect("root block");
        rec.module.functions.push(frame.function);
    });
    name
}

/// Adds an entry point description (its function must have been recorded already).
pub(crate) fn add_entry_point(ep: crate::ir::EntryPoint) {
    with(|rec| rec.module.entry_points.push(ep));
}

/// Everything about a function except its body.
#[derive(Clone, Debug)]
pub struct FunctionHeader {
    pub name: String,
    pub rust_name: String,
    pub doc: Vec<String>,
    pub specialised: Vec<String>,
    pub params: Vec<Param>,
    pub result: Option<Type>,
    pub loc: SourceLoc,
}

/// Makes a Rust identifier a safe, readable WGSL identifier.
pub fn sanitize(name: &str) -> String {
    let mut s: String = name
        .trim_start_matches("r#")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, 'v');
    }
    // A leading `__` is reserved in WGSL; `_e<N>` would look like naga's temporaries.
    while s.starts_with("__") {
        s.remove(0);
    }
    if s == "_" {
        s = "unused".to_string();
    }
    // Keywords, reserved words and shadowed built-ins are renamed by codegen, by naga's lists,
    // only where WGSL requires it.
    s
}
