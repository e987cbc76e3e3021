//! The DSL's IR lowered straight to a `naga::Module`: no WGSL text in between.
//!
//! The printed WGSL is for people (review, snapshots, WebGPU hosts); the module every backend
//! and the wgpu runtime consume is built here, node by node, the way naga's WGSL front end would
//! build it from that text:
//! - pointers stay pointers until a value is needed: `params.sun.direction.x` is a chain of
//!   `AccessIndex` on the uniform's pointer and one `Load` (a backend then reads one component,
//!   never copies the block);
//! - a scalar meeting a vector in `+ - / %` is splatted (naga's IR, unlike WGSL, wants equal
//!   operand types there; `*` takes the mixed form as it is);
//! - every expression that needs it is covered by an `Emit`; `Call` results and the handles that
//!   need none (literals, arguments, globals, locals) stay outside;
//! - `for` becomes a `Loop` whose first statement breaks when the bound is reached and whose
//!   `continuing` block steps the counter, so `continue` still steps it.
//!
//! Each statement's expressions are lowered afresh, as the printer prints them afresh: a value
//! recorded once and used by two statements may read a `var` that changed in between. Within one
//! statement a shared node is lowered once.

use std::collections::HashMap;

use naga::proc::{Emitter, ExpressionKind, ExpressionKindTracker, Layouter};
use naga::{Arena, Block, Expression, Handle, MathFunction, Span, Statement, TypeInner};
use nimbus_dsl::ir::{
    self, BinaryOp, Builtin, ExprId, ExprKind, GlobalKind, Io, Literal, LocalId, SampleKind,
    Scalar, Stage, Stmt, Type, UnaryOp,
};

use crate::error::CodegenError;

/// A lowered module, with where each of the IR's globals went.
pub struct Lowered {
    pub module: naga::Module,
    /// `globals[i]` is the naga global variable of the IR's global `i` (resources and
    /// per-invocation state; `None` for constants and overrides).
    pub globals: Vec<Option<Handle<naga::GlobalVariable>>>,
}

/// What one of the IR's globals became.
#[derive(Clone, Copy)]
enum GlobalRef {
    /// A resource or private variable: a pointer, or for textures and samplers the handle
    /// itself.
    Var {
        handle: Handle<naga::GlobalVariable>,
        is_handle: bool,
    },
    Constant(Handle<naga::Constant>),
    Override(Handle<naga::Override>),
}

/// Why lowering stopped: a literal WGSL cannot spell, or IR the lowering does not know how to
/// express (a bug here; the caller falls back to the printed WGSL for a located error).
pub(crate) enum LowerError {
    Codegen(CodegenError),
    Unsupported(String),
}

impl From<CodegenError> for LowerError {
    fn from(e: CodegenError) -> Self {
        LowerError::Codegen(e)
    }
}

fn unsupported<T>(what: impl Into<String>) -> Result<T, LowerError> {
    Err(LowerError::Unsupported(what.into()))
}

fn scalar(s: Scalar) -> naga::Scalar {
    match s {
        Scalar::F32 => naga::Scalar::F32,
        Scalar::I32 => naga::Scalar::I32,
        Scalar::U32 => naga::Scalar::U32,
        Scalar::Bool => naga::Scalar::BOOL,
    }
}

fn vector_size(n: u8) -> Result<naga::VectorSize, LowerError> {
    Ok(match n {
        2 => naga::VectorSize::Bi,
        3 => naga::VectorSize::Tri,
        4 => naga::VectorSize::Quad,
        _ => return unsupported(format!("a vector of {n} components")),
    })
}

fn stage(s: Stage) -> naga::ShaderStage {
    match s {
        Stage::Vertex => naga::ShaderStage::Vertex,
        Stage::Fragment => naga::ShaderStage::Fragment,
        Stage::Compute => naga::ShaderStage::Compute,
    }
}

fn literal(l: Literal) -> Option<naga::Literal> {
    Some(match l {
        Literal::F32(bits) => {
            let v = f32::from_bits(bits);
            if !v.is_finite() {
                return None;
            }
            naga::Literal::F32(v)
        }
        Literal::I32(v) => naga::Literal::I32(v),
        Literal::U32(v) => naga::Literal::U32(v),
        Literal::Bool(v) => naga::Literal::Bool(v),
    })
}

/// naga's math function for a built-in; `None` for `select`, an expression of its own there.
fn math(b: Builtin) -> Option<MathFunction> {
    Some(match b {
        Builtin::Abs => MathFunction::Abs,
        Builtin::Ceil => MathFunction::Ceil,
        Builtin::Clamp => MathFunction::Clamp,
        Builtin::Cos => MathFunction::Cos,
        Builtin::Cross => MathFunction::Cross,
        Builtin::Distance => MathFunction::Distance,
        Builtin::Dot => MathFunction::Dot,
        Builtin::Exp => MathFunction::Exp,
        Builtin::Exp2 => MathFunction::Exp2,
        Builtin::Floor => MathFunction::Floor,
        Builtin::Fract => MathFunction::Fract,
        Builtin::InverseSqrt => MathFunction::InverseSqrt,
        Builtin::Length => MathFunction::Length,
        Builtin::Log => MathFunction::Log,
        Builtin::Log2 => MathFunction::Log2,
        Builtin::Max => MathFunction::Max,
        Builtin::Min => MathFunction::Min,
        Builtin::Mix => MathFunction::Mix,
        Builtin::Normalize => MathFunction::Normalize,
        Builtin::Pow => MathFunction::Pow,
        Builtin::Round => MathFunction::Round,
        Builtin::Select => return None,
        Builtin::Sign => MathFunction::Sign,
        Builtin::Sin => MathFunction::Sin,
        Builtin::Smoothstep => MathFunction::SmoothStep,
        Builtin::Sqrt => MathFunction::Sqrt,
        Builtin::Step => MathFunction::Step,
        Builtin::Tan => MathFunction::Tan,
        Builtin::Trunc => MathFunction::Trunc,
        Builtin::Atan2 => MathFunction::Atan2,
        Builtin::Acos => MathFunction::Acos,
        Builtin::Asin => MathFunction::Asin,
        Builtin::Atan => MathFunction::Atan,
        Builtin::Fma => MathFunction::Fma,
        Builtin::Saturate => MathFunction::Saturate,
        Builtin::Pack4x8Unorm => MathFunction::Pack4x8unorm,
    })
}

fn binary(op: BinaryOp) -> naga::BinaryOperator {
    use naga::BinaryOperator as B;
    match op {
        BinaryOp::Add => B::Add,
        BinaryOp::Sub => B::Subtract,
        BinaryOp::Mul => B::Multiply,
        BinaryOp::Div => B::Divide,
        BinaryOp::Rem => B::Modulo,
        BinaryOp::Lt => B::Less,
        BinaryOp::Le => B::LessEqual,
        BinaryOp::Gt => B::Greater,
        BinaryOp::Ge => B::GreaterEqual,
        BinaryOp::Eq => B::Equal,
        BinaryOp::Ne => B::NotEqual,
        BinaryOp::And => B::LogicalAnd,
        BinaryOp::Or => B::LogicalOr,
        BinaryOp::BitAnd => B::And,
        BinaryOp::BitOr => B::InclusiveOr,
        BinaryOp::BitXor => B::ExclusiveOr,
        BinaryOp::Shl => B::ShiftLeft,
        BinaryOp::Shr => B::ShiftRight,
    }
}

/// The IR's types as naga types, each inserted once, structs laid out by WGSL's rules (the
/// offsets naga's front end would compute, and so the ones `nimbus_dsl::layout` mirrors).
struct Types {
    map: HashMap<Type, Handle<naga::Type>>,
    layouter: Layouter,
}

impl Types {
    fn get(&mut self, m: &mut naga::Module, ty: Type) -> Result<Handle<naga::Type>, LowerError> {
        if let Some(h) = self.map.get(&ty) {
            return Ok(*h);
        }
        let inner = match ty {
            Type::Scalar(s) => TypeInner::Scalar(scalar(s)),
            Type::Vector(n, s) => TypeInner::Vector {
                size: vector_size(n)?,
                scalar: scalar(s),
            },
            Type::Matrix(n) => TypeInner::Matrix {
                columns: vector_size(n)?,
                rows: vector_size(n)?,
                scalar: naga::Scalar::F32,
            },
            Type::Struct(def) => {
                let mut fields = Vec::with_capacity(def.fields.len());
                for f in def.fields {
                    fields.push((f.name, self.get(m, f.ty)?));
                }
                self.update(m)?;
                let (mut offset, mut align) = (0u32, naga::proc::Alignment::ONE);
                let mut members = Vec::with_capacity(fields.len());
                for (name, h) in fields {
                    let layout = self.layouter[h];
                    offset = layout.alignment.round_up(offset);
                    align = align.max(layout.alignment);
                    members.push(naga::StructMember {
                        name: Some(name.to_string()),
                        ty: h,
                        binding: None,
                        offset,
                    });
                    offset += layout.size;
                }
                TypeInner::Struct {
                    members,
                    span: align.round_up(offset),
                }
            }
            Type::Array(elem, n) => {
                let base = self.get(m, *elem)?;
                self.update(m)?;
                let Some(size) = std::num::NonZeroU32::new(n) else {
                    return unsupported("an array of no elements");
                };
                TypeInner::Array {
                    base,
                    size: naga::ArraySize::Constant(size),
                    stride: self.layouter[base].to_stride(),
                }
            }
            Type::RuntimeArray(s) => {
                let base = self.get(m, Type::Scalar(s))?;
                self.update(m)?;
                TypeInner::Array {
                    base,
                    size: naga::ArraySize::Dynamic,
                    stride: self.layouter[base].to_stride(),
                }
            }
            Type::Texture2d | Type::Texture3d => TypeInner::Image {
                dim: if ty == Type::Texture2d {
                    naga::ImageDimension::D2
                } else {
                    naga::ImageDimension::D3
                },
                arrayed: false,
                class: naga::ImageClass::Sampled {
                    kind: naga::ScalarKind::Float,
                    multi: false,
                },
            },
            Type::Sampler => TypeInner::Sampler { comparison: false },
        };
        let name = match ty {
            Type::Struct(def) => Some(def.name.to_string()),
            _ => None,
        };
        let h = m.types.insert(naga::Type { name, inner }, Span::UNDEFINED);
        self.map.insert(ty, h);
        Ok(h)
    }

    fn update(&mut self, m: &naga::Module) -> Result<(), LowerError> {
        self.layouter
            .update(m.to_ctx())
            .map_err(|e| LowerError::Unsupported(format!("a type naga cannot lay out: {e}")))
    }
}

/// The order a reader scans a hand-written shader's header in: constants, overrides, resources
/// by (group, binding), per-invocation state. The printer and the lowering declare globals in
/// it, so every backend lists them as the WGSL does.
pub(crate) fn declaration_order(module: &ir::Module) -> Vec<usize> {
    let mut order: Vec<usize> = (0..module.globals.len()).collect();
    order.sort_by_key(|&i| match module.globals[i].kind {
        GlobalKind::Const { .. } => (0, 0, 0),
        GlobalKind::Override { .. } => (1, 0, 0),
        GlobalKind::Uniform { group, binding }
        | GlobalKind::Storage { group, binding, .. }
        | GlobalKind::Handle { group, binding } => (2, group, binding),
        GlobalKind::Private => (3, 0, 0),
    });
    order
}

/// What a lowering is for.
#[derive(Clone, Copy)]
pub(crate) enum Lowering<'a> {
    /// The whole module, overrides kept: the gate, the wgpu runtime's module, the WGSL's twin.
    Whole,
    /// One entry point and only what it reaches, each override a constant of its default: what
    /// naga's other back ends translate (no `process_overrides`, no compaction, one validation).
    Baked { entry: &'a str },
}

/// The functions `entry` calls, directly or not, and the globals they read, by index.
fn reached(module: &ir::Module, entry: &str) -> (Vec<bool>, Vec<bool>) {
    let mut functions = vec![false; module.functions.len()];
    let mut globals = vec![false; module.globals.len()];
    let index = |name: &str| module.functions.iter().position(|f| f.name == name);
    let mut stack: Vec<usize> = index(entry).into_iter().collect();
    while let Some(i) = stack.pop() {
        if std::mem::replace(&mut functions[i], true) {
            continue;
        }
        // Only what the statements reach: specialisation leaves dead nodes in the arena, which
        // may name globals it removed.
        let f = &module.functions[i];
        crate::specialise::walk_block(f, &f.body, &mut |id| match &f.expr(id).kind {
            ExprKind::Call(name, _) => stack.extend(index(name)),
            ExprKind::Global(g) => {
                if let Some(used) = globals.get_mut(g.0 as usize) {
                    *used = true;
                }
            }
            _ => {}
        });
    }
    (functions, globals)
}

/// Lowers a specialised, renamed module.
pub(crate) fn lower(module: &ir::Module, lowering: Lowering) -> Result<Lowered, LowerError> {
    let mut m = naga::Module::default();
    let mut types = Types {
        map: HashMap::new(),
        layouter: Layouter::default(),
    };
    // Structs in the order the printer declares them (a baked entry point's unused ones are
    // compacted away at the end).
    for s in &module.structs {
        types.get(&mut m, Type::Struct(s))?;
    }
    let (reached_fns, reached_globals) = match lowering {
        Lowering::Whole => (
            vec![true; module.functions.len()],
            vec![true; module.globals.len()],
        ),
        Lowering::Baked { entry } => reached(module, entry),
    };
    let baked = matches!(lowering, Lowering::Baked { .. });
    let mut refs: Vec<Option<GlobalRef>> = vec![None; module.globals.len()];
    for i in declaration_order(module) {
        if !reached_globals[i] {
            continue;
        }
        let g = &module.globals[i];
        let ty = types.get(&mut m, g.ty)?;
        let value = |m: &mut naga::Module, l: Literal| match literal(l) {
            Some(lit) => Ok(m
                .global_expressions
                .append(Expression::Literal(lit), Span::UNDEFINED)),
            None => unsupported(format!("the non-finite value of `{}`", g.name)),
        };
        let var = |space, binding: Option<(u32, u32)>| naga::GlobalVariable {
            name: Some(g.name.clone()),
            space,
            binding: binding.map(|(group, binding)| naga::ResourceBinding { group, binding }),
            ty,
            init: None,
            memory_decorations: naga::MemoryDecorations::empty(),
        };
        refs[i] = Some(match g.kind {
            GlobalKind::Uniform { group, binding } => GlobalRef::Var {
                handle: m.global_variables.append(
                    var(naga::AddressSpace::Uniform, Some((group, binding))),
                    Span::UNDEFINED,
                ),
                is_handle: false,
            },
            GlobalKind::Storage {
                group,
                binding,
                read_write,
            } => {
                let access = if read_write {
                    naga::StorageAccess::LOAD | naga::StorageAccess::STORE
                } else {
                    naga::StorageAccess::LOAD
                };
                GlobalRef::Var {
                    handle: m.global_variables.append(
                        var(
                            naga::AddressSpace::Storage { access },
                            Some((group, binding)),
                        ),
                        Span::UNDEFINED,
                    ),
                    is_handle: false,
                }
            }
            GlobalKind::Handle { group, binding } => GlobalRef::Var {
                handle: m.global_variables.append(
                    var(naga::AddressSpace::Handle, Some((group, binding))),
                    Span::UNDEFINED,
                ),
                is_handle: true,
            },
            GlobalKind::Private => GlobalRef::Var {
                handle: m
                    .global_variables
                    .append(var(naga::AddressSpace::Private, None), Span::UNDEFINED),
                is_handle: false,
            },
            // A module constant, or an override: kept as one for the whole module, fixed at its
            // default (a constant) in a baked entry point.
            GlobalKind::Const { value: v } | GlobalKind::Override { default: v } => {
                let init = value(&mut m, v)?;
                if matches!(g.kind, GlobalKind::Override { .. }) && !baked {
                    GlobalRef::Override(m.overrides.append(
                        naga::Override {
                            name: Some(g.name.clone()),
                            id: None,
                            ty,
                            init: Some(init),
                        },
                        Span::UNDEFINED,
                    ))
                } else {
                    GlobalRef::Constant(m.constants.append(
                        naga::Constant {
                            name: Some(g.name.clone()),
                            ty,
                            init,
                        },
                        Span::UNDEFINED,
                    ))
                }
            }
        });
    }
    let mut functions: HashMap<&str, Handle<naga::Function>> = HashMap::new();
    for (f, _) in module
        .functions
        .iter()
        .zip(&reached_fns)
        .filter(|(_, reached)| **reached)
    {
        let entry = module.entry_point(&f.name);
        let lowered = FnLower::new(f, &mut m, &mut types, &refs, &functions, entry)?.run()?;
        match entry {
            Some(ep) => m.entry_points.push(naga::EntryPoint {
                name: f.name.clone(),
                stage: stage(ep.stage),
                early_depth_test: None,
                workgroup_size: if ep.stage == Stage::Compute {
                    ep.workgroup_size
                } else {
                    [0; 3]
                },
                workgroup_size_overrides: None,
                function: lowered,
                mesh_info: None,
                task_payload: None,
                incoming_ray_payload: None,
            }),
            None => {
                let h = m.functions.append(lowered, Span::UNDEFINED);
                functions.insert(f.name.as_str(), h);
            }
        }
    }
    let globals = refs
        .iter()
        .map(|r| match r {
            Some(GlobalRef::Var { handle, .. }) => Some(*handle),
            _ => None,
        })
        .collect();
    if baked {
        // Types only another entry point uses; no handle the caller keeps is renumbered.
        naga::compact::compact(&mut m, naga::compact::KeepUnused::No);
    }
    Ok(Lowered { module: m, globals })
}

/// A declared `var`: the variable, the pointer that names it, and its type.
type DeclaredVar = (
    Handle<naga::LocalVariable>,
    Handle<Expression>,
    Handle<naga::Type>,
);

/// How an IR local is reached.
#[derive(Clone, Copy)]
enum LocalSlot {
    /// A `let` not yet bound.
    Unbound,
    /// A `let`: the expression it names.
    Let(Handle<Expression>),
    /// A `var`: the pointer to its local variable.
    Var(Handle<Expression>),
}

/// One function being lowered.
struct FnLower<'a> {
    f: &'a ir::Function,
    m: &'a mut naga::Module,
    types: &'a mut Types,
    globals: &'a [Option<GlobalRef>],
    functions: &'a HashMap<&'a str, Handle<naga::Function>>,
    out: naga::Function,
    args: Vec<Handle<Expression>>,
    locals: Vec<LocalSlot>,
    /// Handles that need no `Emit`, made once per function.
    global_exprs: HashMap<usize, Handle<Expression>>,
    emitter: Emitter,
    /// Which expressions are constant, for naga's constant evaluator.
    kinds: ExpressionKindTracker,
    /// Nodes lowered in the current statement.
    memo: HashMap<ExprId, Handle<Expression>>,
    loop_depth: u32,
}

impl<'a> FnLower<'a> {
    fn new(
        f: &'a ir::Function,
        m: &'a mut naga::Module,
        types: &'a mut Types,
        globals: &'a [Option<GlobalRef>],
        functions: &'a HashMap<&'a str, Handle<naga::Function>>,
        entry: Option<&ir::EntryPoint>,
    ) -> Result<Self, LowerError> {
        let mut arguments = Vec::with_capacity(f.params.len());
        for (i, p) in f.params.iter().enumerate() {
            let ty = types.get(m, p.ty)?;
            let binding = entry
                .and_then(|e| e.inputs.get(i))
                .map(|io| binding(*io, &m.types[ty].inner));
            arguments.push(naga::FunctionArgument {
                name: Some(p.name.clone()),
                ty,
                binding,
            });
        }
        let result = match f.result {
            Some(t) => {
                let ty = types.get(m, t)?;
                let binding = entry
                    .and_then(|e| e.output)
                    .map(|io| binding(io, &m.types[ty].inner));
                Some(naga::FunctionResult { ty, binding })
            }
            None => None,
        };
        let mut out = naga::Function {
            name: Some(f.name.clone()),
            arguments,
            result,
            local_variables: Arena::new(),
            expressions: Arena::new(),
            named_expressions: Default::default(),
            body: Block::new(),
            diagnostic_filter_leaf: None,
        };
        let mut args = Vec::with_capacity(f.params.len());
        let mut kinds = ExpressionKindTracker::new();
        for (i, p) in f.params.iter().enumerate() {
            let h = out
                .expressions
                .append(Expression::FunctionArgument(i as u32), Span::UNDEFINED);
            out.named_expressions.insert(h, p.name.clone());
            kinds.insert(h, ExpressionKind::Runtime);
            args.push(h);
        }
        Ok(Self {
            f,
            m,
            types,
            globals,
            functions,
            out,
            args,
            kinds,
            locals: vec![LocalSlot::Unbound; f.locals.len()],
            global_exprs: HashMap::new(),
            emitter: Emitter::default(),
            memo: HashMap::new(),
            loop_depth: 0,
        })
    }

    fn run(mut self) -> Result<naga::Function, LowerError> {
        let mut body = Block::new();
        self.block(&self.f.body, &mut body)?;
        naga::proc::ensure_block_returns(&mut body);
        self.out.body = body;
        Ok(self.out)
    }

    fn block(&mut self, stmts: &[Stmt], out: &mut Block) -> Result<(), LowerError> {
        for s in stmts {
            self.stmt(s, out)?;
            if s.diverges() {
                break;
            }
        }
        Ok(())
    }

    /// Appends an expression, outside the running `Emit` range when naga wants it there.
    /// An expression of constants is folded by naga's own constant evaluator first, as its WGSL
    /// front end folds it (`f32(AIR_SHADOW_SAMPLES)` reaches the backends as `4.0`, and no
    /// integer division by a constant is left for them to guard).
    fn append(&mut self, e: Expression, out: &mut Block) -> Handle<Expression> {
        let mut evaluator = naga::proc::ConstantEvaluator::for_wgsl_function(
            self.m,
            &mut self.out.expressions,
            &mut self.kinds,
            &mut self.types.layouter,
            &mut self.emitter,
            out,
            false,
        );
        match evaluator.try_eval_and_append(e.clone(), Span::UNDEFINED) {
            Ok(h) => h,
            // A constant expression naga will not fold (an overflow, say) stays as written,
            // for validation to judge.
            Err(_) => self.append_unfolded(e, out),
        }
    }

    /// Appends an expression as it is, outside the running `Emit` range when naga wants it
    /// there.
    fn append_unfolded(&mut self, e: Expression, out: &mut Block) -> Handle<Expression> {
        let pre_emit = e.needs_pre_emit();
        if pre_emit {
            out.extend(self.emitter.finish(&self.out.expressions));
        }
        let h = self.out.expressions.append(e, Span::UNDEFINED);
        self.kinds.insert(h, ExpressionKind::Runtime);
        if pre_emit {
            self.emitter.start(&self.out.expressions);
        }
        h
    }

    /// Lowers one statement: its expressions, the `Emit` covering them, then the statement.
    fn stmt(&mut self, s: &Stmt, out: &mut Block) -> Result<(), LowerError> {
        self.memo.clear();
        self.emitter.start(&self.out.expressions);
        // On an error the whole lowering stops, so the emitter's state no longer matters.
        let statement = self.stmt_body(s, out)?;
        out.extend(self.emitter.finish(&self.out.expressions));
        if let Some(st) = statement {
            out.push(st, Span::UNDEFINED);
        }
        Ok(())
    }

    fn stmt_body(&mut self, s: &Stmt, out: &mut Block) -> Result<Option<Statement>, LowerError> {
        Ok(match s {
            Stmt::Let { local, value, .. } => {
                let h = self.value(*value, out)?;
                self.locals[local.0 as usize] = LocalSlot::Let(h);
                if !self.out.named_expressions.contains_key(&h)
                    && !self.out.expressions[h].needs_pre_emit()
                {
                    self.out
                        .named_expressions
                        .insert(h, self.f.local(*local).name.clone());
                }
                None
            }
            Stmt::Var { local, init, .. } => {
                let (var, pointer, ty) = self.declare_var(*local, out)?;
                let value = match init {
                    Some(i) => Some(self.value(*i, out)?),
                    // A `var` declared in a loop body starts from zero on every iteration.
                    None if self.loop_depth > 0 => {
                        Some(self.append(Expression::ZeroValue(ty), out))
                    }
                    None => None,
                };
                value.and_then(|value| self.initialise(var, pointer, value))
            }
            Stmt::Assign { local, value, .. } => {
                let LocalSlot::Var(pointer) = self.locals[local.0 as usize] else {
                    return unsupported(format!(
                        "an assignment to `{}`, which is not a `var`",
                        self.f.local(*local).name
                    ));
                };
                let value = self.value(*value, out)?;
                Some(Statement::Store { pointer, value })
            }
            Stmt::Store { target, value, .. } => {
                let Some(pointer) = self.place(*target, out)? else {
                    return unsupported("a store to something that is not a variable");
                };
                let value = self.value(*value, out)?;
                Some(Statement::Store { pointer, value })
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                let condition = self.value(*cond, out)?;
                // The condition's `Emit` precedes the `if`; each arm emits its own.
                out.extend(self.emitter.finish(&self.out.expressions));
                let mut accept = Block::new();
                let mut reject = Block::new();
                self.block(then, &mut accept)?;
                self.block(otherwise, &mut reject)?;
                self.emitter.start(&self.out.expressions);
                Some(Statement::If {
                    condition,
                    accept,
                    reject,
                })
            }
            Stmt::For {
                counter,
                start,
                end,
                body,
                ..
            } => self.for_loop(*counter, *start, *end, body, out)?,
            Stmt::Break { .. } => Some(Statement::Break),
            Stmt::Continue { .. } => Some(Statement::Continue),
            Stmt::Return { value, .. } => {
                let value = match value {
                    Some(v) => Some(self.value(*v, out)?),
                    None => None,
                };
                Some(Statement::Return { value })
            }
        })
    }

    /// `for (var i = start; i < end; i += 1) { body }` as naga's front end builds it: the
    /// counter stored before the loop, the bound tested (and re-read) at the top of each
    /// iteration, the step in `continuing`.
    fn for_loop(
        &mut self,
        counter: LocalId,
        start: ExprId,
        end: ExprId,
        body: &[Stmt],
        out: &mut Block,
    ) -> Result<Option<Statement>, LowerError> {
        let l = self.f.local(counter);
        let (var, pointer, _) = self.declare_var(counter, out)?;
        let first = self.value(start, out)?;
        out.extend(self.emitter.finish(&self.out.expressions));
        if let Some(store) = self.initialise(var, pointer, first) {
            out.push(store, Span::UNDEFINED);
        }

        self.loop_depth += 1;
        let mut looped = Block::new();
        // The bound, lowered inside the loop: WGSL evaluates the condition every iteration.
        self.memo.clear();
        self.emitter.start(&self.out.expressions);
        let i = self.append(Expression::Load { pointer }, &mut looped);
        let bound = self.value(end, &mut looped)?;
        let condition = self.append(
            Expression::Binary {
                op: naga::BinaryOperator::Less,
                left: i,
                right: bound,
            },
            &mut looped,
        );
        looped.extend(self.emitter.finish(&self.out.expressions));
        let mut reject = Block::new();
        reject.push(Statement::Break, Span::UNDEFINED);
        looped.push(
            Statement::If {
                condition,
                accept: Block::new(),
                reject,
            },
            Span::UNDEFINED,
        );
        // The body as a block of its own, as the front end nests it.
        let mut inner = Block::new();
        let walked = self.block(body, &mut inner);
        self.loop_depth -= 1;
        walked?;
        looped.push(Statement::Block(inner), Span::UNDEFINED);

        let mut continuing = Block::new();
        self.emitter.start(&self.out.expressions);
        let one = match l.ty {
            Type::Scalar(Scalar::I32) => naga::Literal::I32(1),
            _ => naga::Literal::U32(1),
        };
        let i = self.append(Expression::Load { pointer }, &mut continuing);
        let one = self.append(Expression::Literal(one), &mut continuing);
        let next = self.append(
            Expression::Binary {
                op: naga::BinaryOperator::Add,
                left: i,
                right: one,
            },
            &mut continuing,
        );
        continuing.extend(self.emitter.finish(&self.out.expressions));
        continuing.push(
            Statement::Store {
                pointer,
                value: next,
            },
            Span::UNDEFINED,
        );
        // The caller's statement emitter runs again for what follows (nothing, for a loop).
        self.emitter.start(&self.out.expressions);
        Ok(Some(Statement::Loop {
            body: looped,
            continuing,
            break_if: None,
        }))
    }

    /// Declares the IR's `var` `local` as a naga local variable: the variable, the pointer
    /// that names it, and its type.
    fn declare_var(&mut self, local: LocalId, out: &mut Block) -> Result<DeclaredVar, LowerError> {
        let l = self.f.local(local);
        let ty = self.types.get(self.m, l.ty)?;
        let var = self.out.local_variables.append(
            naga::LocalVariable {
                name: Some(l.name.clone()),
                ty,
                init: None,
            },
            Span::UNDEFINED,
        );
        let pointer = self.append(Expression::LocalVariable(var), out);
        self.locals[local.0 as usize] = LocalSlot::Var(pointer);
        Ok((var, pointer, ty))
    }

    /// A `var`'s first value: its declared initialiser when that is a constant and the `var`
    /// is not in a loop (as naga's front end hoists it, so `float far = -1.0;` reads as
    /// written), else a store where the declaration stands.
    fn initialise(
        &mut self,
        var: Handle<naga::LocalVariable>,
        pointer: Handle<Expression>,
        value: Handle<Expression>,
    ) -> Option<Statement> {
        let leaf = |e: &Expression| {
            matches!(
                e,
                Expression::Literal(_) | Expression::ZeroValue(_) | Expression::Constant(_)
            )
        };
        let constant = match &self.out.expressions[value] {
            Expression::Compose { components, .. } => {
                components.iter().all(|c| leaf(&self.out.expressions[*c]))
            }
            e => leaf(e),
        };
        if constant && self.loop_depth == 0 {
            self.out.local_variables[var].init = Some(value);
            None
        } else {
            Some(Statement::Store { pointer, value })
        }
    }

    /// The handle of global `g` (a pointer, or a texture or sampler itself).
    fn global(&mut self, g: usize, out: &mut Block) -> Result<Handle<Expression>, LowerError> {
        if let Some(h) = self.global_exprs.get(&g) {
            return Ok(*h);
        }
        let e = match self.global_ref(g)? {
            GlobalRef::Var { handle, .. } => Expression::GlobalVariable(handle),
            GlobalRef::Constant(c) => Expression::Constant(c),
            GlobalRef::Override(o) => Expression::Override(o),
        };
        let h = self.append(e, out);
        self.global_exprs.insert(g, h);
        Ok(h)
    }

    /// What global `g` became (every global a lowered function reads was declared).
    fn global_ref(&self, g: usize) -> Result<GlobalRef, LowerError> {
        match self.globals.get(g).copied().flatten() {
            Some(r) => Ok(r),
            None => unsupported(format!("a read of global {g}, which was not declared")),
        }
    }

    /// A pointer to what `id` reads, if it reads memory: a `var`, a resource or private global,
    /// or a member, element or single component of one.
    fn place(
        &mut self,
        id: ExprId,
        out: &mut Block,
    ) -> Result<Option<Handle<Expression>>, LowerError> {
        let e = self.f.expr(id);
        Ok(match &e.kind {
            ExprKind::Local(l) => match self.locals[l.0 as usize] {
                LocalSlot::Var(p) => Some(p),
                _ => None,
            },
            ExprKind::Global(g) => match self.global_ref(g.0 as usize)? {
                GlobalRef::Var {
                    is_handle: false, ..
                } => Some(self.global(g.0 as usize, out)?),
                _ => None,
            },
            ExprKind::Member(base, i) => self
                .place(*base, out)?
                .map(|p| self.append(Expression::AccessIndex { base: p, index: *i }, out)),
            ExprKind::Swizzle(base, c) if c.len() == 1 => self.place(*base, out)?.map(|p| {
                self.append(
                    Expression::AccessIndex {
                        base: p,
                        index: u32::from(c[0]),
                    },
                    out,
                )
            }),
            ExprKind::Index(base, index) => match self.place(*base, out)? {
                Some(p) => Some(self.index(p, *index, out)?),
                None => None,
            },
            _ => None,
        })
    }

    /// `base[index]`: `AccessIndex` when the index is a literal (naga's front end folds it so,
    /// and only a constant index may reach into a matrix or array held by value).
    fn index(
        &mut self,
        base: Handle<Expression>,
        index: ExprId,
        out: &mut Block,
    ) -> Result<Handle<Expression>, LowerError> {
        let constant = match self.f.expr(index).kind {
            ExprKind::Literal(Literal::U32(v)) => Some(v),
            ExprKind::Literal(Literal::I32(v)) => u32::try_from(v).ok(),
            _ => None,
        };
        Ok(match constant {
            Some(index) => self.append(Expression::AccessIndex { base, index }, out),
            None => {
                let index = self.value(index, out)?;
                self.append(Expression::Access { base, index }, out)
            }
        })
    }

    /// The value of `id`.
    fn value(&mut self, id: ExprId, out: &mut Block) -> Result<Handle<Expression>, LowerError> {
        if let Some(h) = self.memo.get(&id) {
            return Ok(*h);
        }
        let h = self.value_uncached(id, out)?;
        self.memo.insert(id, h);
        Ok(h)
    }

    fn value_uncached(
        &mut self,
        id: ExprId,
        out: &mut Block,
    ) -> Result<Handle<Expression>, LowerError> {
        let e = self.f.expr(id);
        if matches!(
            e.kind,
            ExprKind::Local(_)
                | ExprKind::Global(_)
                | ExprKind::Member(..)
                | ExprKind::Index(..)
                | ExprKind::Swizzle(..)
        ) && let Some(pointer) = self.place(id, out)?
        {
            return Ok(self.append(Expression::Load { pointer }, out));
        }
        let expr = match &e.kind {
            ExprKind::Literal(l) => match literal(*l) {
                Some(lit) => Expression::Literal(lit),
                None => {
                    return Err(CodegenError::NonFiniteLiteral {
                        function: self.f.rust_name.clone(),
                        loc: self.f.loc,
                    }
                    .into());
                }
            },
            ExprKind::Arg(i) => return Ok(self.args[*i as usize]),
            ExprKind::Local(l) => match self.locals[l.0 as usize] {
                LocalSlot::Let(h) => return Ok(h),
                _ => {
                    return unsupported(format!(
                        "a read of `{}` before its `let`",
                        self.f.local(*l).name
                    ));
                }
            },
            ExprKind::Global(g) => return self.global(g.0 as usize, out),
            ExprKind::Unary(op, a) => Expression::Unary {
                op: match op {
                    UnaryOp::Neg => naga::UnaryOperator::Negate,
                    UnaryOp::Not => naga::UnaryOperator::LogicalNot,
                },
                expr: self.value(*a, out)?,
            },
            ExprKind::Binary(op @ (BinaryOp::And | BinaryOp::Or), a, b) => {
                return self.short_circuit(*op == BinaryOp::And, *a, *b, out);
            }
            ExprKind::Binary(op, a, b) => {
                let mut left = self.value(*a, out)?;
                let mut right = self.value(*b, out)?;
                if matches!(
                    op,
                    BinaryOp::Add | BinaryOp::Sub | BinaryOp::Div | BinaryOp::Rem
                ) {
                    match (self.f.expr(*a).ty, self.f.expr(*b).ty) {
                        (Type::Vector(n, _), Type::Scalar(_)) => {
                            right = self.splat(n, right, out)?;
                        }
                        (Type::Scalar(_), Type::Vector(n, _)) => {
                            left = self.splat(n, left, out)?;
                        }
                        _ => {}
                    }
                }
                Expression::Binary {
                    op: binary(*op),
                    left,
                    right,
                }
            }
            ExprKind::Builtin(Builtin::Select, args) => {
                let [if_false, if_true, cond] = args.as_slice() else {
                    return unsupported("`select` without three operands");
                };
                self.select(*if_false, *if_true, *cond, out)?
            }
            ExprKind::Builtin(b, args) => {
                let mut a = Vec::with_capacity(args.len());
                for x in args {
                    a.push(self.value(*x, out)?);
                }
                let Some(&arg) = a.first() else {
                    return unsupported(format!("`{b:?}` without operands"));
                };
                let Some(fun) = math(*b) else {
                    return unsupported(format!("`{b:?}` as a math function"));
                };
                Expression::Math {
                    fun,
                    arg,
                    arg1: a.get(1).copied(),
                    arg2: a.get(2).copied(),
                    arg3: a.get(3).copied(),
                }
            }
            ExprKind::Call(name, args) => {
                let Some(&function) = self.functions.get(name.as_str()) else {
                    return unsupported(format!("a call of `{name}`, defined after its caller"));
                };
                let mut arguments = Vec::with_capacity(args.len());
                for x in args {
                    arguments.push(self.value(*x, out)?);
                }
                // The arguments' `Emit` comes before the call; the result is defined by it.
                out.extend(self.emitter.finish(&self.out.expressions));
                let result = self
                    .out
                    .expressions
                    .append(Expression::CallResult(function), Span::UNDEFINED);
                self.kinds.insert(result, ExpressionKind::Runtime);
                out.push(
                    Statement::Call {
                        function,
                        arguments,
                        result: Some(result),
                    },
                    Span::UNDEFINED,
                );
                self.emitter.start(&self.out.expressions);
                return Ok(result);
            }
            ExprKind::Construct(ty, args) => return self.construct(*ty, args, out),
            ExprKind::Swizzle(v, c) => {
                let vector = self.value(*v, out)?;
                if let [one] = c.as_slice() {
                    Expression::AccessIndex {
                        base: vector,
                        index: u32::from(*one),
                    }
                } else {
                    let mut pattern = [naga::SwizzleComponent::X; 4];
                    for (slot, i) in pattern.iter_mut().zip(c) {
                        *slot = match i {
                            0 => naga::SwizzleComponent::X,
                            1 => naga::SwizzleComponent::Y,
                            2 => naga::SwizzleComponent::Z,
                            _ => naga::SwizzleComponent::W,
                        };
                    }
                    Expression::Swizzle {
                        size: vector_size(c.len() as u8)?,
                        vector,
                        pattern,
                    }
                }
            }
            ExprKind::Member(v, i) => Expression::AccessIndex {
                base: self.value(*v, out)?,
                index: *i,
            },
            ExprKind::Index(a, i) => {
                let base = self.value(*a, out)?;
                return self.index(base, *i, out);
            }
            ExprKind::Convert(s, a) => Expression::As {
                expr: self.value(*a, out)?,
                kind: scalar(*s).kind,
                convert: Some(scalar(*s).width),
            },
            ExprKind::Bitcast(s, a) => Expression::As {
                expr: self.value(*a, out)?,
                kind: scalar(*s).kind,
                convert: None,
            },
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => self.select(*if_false, *if_true, *cond, out)?,
            ExprKind::Sample {
                texture,
                sampler,
                coords,
                kind,
            } => {
                let image = self.value(*texture, out)?;
                let sampler = self.value(*sampler, out)?;
                let coordinate = self.value(*coords, out)?;
                let level = match kind {
                    SampleKind::Level(l) => naga::SampleLevel::Exact(self.value(*l, out)?),
                    SampleKind::Implicit => naga::SampleLevel::Auto,
                };
                Expression::ImageSample {
                    image,
                    sampler,
                    gather: None,
                    coordinate,
                    array_index: None,
                    offset: None,
                    level,
                    depth_ref: None,
                    clamp_to_edge: false,
                }
            }
            ExprKind::Load {
                texture,
                texel,
                level,
            } => Expression::ImageLoad {
                image: self.value(*texture, out)?,
                coordinate: self.value(*texel, out)?,
                array_index: None,
                sample: None,
                level: Some(self.value(*level, out)?),
            },
        };
        Ok(self.append(expr, out))
    }

    /// `a && b` / `a || b` evaluating `b` only when it decides, as WGSL says and naga's front
    /// end builds it: a `bool` local set in an `if` (so a call or a texture read on the right
    /// is skipped when the left decides).
    fn short_circuit(
        &mut self,
        and: bool,
        a: ExprId,
        b: ExprId,
        out: &mut Block,
    ) -> Result<Handle<Expression>, LowerError> {
        let condition = self.value(a, out)?;
        let ty = self.types.get(self.m, Type::BOOL)?;
        let var = self.out.local_variables.append(
            naga::LocalVariable {
                name: Some("local".to_string()),
                ty,
                init: None,
            },
            Span::UNDEFINED,
        );
        let pointer = self.append(Expression::LocalVariable(var), out);
        let decided = self.append(Expression::Literal(naga::Literal::Bool(!and)), out);
        out.extend(self.emitter.finish(&self.out.expressions));
        // What the right side lowers to lives in its arm only: forget it after.
        let outer = self.memo.clone();
        let mut evaluate = Block::new();
        self.emitter.start(&self.out.expressions);
        let right = self.value(b, &mut evaluate);
        self.memo = outer;
        let right = right?;
        evaluate.extend(self.emitter.finish(&self.out.expressions));
        evaluate.push(
            Statement::Store {
                pointer,
                value: right,
            },
            Span::UNDEFINED,
        );
        let mut decide = Block::new();
        decide.push(
            Statement::Store {
                pointer,
                value: decided,
            },
            Span::UNDEFINED,
        );
        let (accept, reject) = if and {
            (evaluate, decide)
        } else {
            (decide, evaluate)
        };
        out.push(
            Statement::If {
                condition,
                accept,
                reject,
            },
            Span::UNDEFINED,
        );
        self.emitter.start(&self.out.expressions);
        Ok(self.append(Expression::Load { pointer }, out))
    }

    /// `select(if_false, if_true, cond)`, its operands in WGSL's order.
    fn select(
        &mut self,
        if_false: ExprId,
        if_true: ExprId,
        cond: ExprId,
        out: &mut Block,
    ) -> Result<Expression, LowerError> {
        let reject = self.value(if_false, out)?;
        let accept = self.value(if_true, out)?;
        let condition = self.value(cond, out)?;
        Ok(Expression::Select {
            condition,
            accept,
            reject,
        })
    }

    fn splat(
        &mut self,
        n: u8,
        value: Handle<Expression>,
        out: &mut Block,
    ) -> Result<Handle<Expression>, LowerError> {
        Ok(self.append(
            Expression::Splat {
                size: vector_size(n)?,
                value,
            },
            out,
        ))
    }

    /// `T(args)`: the zero value, a splat, a conversion, or a composition.
    fn construct(
        &mut self,
        ty: Type,
        args: &[ExprId],
        out: &mut Block,
    ) -> Result<Handle<Expression>, LowerError> {
        let h = self.types.get(self.m, ty)?;
        if args.is_empty() {
            return Ok(self.append(Expression::ZeroValue(h), out));
        }
        if let [one] = args {
            let arg_ty = self.f.expr(*one).ty;
            let value = self.value(*one, out)?;
            if arg_ty == ty {
                return Ok(value);
            }
            match (ty, arg_ty) {
                (Type::Vector(n, _), Type::Scalar(s)) if ty.scalar() == Some(s) => {
                    return self.splat(n, value, out);
                }
                (Type::Scalar(s) | Type::Vector(_, s), Type::Scalar(_) | Type::Vector(..)) => {
                    let s = scalar(s);
                    return Ok(self.append(
                        Expression::As {
                            expr: value,
                            kind: s.kind,
                            convert: Some(s.width),
                        },
                        out,
                    ));
                }
                _ => {}
            }
        }
        let mut components = Vec::with_capacity(args.len());
        for a in args {
            components.push(self.value(*a, out)?);
        }
        Ok(self.append(Expression::Compose { ty: h, components }, out))
    }
}

/// naga's binding for an entry point's parameter or result; a float at a location is
/// interpolated perspective-correct at the centre, as WGSL's default says.
fn binding(io: Io, ty: &TypeInner) -> naga::Binding {
    match io {
        Io::Position => naga::Binding::BuiltIn(naga::BuiltIn::Position { invariant: false }),
        Io::VertexIndex => naga::Binding::BuiltIn(naga::BuiltIn::VertexIndex),
        Io::GlobalInvocationId => naga::Binding::BuiltIn(naga::BuiltIn::GlobalInvocationId),
        Io::Location(location) => {
            let float = ty.scalar_kind() == Some(naga::ScalarKind::Float);
            naga::Binding::Location {
                location,
                interpolation: float.then_some(naga::Interpolation::Perspective),
                sampling: float.then_some(naga::Sampling::Center),
                blend_src: None,
                per_primitive: false,
            }
        }
    }
}
