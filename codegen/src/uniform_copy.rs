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

//!
//! The same copy serves hosts that cannot describe a struct-of-structs block with `u32` members
//! (three.js's `UniformsGroup`, a plain array of `vec4`s): [`flatten_uniform_blocks`] makes the
//! binding an `array<vec4<u32>, N>` holding the block's bytes, and the entry point unpacks it
//! into the private copy (`u = CloudUniforms(LayerGroup(bitcast<vec4<f32>>(u_words[0]), ...),
//! ...)`). The bytes a host writes are the same either way.

use crate::wgsl_spelling::wgsl_type;
use std::collections::{BTreeMap, BTreeSet};

use nimbus_dsl::ir::{
    Expr, ExprId, ExprKind, Function, Global, GlobalId, GlobalKind, Literal, Module, Scalar, Stmt,
    Type,
};

/// How an entry point fills the private copy of a uniform block.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Fill {
    /// `u = u_buffer;` (the binding keeps the block's struct type).
    Copy,
    /// `u = T(..)` from the words of an `array<vec4<u32>, N>` binding.
    Unpack,
}

/// One 16-byte word of a flattened block. Unsigned, so that integer members are read as they
/// are and float members by `bitcast`: small integers stored in float words would be denormal
/// floats, which some drivers flush to zero on the way through a float register.
static WORD: Type = Type::Vector(4, Scalar::U32);

/// Rewrites `module` so that every struct uniform block is read through a per-invocation copy.
pub fn copy_uniforms_per_invocation(module: &mut Module) {
    read_through_copies(module, Fill::Copy);
}

/// Rewrites `module` so that every struct uniform block is bound as an array of `vec4<u32>`
/// words (`u_words`, same slot, same bytes) and unpacked once per invocation into a private
/// copy that the code reads as before.
pub fn flatten_uniform_blocks(module: &mut Module) {
    read_through_copies(module, Fill::Unpack);
}

fn read_through_copies(module: &mut Module, fill: Fill) {
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
        let words = size_of(original.ty).div_ceil(16);
        match fill {
            Fill::Copy => module.globals[block].name = format!("{}_buffer", original.name),
            Fill::Unpack => {
                module.globals[block].name = format!("{}_words", original.name);
                module.globals[block].ty = Type::Array(&WORD, words);
                module.globals[block].doc = format!(
                    "The bytes of `{}` ({}), as {words} vec4 words.",
                    original.name,
                    wgsl_type(original.ty)
                );
            }
        }
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
            let value = match fill {
                Fill::Copy => push(f, ExprKind::Global(buffer), original.ty),
                Fill::Unpack => {
                    let words_expr = push(f, ExprKind::Global(buffer), Type::Array(&WORD, words));
                    unpack(f, words_expr, original.ty, 0)
                }
            };
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

fn push(f: &mut Function, kind: ExprKind, ty: Type) -> ExprId {
    let id = ExprId(f.exprs.len() as u32);
    f.exprs.push(Expr { kind, ty });
    id
}

fn size_of(ty: Type) -> u32 {
    nimbus_dsl::layout::align_size(ty).1
}

/// The value of type `ty` at byte `offset` of the words array `words`.
fn unpack(f: &mut Function, words: ExprId, ty: Type, offset: u32) -> ExprId {
    let word = |f: &mut Function, k: u32| {
        let index = push(f, ExprKind::Literal(Literal::U32(k)), Type::U32);
        push(f, ExprKind::Index(words, index), WORD)
    };
    match ty {
        Type::Scalar(s) | Type::Vector(_, s) => {
            let n = match ty {
                Type::Vector(n, _) => n,
                _ => 1,
            };
            let w = word(f, offset / 16);
            let first = ((offset % 16) / 4) as u8;
            let lanes: Vec<u8> = (first..first + n).collect();
            let uint_ty = if n == 1 {
                Type::U32
            } else {
                Type::Vector(n, Scalar::U32)
            };
            let uints = if n == 4 {
                w
            } else {
                push(f, ExprKind::Swizzle(w, lanes), uint_ty)
            };
            match s {
                Scalar::U32 => uints,
                other => push(f, ExprKind::Bitcast(other, uints), ty),
            }
        }
        Type::Matrix(n) => {
            let col_ty = Type::Vector(n, Scalar::F32);
            let cols = (0..u32::from(n))
                .map(|c| unpack(f, words, col_ty, offset + 16 * c))
                .collect();
            push(f, ExprKind::Construct(ty, cols), ty)
        }
        Type::Struct(def) => {
            let (_, _, offsets) = nimbus_dsl::layout::struct_layout(def);
            let fields = def
                .fields
                .iter()
                .zip(offsets)
                .map(|(field, o)| unpack(f, words, field.ty, offset + o))
                .collect();
            push(f, ExprKind::Construct(ty, fields), ty)
        }
        Type::Array(elem, n) => {
            let (_, stride) = nimbus_dsl::layout::array_stride(*elem);
            let elems = (0..n)
                .map(|i| unpack(f, words, *elem, offset + i * stride))
                .collect();
            push(f, ExprKind::Construct(ty, elems), ty)
        }
        // Handles and runtime arrays are never members of a uniform block.
        Type::RuntimeArray(_) | Type::Texture2d | Type::Texture3d | Type::Sampler => {
            push(f, ExprKind::Literal(Literal::U32(0)), Type::U32)
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
