//! DSL value types. Each is a `Copy` handle to a recorded expression and has the operators and
//! methods of its CPU twin (`f32`, `glam::Vec3`...), with the same meaning, so one function body
//! type-checks against both. Mixing types that WGSL would reject (`Vec3 + U32`) does not compile.

mod array;
mod block_words;
mod matrix;
mod resource;
pub(crate) mod scalar;
pub mod scalar_ext {
    //! CPU-side methods that mirror DSL methods with no std equivalent.
    pub use super::scalar::CpuScalarExt;
}
mod traits;
mod vector;

pub use array::{Array, Indexable};
pub use matrix::{Mat3, Mat4};
pub use resource::{Sampler, StorageArray, StorageElement, Texture2d, Texture3d};
pub use scalar::{Bool, F32, I32, U32};
pub use traits::{Lift, ShaderType, SpecValue, Value, lift};
pub use vector::{
    CpuVecExt, IVec2, IVec3, IVec4, UVec2, UVec3, UVec4, Vec2, Vec3, Vec4, ivec2, ivec3, ivec4,
    uvec2, uvec3, uvec4, vec2, vec3, vec4,
};

use crate::ir::{BinaryOp, Builtin, ExprId, ExprKind, Type, UnaryOp};
use crate::record::push_expr;

pub(crate) fn binary(op: BinaryOp, a: ExprId, b: ExprId, ty: Type) -> ExprId {
    push_expr(ExprKind::Binary(op, a, b), ty)
}

pub(crate) fn unary(op: UnaryOp, a: ExprId, ty: Type) -> ExprId {
    push_expr(ExprKind::Unary(op, a), ty)
}

pub(crate) fn builtin(f: Builtin, args: &[ExprId], ty: Type) -> ExprId {
    push_expr(ExprKind::Builtin(f, args.to_vec()), ty)
}

/// Implements `impl Op<Rhs> for Lhs { type Output = Out }` for DSL operands, converting both
/// sides with `Into` so Rust literals mix with recorded values (`x * 2.0`).
macro_rules! impl_binop {
    ($lhs:ty, $rhs:ty => $out:ty; $($trait:ident $method:ident $op:ident),+) => {$(
        impl ::core::ops::$trait<$rhs> for $lhs {
            type Output = $out;
            fn $method(self, rhs: $rhs) -> $out {
                let a: ExprId = $crate::value::Value::id(<$lhs as $crate::value::IntoValueOf>::into_value_id(self));
                let b: ExprId = $crate::value::Value::id(<$rhs as $crate::value::IntoValueOf>::into_value_id(rhs));
                <$out as $crate::value::Value>::from_id($crate::value::binary(
                    $crate::ir::BinaryOp::$op,
                    a,
                    b,
                    <$out as $crate::value::Value>::TYPE,
                ))
            }
        }
    )+};
}
pub(crate) use impl_binop;

/// Implements `op=` in terms of `op` (only meaningful on `Var` reads, but keeps glam parity).
macro_rules! impl_assign_op {
    ($lhs:ty, $rhs:ty; $($trait:ident $method:ident $op:tt),+) => {$(
        impl ::core::ops::$trait<$rhs> for $lhs {
            fn $method(&mut self, rhs: $rhs) {
                *self = *self $op rhs;
            }
        }
    )+};
}
pub(crate) use impl_assign_op;

/// Conversion of an operand (a DSL value or a Rust literal of the matching kind) to a DSL value.
pub trait IntoValueOf {
    type Value: Value;
    fn into_value_id(self) -> Self::Value;
}
