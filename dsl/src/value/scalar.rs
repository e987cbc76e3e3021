//! Scalar values: `F32`, `I32`, `U32`, `Bool`, the twins of `f32`, `i32`, `u32`, `bool`.

use super::{IntoValueOf, Lift, ShaderType, Value, builtin, impl_assign_op, impl_binop, unary};
use crate::ir::{Builtin, ExprId, ExprKind, Literal, Type, UnaryOp};
use crate::record::push_expr;

macro_rules! scalar {
    ($(#[$doc:meta])* $name:ident, $rust:ty, $ty:expr, $lit:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name(ExprId);

        impl Value for $name {
            const TYPE: Type = $ty;
            fn id(self) -> ExprId {
                self.0
            }
            fn from_id(id: ExprId) -> Self {
                Self(id)
            }
        }

        impl $name {
            /// A literal.
            pub fn lit(v: $rust) -> Self {
                #[allow(clippy::redundant_closure_call, reason = "literal constructor passed as a closure")]
                Self(push_expr(ExprKind::Literal(($lit)(v)), $ty))
            }
        }

        impl From<$rust> for $name {
            fn from(v: $rust) -> Self {
                Self::lit(v)
            }
        }

        impl ShaderType for $rust {
            type Dsl = $name;
        }

        impl Lift for $rust {
            fn lift(self) -> $name {
                $name::lit(self)
            }
        }

        impl IntoValueOf for $name {
            type Value = $name;
            fn into_value_id(self) -> $name {
                self
            }
        }

        impl IntoValueOf for $rust {
            type Value = $name;
            fn into_value_id(self) -> $name {
                $name::lit(self)
            }
        }
    };
}

scalar!(
    /// Twin of `f32`.
    F32, f32, Type::F32, Literal::f32
);
scalar!(
    /// Twin of `i32`.
    I32, i32, Type::I32, Literal::I32
);
scalar!(
    /// Twin of `u32`.
    U32, u32, Type::U32, Literal::U32
);
scalar!(
    /// Twin of `bool`.
    Bool, bool, Type::BOOL, Literal::Bool
);

macro_rules! arith {
    ($name:ident, $rust:ty) => {
        impl_binop!($name, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div, Rem rem Rem);
        impl_binop!($name, $rust => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div, Rem rem Rem);
        impl_binop!($rust, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div, Rem rem Rem);
        impl_assign_op!($name, $name; AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);
        impl_assign_op!($name, $rust; AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);

        impl $name {
            /// `min(self, other)`.
            #[must_use]
            pub fn min(self, other: impl Into<$name>) -> $name {
                $name(builtin(Builtin::Min, &[self.0, other.into().0], <$name as Value>::TYPE))
            }
            /// `max(self, other)`.
            #[must_use]
            pub fn max(self, other: impl Into<$name>) -> $name {
                $name(builtin(Builtin::Max, &[self.0, other.into().0], <$name as Value>::TYPE))
            }
            /// `clamp(self, lo, hi)` (min(max(self, lo), hi)).
            #[must_use]
            pub fn clamp(self, lo: impl Into<$name>, hi: impl Into<$name>) -> $name {
                $name(builtin(
                    Builtin::Clamp,
                    &[self.0, lo.into().0, hi.into().0],
                    <$name as Value>::TYPE,
                ))
            }
        }
    };
}
arith!(F32, f32);
arith!(I32, i32);
arith!(U32, u32);

macro_rules! bits {
    ($name:ident, $rust:ty) => {
        impl_binop!($name, $name => $name; BitAnd bitand BitAnd, BitOr bitor BitOr, BitXor bitxor BitXor);
        impl_binop!($name, $rust => $name; BitAnd bitand BitAnd, BitOr bitor BitOr, BitXor bitxor BitXor);
        impl_binop!($name, U32 => $name; Shl shl Shl, Shr shr Shr);
        impl_binop!($name, u32 => $name; Shl shl Shl, Shr shr Shr);
        // A literal shifted by a value (`1u32 << k`: the bit of tile `k`).
        impl_binop!($rust, U32 => $name; Shl shl Shl, Shr shr Shr);
    };
}
bits!(I32, i32);
bits!(U32, u32);
impl_binop!(Bool, Bool => Bool; BitAnd bitand BitAnd, BitOr bitor BitOr, BitXor bitxor BitXor);
impl_binop!(Bool, bool => Bool; BitAnd bitand BitAnd, BitOr bitor BitOr, BitXor bitxor BitXor);

impl core::ops::Neg for F32 {
    type Output = F32;
    fn neg(self) -> F32 {
        F32(unary(UnaryOp::Neg, self.0, Type::F32))
    }
}

impl core::ops::Neg for I32 {
    type Output = I32;
    fn neg(self) -> I32 {
        I32(unary(UnaryOp::Neg, self.0, Type::I32))
    }
}

impl core::ops::Not for Bool {
    type Output = Bool;
    fn not(self) -> Bool {
        Bool(unary(UnaryOp::Not, self.0, Type::BOOL))
    }
}

macro_rules! unary_builtins {
    ($ty:ident; $($(#[$doc:meta])* $method:ident => $b:ident),* $(,)?) => {
        impl $ty {$(
            $(#[$doc])*
            #[must_use]
            pub fn $method(self) -> $ty {
                $ty(builtin(Builtin::$b, &[self.0], <$ty as Value>::TYPE))
            }
        )*}
    };
}

unary_builtins!(F32;
    /// `|x|`.
    abs => Abs,
    /// Rounds towards +∞.
    ceil => Ceil,
    /// Rounds towards −∞.
    floor => Floor,
    /// Rounds towards zero.
    trunc => Trunc,
    /// `e^x`.
    exp => Exp,
    /// `2^x`.
    exp2 => Exp2,
    /// Natural logarithm (WGSL `log`).
    ln => Log,
    /// Base-2 logarithm.
    log2 => Log2,
    /// Square root.
    sqrt => Sqrt,
    /// Sine (radians).
    sin => Sin,
    /// Cosine (radians).
    cos => Cos,
    /// Tangent (radians).
    tan => Tan,
    /// Arc sine.
    asin => Asin,
    /// Arc cosine.
    acos => Acos,
    /// Arc tangent.
    atan => Atan,
    /// `x - floor(x)`, in [0, 1): GLSL/WGSL `fract` (not Rust's `f32::fract`).
    fract_gl => Fract,
    /// `clamp(x, 0, 1)`.
    saturate => Saturate,
    /// `1 / sqrt(x)`.
    inverse_sqrt => InverseSqrt,
);

unary_builtins!(I32;
    /// `|x|` (wrapping at `i32::MIN` as WGSL does).
    abs => Abs,
);

impl F32 {
    /// Rust's `f32::to_radians`: the same product by the same `f32` constant.
    #[must_use]
    pub fn to_radians(self) -> F32 {
        self * (core::f32::consts::PI / 180.0)
    }

    /// Rust's `f32::fract`: `x - trunc(x)` (keeps the sign of `x`). For GLSL's `fract` use
    /// [`F32::fract_gl`].
    #[must_use]
    pub fn fract(self) -> F32 {
        self - self.trunc()
    }

    /// `x^y` (WGSL `pow`; undefined for x < 0 on the GPU, as `powf` is NaN on the CPU).
    #[must_use]
    pub fn powf(self, y: impl Into<F32>) -> F32 {
        F32(builtin(Builtin::Pow, &[self.0, y.into().0], Type::F32))
    }

    /// Four-quadrant arc tangent of `self / x`.
    #[must_use]
    pub fn atan2(self, x: impl Into<F32>) -> F32 {
        F32(builtin(Builtin::Atan2, &[self.0, x.into().0], Type::F32))
    }

    /// `self * a + b` (WGSL `fma`).
    #[must_use]
    pub fn mul_add(self, a: impl Into<F32>, b: impl Into<F32>) -> F32 {
        F32(builtin(
            Builtin::Fma,
            &[self.0, a.into().0, b.into().0],
            Type::F32,
        ))
    }

    /// `1 / x`.
    #[must_use]
    pub fn recip(self) -> F32 {
        1.0 / self
    }

    /// `self + (rhs - self) * t`, exactly glam's `FloatExt::lerp` (spelled out rather than
    /// WGSL `mix`, whose formula differs and loses the endpoints under cancellation). Use the
    /// free function [`crate::builtins::mix`] for WGSL's `a·(1 − t) + b·t`.
    #[must_use]
    pub fn lerp(self, rhs: impl Into<F32>, t: impl Into<F32>) -> F32 {
        self + (rhs.into() - self) * t.into()
    }

    /// Whether the value is NaN (`x != x`).
    #[must_use]
    pub fn is_nan(self) -> Bool {
        crate::ops::ne(self, self)
    }
}

/// CPU twins of DSL scalar methods that neither std nor glam has (`fract_gl` comes from
/// glam's `FloatExt`).
pub trait CpuScalarExt {
    /// `clamp(x, 0, 1)`.
    fn saturate(self) -> Self;
    /// `1 / sqrt(x)`.
    fn inverse_sqrt(self) -> Self;
}

impl CpuScalarExt for f32 {
    fn saturate(self) -> f32 {
        self.clamp(0.0, 1.0)
    }
    fn inverse_sqrt(self) -> f32 {
        1.0 / self.sqrt()
    }
}

macro_rules! wrapping {
    ($name:ident, $rust:ty) => {
        impl $name {
            /// Wrapping `+` (WGSL integer arithmetic always wraps; Rust's twin is `wrapping_add`).
            #[must_use]
            pub fn wrapping_add(self, rhs: impl Into<$name>) -> $name {
                self + rhs.into()
            }
            /// Wrapping `-`.
            #[must_use]
            pub fn wrapping_sub(self, rhs: impl Into<$name>) -> $name {
                self - rhs.into()
            }
            /// Wrapping `*`.
            #[must_use]
            pub fn wrapping_mul(self, rhs: impl Into<$name>) -> $name {
                self * rhs.into()
            }
        }
    };
}
wrapping!(U32, u32);
wrapping!(I32, i32);

impl U32 {
    /// `min(self, other)` is in `arith!`; this is Rust's `u32::rem_euclid` (same as `%` for u32).
    #[must_use]
    pub fn rem_euclid(self, rhs: impl Into<U32>) -> U32 {
        self % rhs.into()
    }
}

impl I32 {
    /// Rust's `i32::rem_euclid`: the remainder in `[0, |rhs|)`.
    #[must_use]
    pub fn rem_euclid(self, rhs: impl Into<I32>) -> I32 {
        let r = rhs.into();
        let m = self % r;
        crate::builtins::select(m, m + r.abs(), crate::ops::lt(m, 0i32))
    }
}
