//! CPU/GPU parity: run a `#[shader_fn]` over many inputs on the GPU, through a compute kernel
//! that codegen builds around the function from its signature alone.
//!
//! Inputs and outputs travel as raw 32-bit words (`f32` bits, `u32`, `i32` bits), so the GPU
//! sees exactly the values the CPU twin saw. Struct parameters are flattened field by field.

use nimbus_codegen::{Generated, Target, generate};
use nimbus_dsl::ir::{ExprId, ExprKind, Scalar, Type};
use nimbus_dsl::record::push_expr;
use nimbus_dsl::shader::U32;
use nimbus_dsl::{ModuleBuilder, Value, loc};

use nimbus_runtime::RuntimeError;
use nimbus_runtime::{Gpu, GpuResource};

const WORKGROUP: u32 = 64;
/// Binding of the input words (the output words are the next one), in group 0.
pub const INPUT_BINDING: u32 = 100;

/// 32-bit words per value of `ty`.
pub fn words_of(ty: Type) -> Result<usize, RuntimeError> {
    Ok(match ty {
        Type::Scalar(_) => 1,
        Type::Vector(n, _) => usize::from(n),
        Type::Matrix(n) => usize::from(n) * usize::from(n),
        Type::Array(elem, n) => words_of(*elem)? * n as usize,
        Type::Struct(def) => {
            let mut total = 0;
            for f in def.fields {
                total += words_of(f.ty)?;
            }
            total
        }
        other => {
            return Err(RuntimeError::Kernel(format!(
                "{} values cannot be passed through a parity buffer",
                nimbus_codegen::wgsl_type(other)
            )));
        }
    })
}

fn from_word(word: ExprId, s: Scalar) -> ExprId {
    match s {
        Scalar::U32 => word,
        Scalar::F32 | Scalar::I32 => push_expr(ExprKind::Bitcast(s, word), Type::Scalar(s)),
        Scalar::Bool => {
            let zero = push_expr(
                ExprKind::Literal(nimbus_dsl::ir::Literal::U32(0)),
                Type::U32,
            );
            push_expr(
                ExprKind::Binary(nimbus_dsl::ir::BinaryOp::Ne, word, zero),
                Type::BOOL,
            )
        }
    }
}

fn to_word(value: ExprId, s: Scalar) -> ExprId {
    match s {
        Scalar::U32 => value,
        Scalar::F32 | Scalar::I32 => push_expr(ExprKind::Bitcast(Scalar::U32, value), Type::U32),
        Scalar::Bool => {
            let one = push_expr(
                ExprKind::Literal(nimbus_dsl::ir::Literal::U32(1)),
                Type::U32,
            );
            let zero = push_expr(
                ExprKind::Literal(nimbus_dsl::ir::Literal::U32(0)),
                Type::U32,
            );
            push_expr(
                ExprKind::Select {
                    if_false: zero,
                    if_true: one,
                    cond: value,
                },
                Type::U32,
            )
        }
    }
}

/// Builds a value of `ty` from consecutive words starting at `read(offset)`.
fn load(ty: Type, offset: &mut usize, read: &mut impl FnMut(usize) -> ExprId) -> ExprId {
    match ty {
        Type::Scalar(s) => {
            let w = read(*offset);
            *offset += 1;
            from_word(w, s)
        }
        Type::Vector(n, s) => {
            let parts = (0..n)
                .map(|_| load(Type::Scalar(s), offset, read))
                .collect();
            push_expr(ExprKind::Construct(ty, parts), ty)
        }
        Type::Matrix(n) => {
            let col = Type::Vector(n, Scalar::F32);
            let parts = (0..n).map(|_| load(col, offset, read)).collect();
            push_expr(ExprKind::Construct(ty, parts), ty)
        }
        Type::Struct(def) => {
            let parts = def
                .fields
                .iter()
                .map(|f| load(f.ty, offset, read))
                .collect();
            push_expr(ExprKind::Construct(ty, parts), ty)
        }
        Type::Array(elem, n) => {
            let parts = (0..n).map(|_| load(*elem, offset, read)).collect();
            push_expr(ExprKind::Construct(ty, parts), ty)
        }
        _ => read(*offset),
    }
}

/// Words of a result value: scalars, vectors, and structs of them field by field (as
/// [`load`] reads parameters).
fn store(
    ty: Type,
    value: ExprId,
    write: &mut impl FnMut(usize, ExprId),
    offset: &mut usize,
) -> Result<(), RuntimeError> {
    match ty {
        Type::Scalar(s) => {
            write(*offset, to_word(value, s));
            *offset += 1;
        }
        Type::Vector(n, s) => {
            for i in 0..n {
                let c = push_expr(ExprKind::Swizzle(value, vec![i]), Type::Scalar(s));
                write(*offset, to_word(c, s));
                *offset += 1;
            }
        }
        Type::Struct(def) => {
            for (i, f) in def.fields.iter().enumerate() {
                let member = push_expr(ExprKind::Member(value, i as u32), f.ty);
                store(f.ty, member, write, offset)?;
            }
        }
        other => {
            return Err(RuntimeError::Kernel(format!(
                "parity results must be scalars, vectors or structs of them, not {}",
                nimbus_codegen::wgsl_type(other)
            )));
        }
    }
    Ok(())
}

/// A function under test: its parameter types, result type and a closure recording a call.
pub struct KernelFn<'a> {
    pub name: &'a str,
    pub params: Vec<Type>,
    pub result: Type,
    pub call: &'a dyn Fn(&[ExprId]) -> ExprId,
    /// Textures and samplers for the bindings (of group 0) the function reads as globals,
    /// by binding number.
    pub resources: &'a [(u32, GpuResource)],
}

impl KernelFn<'_> {
    /// Words per input record (all parameters) and per output record.
    pub fn record_words(&self) -> Result<(usize, usize), RuntimeError> {
        let input = self
            .params
            .iter()
            .map(|t| words_of(*t))
            .sum::<Result<usize, _>>()?;
        Ok((input, words_of(self.result)?))
    }
}

/// The parity kernel for `f`, generated (its WGSL, validated by naga like every other output,
/// and its binding description).
fn kernel(f: &KernelFn<'_>) -> Result<Generated, RuntimeError> {
    let (in_words, out_words) = f.record_words()?;
    let module = ModuleBuilder::build(
        &format!("parity_{}", f.name),
        "CPU/GPU parity kernel: reads argument words, calls the function, writes result words.",
        loc!(),
        |m| {
            // The harness's own buffers sit above the bindings of the code under test.
            let input = m.storage::<U32>(
                "inputs",
                0,
                INPUT_BINDING,
                false,
                "Argument words, one record per invocation.",
            );
            let output = m.storage::<U32>(
                "outputs",
                0,
                INPUT_BINDING + 1,
                true,
                "Result words, one record per invocation.",
            );
            m.compute(
                "parity_main",
                "One call per invocation.",
                loc!(),
                [WORKGROUP, 1, 1],
                |gid| {
                    let index = gid.x;
                    let inputs = input.array();
                    let in_base = index * (in_words as u32);
                    let mut read = |offset: usize| inputs.get(in_base + offset as u32).id();
                    let mut offset = 0;
                    let args: Vec<ExprId> = f
                        .params
                        .iter()
                        .map(|t| load(*t, &mut offset, &mut read))
                        .collect();
                    let result = (f.call)(&args);
                    let outputs = output.array();
                    let out_base = index * (out_words as u32);
                    let mut write = |i: usize, word: ExprId| {
                        outputs.set(out_base + i as u32, U32::from_id(word));
                    };
                    let _ = store(f.result, result, &mut write, &mut 0);
                },
            );
        },
    )?;
    Ok(generate(module, "parity", &[Target::Wgsl])?)
}

/// Runs `f` on the GPU for every record of `inputs` (each `words_of(params)` words long) and
/// returns the result words, one record per input.
pub fn run_on_gpu(gpu: &Gpu, f: &KernelFn<'_>, inputs: &[u32]) -> Result<Vec<u32>, RuntimeError> {
    let (in_words, out_words) = f.record_words()?;
    if in_words == 0 || !inputs.len().is_multiple_of(in_words) {
        return Err(RuntimeError::Kernel(format!(
            "{} input words is not a whole number of {in_words}-word records",
            inputs.len()
        )));
    }
    let count = inputs.len() / in_words;
    let groups = count.div_ceil(WORKGROUP as usize);
    // Pad to whole workgroups so the kernel needs no bounds check; padded results are dropped.
    let mut padded = inputs.to_vec();
    padded.resize(groups * WORKGROUP as usize * in_words, 0);
    let kernel = kernel(f)?;
    let out = gpu.run_compute(
        &kernel,
        "parity_main",
        INPUT_BINDING,
        &padded,
        groups * WORKGROUP as usize * out_words,
        groups as u32,
        f.resources,
    )?;
    Ok(out[..count * out_words].to_vec())
}

/// The textures and sampler of the cloud passes at their bindings, for a kernel around a cloud
/// model function (which reads them as globals).
pub fn cloud_resources(
    t: &nimbus_clouds::model::bindings::CloudTextures,
) -> Vec<(u32, GpuResource)> {
    use nimbus_clouds::model::bindings::{
        DETAIL, LINEAR_REPEAT, SHADOW_MAP, SHAPE, TURBULENCE, WEATHER,
    };
    vec![
        (
            WEATHER.slot().1,
            GpuResource::Texture2d((*t.weather).clone()),
        ),
        (SHAPE.slot().1, GpuResource::Texture3d((*t.shape).clone())),
        (DETAIL.slot().1, GpuResource::Texture3d((*t.detail).clone())),
        (
            TURBULENCE.slot().1,
            GpuResource::Texture2d((*t.turbulence).clone()),
        ),
        (
            SHADOW_MAP.slot().1,
            GpuResource::Texture2d((*t.shadow).clone()),
        ),
        (
            LINEAR_REPEAT.slot().1,
            GpuResource::Sampler(nimbus_dsl::cpu::Sampler::default()),
        ),
    ]
}
