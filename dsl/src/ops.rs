//! Operators Rust cannot overload for DSL types: comparisons (`<` must return `bool`), the
//! short-circuit `&&`/`||`, and `as` casts. `#[shader_fn]` rewrites them into calls to these
//! functions in the shader twin. For plain Rust values (generation-time `#[spec]` parameters)
//! they compute a `bool`, so an `if` on them is decided while the shader is generated.

use crate::ir::{BinaryOp, ExprKind, Scalar, Type};
use crate::record::push_expr;
use crate::value::{Bool, F32, I32, IntoValueOf, U32, Value, binary};

/// Comparison of two operands; `Output` is `bool` for Rust values and [`Bool`] for DSL values.
pub trait ShaderCmp<Rhs> {
    type Output;
    fn cmp_op(self, rhs: Rhs, op: BinaryOp) -> Self::Output;
}

macro_rules! cmp_rust {
    ($($t:ty),*) => {$(
        impl ShaderCmp<$t> for $t {
            type Output = bool;
            fn cmp_op(self, rhs: $t, op: BinaryOp) -> bool {
                match op {
                    BinaryOp::Lt => self < rhs,
                    BinaryOp::Le => self <= rhs,
                    BinaryOp::Gt => self > rhs,
                    BinaryOp::Ge => self >= rhs,
                    BinaryOp::Eq => self == rhs,
                    _ => self != rhs,
                }
            }
        }
    )*};
}
cmp_rust!(f32, i32, u32, usize, u8, bool);

macro_rules! cmp_dsl {
    ($dsl:ty, $rust:ty) => {
        cmp_dsl!(@one $dsl, $dsl);
        cmp_dsl!(@one $dsl, $rust);
        cmp_dsl!(@one $rust, $dsl);
    };
    (@one $l:ty, $r:ty) => {
        impl ShaderCmp<$r> for $l {
            type Output = Bool;
            fn cmp_op(self, rhs: $r, op: BinaryOp) -> Bool {
                let a = self.into_value_id().id();
                let b = rhs.into_value_id().id();
                Bool::from_id(binary(op, a, b, Type::BOOL))
            }
        }
    };
}
cmp_dsl!(F32, f32);
cmp_dsl!(I32, i32);
cmp_dsl!(U32, u32);
cmp_dsl!(Bool, bool);

/// `a < b`.
pub fn lt<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Lt)
}
/// `a <= b`.
pub fn le<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Le)
}
/// `a > b`.
pub fn gt<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Gt)
}
/// `a >= b`.
pub fn ge<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Ge)
}
/// `a == b`.
pub fn eq<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Eq)
}
/// `a != b`.
pub fn ne<A: ShaderCmp<B>, B>(a: A, b: B) -> A::Output {
    a.cmp_op(b, BinaryOp::Ne)
}

/// `&&` and `||`. For DSL values both sides are evaluated (they are pure expressions).
pub trait ShaderLogic<Rhs> {
    type Output;
    fn logic(self, rhs: Rhs, op: BinaryOp) -> Self::Output;
}

impl ShaderLogic<bool> for bool {
    type Output = bool;
    fn logic(self, rhs: bool, op: BinaryOp) -> bool {
        if op == BinaryOp::And {
            self && rhs
        } else {
            self || rhs
        }
    }
}

macro_rules! logic_dsl {
    ($l:ty, $r:ty) => {
        impl ShaderLogic<$r> for $l {
            type Output = Bool;
            fn logic(self, rhs: $r, op: BinaryOp) -> Bool {
                let a = self.into_value_id().id();
                let b = rhs.into_value_id().id();
                Bool::from_id(binary(op, a, b, Type::BOOL))
            }
        }
    };
}
logic_dsl!(Bool, Bool);
logic_dsl!(Bool, bool);
logic_dsl!(bool, Bool);

/// `a && b`.
pub fn and<A: ShaderLogic<B>, B>(a: A, b: B) -> A::Output {
    a.logic(b, BinaryOp::And)
}
/// `a || b`.
pub fn or<A: ShaderLogic<B>, B>(a: A, b: B) -> A::Output {
    a.logic(b, BinaryOp::Or)
}

/// `value as Target` between scalar kinds.
pub trait CastTo<Target> {
    fn cast_to(self) -> Target;
}

macro_rules! cast_dsl {
    ($from:ty => $($to:ident: $sk:expr),*) => {$(
        impl CastTo<$to> for $from {
            fn cast_to(self) -> $to {
                $to::from_id(push_expr(ExprKind::Convert($sk, self.id()), <$to as Value>::TYPE))
            }
        }
    )*};
}
cast_dsl!(F32 => F32: Scalar::F32, I32: Scalar::I32, U32: Scalar::U32);
cast_dsl!(I32 => F32: Scalar::F32, I32: Scalar::I32, U32: Scalar::U32);
cast_dsl!(U32 => F32: Scalar::F32, I32: Scalar::I32, U32: Scalar::U32);

macro_rules! cast_rust {
    ($from:ty => $($to:ident: $rust:ty),*) => {$(
        impl CastTo<$to> for $from {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss, clippy::cast_precision_loss, reason = "mirrors Rust `as`")]
            fn cast_to(self) -> $to {
                $to::lit(self as $rust)
            }
        }
    )*};
}
cast_rust!(f32 => F32: f32, I32: i32, U32: u32);
cast_rust!(i32 => F32: f32, I32: i32, U32: u32);
cast_rust!(u32 => F32: f32, I32: i32, U32: u32);
cast_rust!(usize => F32: f32, I32: i32, U32: u32);

/// `value as T`, with `T` the shader twin of the Rust target type.
pub fn cast<T, V: CastTo<T>>(v: V) -> T {
    v.cast_to()
}

/// `f32::from_bits`/`to_bits` style reinterpretation.
pub fn bitcast_f32(v: U32) -> F32 {
    F32::from_id(push_expr(ExprKind::Bitcast(Scalar::F32, v.id()), Type::F32))
}

/// Reinterprets an `f32`'s bits as a `u32`.
pub fn bitcast_u32(v: F32) -> U32 {
    U32::from_id(push_expr(ExprKind::Bitcast(Scalar::U32, v.id()), Type::U32))
}

/// `a[i]`: an index into a recorded array, or into a plain Rust array (see
/// [`crate::value::Indexable`]). The macro strips the `as usize` a CPU twin needs.
pub fn index<A: crate::value::Indexable<I>, I>(array: A, i: I) -> A::Output {
    array.index_at(i)
}
