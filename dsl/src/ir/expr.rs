//! Expressions: a per-function arena of typed nodes. DSL values are `Copy` handles into it, which
//! is what lets the same Rust tokens (`x * x + y`) compile both for `f32` and for the recorder.

use super::types::{Scalar, Type};

/// Index of an expression in its function's arena.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub struct ExprId(pub u32);

/// Index of a named local (`let` or `var`) in its function.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub struct LocalId(pub u32);

/// Index of a module-level global (uniform, texture, sampler, storage buffer, override).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct GlobalId(pub u32);

/// A literal value. Floats are stored as bits so that literals hash and compare exactly.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Literal {
    F32(u32),
    I32(i32),
    U32(u32),
    Bool(bool),
}

impl Literal {
    pub fn f32(v: f32) -> Self {
        Literal::F32(v.to_bits())
    }

    pub fn ty(self) -> Type {
        match self {
            Literal::F32(_) => Type::F32,
            Literal::I32(_) => Type::I32,
            Literal::U32(_) => Type::U32,
            Literal::Bool(_) => Type::BOOL,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum UnaryOp {
    Neg,
    Not,
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    BitAnd,
    BitOr,
    BitXor,
    Shl,
    Shr,
}

impl BinaryOp {
    pub fn is_comparison(self) -> bool {
        matches!(
            self,
            BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge | BinaryOp::Eq | BinaryOp::Ne
        )
    }
}

/// A built-in function. The DSL exposes each under the name its Rust twin has (`exp`,
/// `max`, `lerp`...), so the CPU and the shader agree on meaning, not just on spelling.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Builtin {
    Abs,
    Ceil,
    Clamp,
    Cos,
    Cross,
    Distance,
    Dot,
    Exp,
    Exp2,
    Floor,
    Fract,
    InverseSqrt,
    Length,
    Log,
    Log2,
    Max,
    Min,
    Mix,
    Normalize,
    Pow,
    Round,
    Select,
    Sign,
    Sin,
    Smoothstep,
    Sqrt,
    Step,
    Tan,
    Trunc,
    Atan2,
    Acos,
    Asin,
    Atan,
    Fma,
    Saturate,
    Pack4x8Unorm,
}

impl Builtin {
    /// Every built-in function.
    pub const ALL: [Builtin; 36] = [
        Builtin::Abs,
        Builtin::Ceil,
        Builtin::Clamp,
        Builtin::Cos,
        Builtin::Cross,
        Builtin::Distance,
        Builtin::Dot,
        Builtin::Exp,
        Builtin::Exp2,
        Builtin::Floor,
        Builtin::Fract,
        Builtin::InverseSqrt,
        Builtin::Length,
        Builtin::Log,
        Builtin::Log2,
        Builtin::Max,
        Builtin::Min,
        Builtin::Mix,
        Builtin::Normalize,
        Builtin::Pow,
        Builtin::Round,
        Builtin::Select,
        Builtin::Sign,
        Builtin::Sin,
        Builtin::Smoothstep,
        Builtin::Sqrt,
        Builtin::Step,
        Builtin::Tan,
        Builtin::Trunc,
        Builtin::Atan2,
        Builtin::Acos,
        Builtin::Asin,
        Builtin::Atan,
        Builtin::Fma,
        Builtin::Saturate,
        Builtin::Pack4x8Unorm,
    ];
}

/// How a texture is read.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum SampleKind {
    /// `textureSampleLevel`: explicit level of detail, valid in every stage.
    Level(ExprId),
    /// `textureSample`: implicit derivatives, fragment stage only.
    Implicit,
}

/// One expression node.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum ExprKind {
    Literal(Literal),
    /// The n-th parameter of the function being recorded.
    Arg(u32),
    /// A read of a `let` (by value) or a `var` (a load).
    Local(LocalId),
    Global(GlobalId),
    Unary(UnaryOp, ExprId),
    Binary(BinaryOp, ExprId, ExprId),
    Builtin(Builtin, Vec<ExprId>),
    /// Call of another recorded function, by its (specialised) name.
    Call(String, Vec<ExprId>),
    /// `T(a, b, ...)` for vectors, matrices and structs.
    Construct(Type, Vec<ExprId>),
    /// `v.xy`, `v.zyx`: component indices 0..4.
    Swizzle(ExprId, Vec<u8>),
    /// `s.field` by field index.
    Member(ExprId, u32),
    /// `array[index]` on a storage buffer.
    Index(ExprId, ExprId),
    /// Value conversion `f32(x)` etc. to the given scalar kind (vectors keep their size).
    Convert(Scalar, ExprId),
    /// Bit reinterpretation `bitcast<T>(x)`.
    Bitcast(Scalar, ExprId),
    /// `select(if_false, if_true, cond)`.
    Select {
        if_false: ExprId,
        if_true: ExprId,
        cond: ExprId,
    },
    Sample {
        texture: ExprId,
        sampler: ExprId,
        coords: ExprId,
        kind: SampleKind,
    },
    /// `textureLoad(texture, texel, level)`: one texel by its integer coordinates, no sampler
    /// (the texture may be unfilterable: an engine's depth buffer).
    Load {
        texture: ExprId,
        texel: ExprId,
        level: ExprId,
    },
}

impl ExprKind {
    /// Calls `visit` on each operand, in the order the printer writes them.
    pub fn for_each_operand(&self, mut visit: impl FnMut(ExprId)) {
        match self {
            ExprKind::Literal(_) | ExprKind::Arg(_) | ExprKind::Local(_) | ExprKind::Global(_) => {}
            ExprKind::Unary(_, a)
            | ExprKind::Swizzle(a, _)
            | ExprKind::Member(a, _)
            | ExprKind::Convert(_, a)
            | ExprKind::Bitcast(_, a) => visit(*a),
            ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
                visit(*a);
                visit(*b);
            }
            ExprKind::Builtin(_, args) | ExprKind::Call(_, args) | ExprKind::Construct(_, args) => {
                args.iter().for_each(|a| visit(*a));
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => {
                visit(*if_false);
                visit(*if_true);
                visit(*cond);
            }
            ExprKind::Sample {
                texture,
                sampler,
                coords,
                kind,
            } => {
                visit(*texture);
                visit(*sampler);
                visit(*coords);
                if let SampleKind::Level(l) = kind {
                    visit(*l);
                }
            }
            ExprKind::Load {
                texture,
                texel,
                level,
            } => {
                visit(*texture);
                visit(*texel);
                visit(*level);
            }
        }
    }

    /// Calls `visit` on each operand, which it may replace.
    pub fn for_each_operand_mut(&mut self, mut visit: impl FnMut(&mut ExprId)) {
        match self {
            ExprKind::Literal(_) | ExprKind::Arg(_) | ExprKind::Local(_) | ExprKind::Global(_) => {}
            ExprKind::Unary(_, a)
            | ExprKind::Swizzle(a, _)
            | ExprKind::Member(a, _)
            | ExprKind::Convert(_, a)
            | ExprKind::Bitcast(_, a) => visit(a),
            ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
                visit(a);
                visit(b);
            }
            ExprKind::Builtin(_, args) | ExprKind::Call(_, args) | ExprKind::Construct(_, args) => {
                args.iter_mut().for_each(visit);
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => {
                visit(if_false);
                visit(if_true);
                visit(cond);
            }
            ExprKind::Sample {
                texture,
                sampler,
                coords,
                kind,
            } => {
                visit(texture);
                visit(sampler);
                visit(coords);
                if let SampleKind::Level(l) = kind {
                    visit(l);
                }
            }
            ExprKind::Load {
                texture,
                texel,
                level,
            } => {
                visit(texture);
                visit(texel);
                visit(level);
            }
        }
    }
}

/// A typed node.
#[derive(Clone, PartialEq, Debug)]
pub struct Expr {
    pub kind: ExprKind,
    pub ty: Type,
}
