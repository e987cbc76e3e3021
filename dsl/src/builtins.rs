//! WGSL built-ins that have no method on `f32`/glam: `smoothstep`, `step`, `mix`, `select`.
//! Each is one generic function that works on CPU values and on DSL values, so a
//! `#[shader_fn]` body calls them unchanged in both lives.

use crate::ir::{Builtin, ExprKind, Type};
use crate::record::push_expr;
use crate::value::{Bool, F32, IntoValueOf, Value, Vec2, Vec3, Vec4, builtin};

/// Types with GLSL-style interpolation built-ins.
pub trait Interpolate: Sized + Copy {
    /// The factor type of `mix` (the scalar for vectors, as in WGSL's `mix(vec, vec, f32)`).
    type Factor;
    fn smoothstep_impl(edge0: Self, edge1: Self, x: Self) -> Self;
    fn step_impl(edge: Self, x: Self) -> Self;
    fn mix_impl(a: Self, b: Self, t: Self::Factor) -> Self;
}

fn smoothstep_f32(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn step_f32(edge: f32, x: f32) -> f32 {
    if edge <= x { 1.0 } else { 0.0 }
}

fn mix_f32(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

impl Interpolate for f32 {
    type Factor = f32;
    fn smoothstep_impl(e0: f32, e1: f32, x: f32) -> f32 {
        smoothstep_f32(e0, e1, x)
    }
    fn step_impl(edge: f32, x: f32) -> f32 {
        step_f32(edge, x)
    }
    fn mix_impl(a: f32, b: f32, t: f32) -> f32 {
        mix_f32(a, b, t)
    }
}

macro_rules! interp_glam {
    ($($t:ty),*) => {$(
        impl Interpolate for $t {
            type Factor = f32;
            fn smoothstep_impl(e0: $t, e1: $t, x: $t) -> $t {
                let (a, b, c) = (e0.to_array(), e1.to_array(), x.to_array());
                <$t>::from_array(std::array::from_fn(|i| smoothstep_f32(a[i], b[i], c[i])))
            }
            fn step_impl(edge: $t, x: $t) -> $t {
                let (a, b) = (edge.to_array(), x.to_array());
                <$t>::from_array(std::array::from_fn(|i| step_f32(a[i], b[i])))
            }
            fn mix_impl(a: $t, b: $t, t: f32) -> $t {
                a * (1.0 - t) + b * t
            }
        }
    )*};
}
interp_glam!(glam::Vec2, glam::Vec3, glam::Vec4);

macro_rules! interp_dsl {
    ($($t:ty => $factor:ty),*) => {$(
        impl Interpolate for $t {
            type Factor = $factor;
            fn smoothstep_impl(e0: $t, e1: $t, x: $t) -> $t {
                <$t>::from_id(builtin(Builtin::Smoothstep, &[e0.id(), e1.id(), x.id()], <$t>::TYPE))
            }
            fn step_impl(edge: $t, x: $t) -> $t {
                <$t>::from_id(builtin(Builtin::Step, &[edge.id(), x.id()], <$t>::TYPE))
            }
            fn mix_impl(a: $t, b: $t, t: $factor) -> $t {
                let t = if <$t>::TYPE == Type::F32 {
                    t.id()
                } else {
                    push_expr(ExprKind::Construct(<$t>::TYPE, vec![t.id()]), <$t>::TYPE)
                };
                <$t>::from_id(builtin(Builtin::Mix, &[a.id(), b.id(), t], <$t>::TYPE))
            }
        }
    )*};
}
interp_dsl!(F32 => F32, Vec2 => F32, Vec3 => F32, Vec4 => F32);

/// Hermite interpolation between 0 and 1 as `x` goes from `edge0` to `edge1`.
pub fn smoothstep<T: Interpolate>(edge0: impl Into<T>, edge1: impl Into<T>, x: T) -> T {
    T::smoothstep_impl(edge0.into(), edge1.into(), x)
}

/// 1 where `edge <= x`, else 0.
pub fn step<T: Interpolate>(edge: impl Into<T>, x: T) -> T {
    T::step_impl(edge.into(), x)
}

/// `a * (1 - t) + b * t`.
pub fn mix<T: Interpolate>(a: T, b: impl Into<T>, t: impl Into<T::Factor>) -> T {
    T::mix_impl(a, b.into(), t.into())
}

/// Picks between two values without branching, dispatched on the condition: a Rust `bool`
/// picks now, a DSL [`Bool`] records a WGSL `select`. The two values may mix Rust literals and
/// DSL values of the same kind.
pub trait SelectCond<A, B> {
    type Out;
    fn select_impl(self, if_false: A, if_true: B) -> Self::Out;
}

impl<T: Copy> SelectCond<T, T> for bool {
    type Out = T;
    fn select_impl(self, if_false: T, if_true: T) -> T {
        if self { if_true } else { if_false }
    }
}

impl<A: IntoValueOf, B: IntoValueOf<Value = A::Value>> SelectCond<A, B> for Bool {
    type Out = A::Value;
    fn select_impl(self, if_false: A, if_true: B) -> A::Value {
        let f = if_false.into_value_id();
        let t = if_true.into_value_id();
        <A::Value>::from_id(push_expr(
            ExprKind::Select {
                if_false: f.id(),
                if_true: t.id(),
                cond: self.id(),
            },
            <A::Value as Value>::TYPE,
        ))
    }
}

/// `if cond { if_true } else { if_false }` as an expression (WGSL `select`).
pub fn select<A, B, C: SelectCond<A, B>>(if_false: A, if_true: B, cond: C) -> C::Out {
    cond.select_impl(if_false, if_true)
}

/// Packs four values in [0, 1] into the bytes of a `u32` (x in the lowest byte), rounding to the
/// nearest of 256 levels: WGSL `pack4x8unorm`.
pub trait Pack4x8Unorm {
    type Out;
    fn pack4x8unorm_impl(self) -> Self::Out;
}

impl Pack4x8Unorm for glam::Vec4 {
    type Out = u32;
    fn pack4x8unorm_impl(self) -> u32 {
        let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u32;
        b(self.x) | (b(self.y) << 8) | (b(self.z) << 16) | (b(self.w) << 24)
    }
}

impl Pack4x8Unorm for Vec4 {
    type Out = crate::value::U32;
    fn pack4x8unorm_impl(self) -> crate::value::U32 {
        crate::value::U32::from_id(builtin(Builtin::Pack4x8Unorm, &[self.id()], Type::U32))
    }
}

/// `pack4x8unorm(v)`: four unorm bytes in one word (x lowest).
pub fn pack4x8unorm<T: Pack4x8Unorm>(v: T) -> T::Out {
    v.pack4x8unorm_impl()
}
