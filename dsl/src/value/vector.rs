//! Vector values, twins of glam's `Vec2`..`Vec4`, `IVec*` and `UVec*`. Components are public
//! fields (`v.x`) as in glam; each is a recorded swizzle of the vector.

use super::{
    F32, I32, IntoValueOf, Lift, ShaderType, U32, Value, builtin, impl_assign_op, impl_binop, unary,
};
use crate::ir::{Builtin, ExprId, ExprKind, Scalar, Type, UnaryOp};
use crate::record::push_expr;

fn component(v: ExprId, i: u8, s: Scalar) -> ExprId {
    push_expr(ExprKind::Swizzle(v, vec![i]), Type::Scalar(s))
}

macro_rules! vector {
    (
        $(#[$doc:meta])* $name:ident, $glam:ty, $scalar:ident, $rust:ty, $sk:expr, $n:literal,
        [$($field:ident: $idx:literal),+], $ctor:ident
    ) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name {
            $(pub $field: $scalar,)+
            id: ExprId,
        }

        impl Value for $name {
            const TYPE: Type = Type::Vector($n, $sk);
            fn id(self) -> ExprId {
                self.id
            }
            fn from_id(id: ExprId) -> Self {
                Self { $($field: $scalar::from_id(component(id, $idx, $sk)),)+ id }
            }
        }

        impl ShaderType for $glam {
            type Dsl = $name;
        }

        /// `v[i]`: a component chosen at run time (the CPU twin indexes glam's vector).
        impl<I: Into<U32>> crate::value::Indexable<I> for $name {
            type Output = $scalar;
            fn index_at(self, index: I) -> $scalar {
                $scalar::from_id(push_expr(
                    ExprKind::Index(self.id, Value::id(index.into())),
                    Type::Scalar($sk),
                ))
            }
        }

        impl Lift for $glam {
            fn lift(self) -> $name {
                $name::new($(self.$field),+)
            }
        }

        impl From<$glam> for $name {
            fn from(v: $glam) -> Self {
                v.lift()
            }
        }

        impl IntoValueOf for $name {
            type Value = $name;
            fn into_value_id(self) -> $name {
                self
            }
        }

        impl IntoValueOf for $glam {
            type Value = $name;
            fn into_value_id(self) -> $name {
                self.lift()
            }
        }

        impl $name {
            /// Builds a vector from its components.
            pub fn new($($field: impl Into<$scalar>),+) -> Self {
                let args = vec![$($field.into().id()),+];
                Self::from_id(push_expr(ExprKind::Construct(<Self as Value>::TYPE, args), <Self as Value>::TYPE))
            }

            /// All components equal to `v`.
            pub fn splat(v: impl Into<$scalar>) -> Self {
                let v = v.into().id();
                Self::from_id(push_expr(ExprKind::Construct(<Self as Value>::TYPE, vec![v]), <Self as Value>::TYPE))
            }

            /// Component-wise minimum.
            #[must_use]
            pub fn min(self, rhs: impl Into<$name>) -> Self {
                Self::from_id(builtin(Builtin::Min, &[self.id, rhs.into().id], <Self as Value>::TYPE))
            }

            /// Component-wise maximum.
            #[must_use]
            pub fn max(self, rhs: impl Into<$name>) -> Self {
                Self::from_id(builtin(Builtin::Max, &[self.id, rhs.into().id], <Self as Value>::TYPE))
            }

            /// Component-wise clamp.
            #[must_use]
            pub fn clamp(self, lo: impl Into<$name>, hi: impl Into<$name>) -> Self {
                Self::from_id(builtin(
                    Builtin::Clamp,
                    &[self.id, lo.into().id, hi.into().id],
                    <Self as Value>::TYPE,
                ))
            }

            /// Component-wise absolute value.
            #[must_use]
            pub fn abs(self) -> Self {
                Self::from_id(builtin(Builtin::Abs, &[self.id], <Self as Value>::TYPE))
            }
        }

        /// Shorthand constructor, as glam's free function of the same name.
        pub fn $ctor($($field: impl Into<$scalar>),+) -> $name {
            $name::new($($field),+)
        }

        impl_binop!($name, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($name, $glam => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($glam, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($name, $scalar => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($name, $rust => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($scalar, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_binop!($rust, $name => $name; Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);
        impl_assign_op!($name, $name; AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);
        impl_assign_op!($name, $scalar; MulAssign mul_assign *, DivAssign div_assign /);
        impl_assign_op!($name, $rust; MulAssign mul_assign *, DivAssign div_assign /);
    };
}

macro_rules! float_vector {
    ($name:ident) => {
        impl $name {
            /// Dot product.
            #[must_use]
            pub fn dot(self, rhs: impl Into<$name>) -> F32 {
                F32::from_id(builtin(Builtin::Dot, &[self.id, rhs.into().id], Type::F32))
            }

            /// Euclidean length.
            #[must_use]
            pub fn length(self) -> F32 {
                F32::from_id(builtin(Builtin::Length, &[self.id], Type::F32))
            }

            /// Squared length (`dot(v, v)`).
            #[must_use]
            pub fn length_squared(self) -> F32 {
                self.dot(self)
            }

            /// Distance to `rhs`.
            #[must_use]
            pub fn distance(self, rhs: impl Into<$name>) -> F32 {
                F32::from_id(builtin(
                    Builtin::Distance,
                    &[self.id, rhs.into().id],
                    Type::F32,
                ))
            }

            /// Unit vector in the same direction (NaN for a zero vector on the CPU; undefined on
            /// the GPU, so callers guard zero lengths).
            #[must_use]
            pub fn normalize(self) -> Self {
                Self::from_id(builtin(
                    Builtin::Normalize,
                    &[self.id],
                    <Self as Value>::TYPE,
                ))
            }

            /// `self * (1 - s) + rhs * s`, exactly glam's vector `lerp` (spelled out so the GPU
            /// evaluates the same formula as the CPU).
            #[must_use]
            pub fn lerp(self, rhs: impl Into<$name>, s: impl Into<F32>) -> Self {
                let s = s.into();
                self * (1.0 - s) + rhs.into() * s
            }

            /// Component-wise `e^x`.
            #[must_use]
            pub fn exp(self) -> Self {
                Self::from_id(builtin(Builtin::Exp, &[self.id], <Self as Value>::TYPE))
            }

            /// Component-wise floor.
            #[must_use]
            pub fn floor(self) -> Self {
                Self::from_id(builtin(Builtin::Floor, &[self.id], <Self as Value>::TYPE))
            }

            /// Component-wise `x - floor(x)`, glam's `fract_gl`.
            #[must_use]
            pub fn fract_gl(self) -> Self {
                Self::from_id(builtin(Builtin::Fract, &[self.id], <Self as Value>::TYPE))
            }

            /// Component-wise `clamp(x, 0, 1)`.
            #[must_use]
            pub fn saturate(self) -> Self {
                Self::from_id(builtin(
                    Builtin::Saturate,
                    &[self.id],
                    <Self as Value>::TYPE,
                ))
            }

            /// Component-wise `x^e`, each lane its own exponent (WGSL's vector `pow`).
            #[must_use]
            pub fn pow(self, e: impl Into<$name>) -> Self {
                Self::from_id(builtin(
                    Builtin::Pow,
                    &[self.id, e.into().id],
                    <Self as Value>::TYPE,
                ))
            }

            /// Component-wise `x^e`.
            #[must_use]
            pub fn powf(self, e: impl Into<F32>) -> Self {
                let e = $name::splat(e.into());
                Self::from_id(builtin(
                    Builtin::Pow,
                    &[self.id, e.id],
                    <Self as Value>::TYPE,
                ))
            }
        }

        impl core::ops::Neg for $name {
            type Output = $name;
            fn neg(self) -> $name {
                $name::from_id(unary(UnaryOp::Neg, self.id, <Self as Value>::TYPE))
            }
        }
    };
}

fn swizzle<T: Value>(v: ExprId, idx: &[u8]) -> T {
    T::from_id(push_expr(ExprKind::Swizzle(v, idx.to_vec()), T::TYPE))
}

vector!(
    /// Twin of `glam::Vec2`.
    Vec2, glam::Vec2, F32, f32, Scalar::F32, 2, [x: 0, y: 1], vec2
);
vector!(
    /// Twin of `glam::Vec3`.
    Vec3, glam::Vec3, F32, f32, Scalar::F32, 3, [x: 0, y: 1, z: 2], vec3
);
vector!(
    /// Twin of `glam::Vec4`.
    Vec4, glam::Vec4, F32, f32, Scalar::F32, 4, [x: 0, y: 1, z: 2, w: 3], vec4
);
vector!(
    /// Twin of `glam::IVec2`.
    IVec2, glam::IVec2, I32, i32, Scalar::I32, 2, [x: 0, y: 1], ivec2
);
vector!(
    /// Twin of `glam::IVec3`.
    IVec3, glam::IVec3, I32, i32, Scalar::I32, 3, [x: 0, y: 1, z: 2], ivec3
);
vector!(
    /// Twin of `glam::IVec4`.
    IVec4, glam::IVec4, I32, i32, Scalar::I32, 4, [x: 0, y: 1, z: 2, w: 3], ivec4
);
vector!(
    /// Twin of `glam::UVec2`.
    UVec2, glam::UVec2, U32, u32, Scalar::U32, 2, [x: 0, y: 1], uvec2
);
vector!(
    /// Twin of `glam::UVec3`.
    UVec3, glam::UVec3, U32, u32, Scalar::U32, 3, [x: 0, y: 1, z: 2], uvec3
);
vector!(
    /// Twin of `glam::UVec4`.
    UVec4, glam::UVec4, U32, u32, Scalar::U32, 4, [x: 0, y: 1, z: 2, w: 3], uvec4
);
float_vector!(Vec2);
float_vector!(Vec3);
float_vector!(Vec4);

impl Vec3 {
    /// Cross product.
    #[must_use]
    pub fn cross(self, rhs: impl Into<Vec3>) -> Vec3 {
        Vec3::from_id(builtin(
            Builtin::Cross,
            &[self.id, rhs.into().id],
            Vec3::TYPE,
        ))
    }

    /// `vec4(self, w)`.
    #[must_use]
    pub fn extend(self, w: impl Into<F32>) -> Vec4 {
        let args = vec![self.id, w.into().id()];
        Vec4::from_id(push_expr(ExprKind::Construct(Vec4::TYPE, args), Vec4::TYPE))
    }

    /// `v.xy`.
    #[must_use]
    pub fn truncate(self) -> Vec2 {
        swizzle(self.id, &[0, 1])
    }

    /// `v.xy`.
    #[must_use]
    pub fn xy(self) -> Vec2 {
        swizzle(self.id, &[0, 1])
    }
}

impl Vec2 {
    /// `vec3(self, z)`.
    #[must_use]
    pub fn extend(self, z: impl Into<F32>) -> Vec3 {
        let args = vec![self.id, z.into().id()];
        Vec3::from_id(push_expr(ExprKind::Construct(Vec3::TYPE, args), Vec3::TYPE))
    }
}

impl Vec4 {
    /// `v.xyz`.
    #[must_use]
    pub fn truncate(self) -> Vec3 {
        swizzle(self.id, &[0, 1, 2])
    }

    /// `v.xyz`.
    #[must_use]
    pub fn xyz(self) -> Vec3 {
        swizzle(self.id, &[0, 1, 2])
    }

    /// `v.xy`.
    #[must_use]
    pub fn xy(self) -> Vec2 {
        swizzle(self.id, &[0, 1])
    }
}

impl UVec3 {
    /// `v.xy`.
    #[must_use]
    pub fn xy(self) -> UVec2 {
        swizzle(self.id, &[0, 1])
    }
}

/// CPU twins of DSL vector methods that glam does not have.
pub trait CpuVecExt {
    /// Component-wise `clamp(x, 0, 1)`.
    fn saturate(self) -> Self;

    /// Component-wise `x^e`, each lane its own exponent (WGSL's vector `pow`).
    fn pow(self, e: Self) -> Self;
}

macro_rules! cpu_vec_ext {
    ($($t:ty),*) => {$(
        impl CpuVecExt for $t {
            fn saturate(self) -> Self {
                self.clamp(<$t>::ZERO, <$t>::ONE)
            }

            fn pow(self, e: Self) -> Self {
                <$t>::from_array(
                    core::array::from_fn(|i| self.to_array()[i].powf(e.to_array()[i])),
                )
            }
        }
    )*};
}
cpu_vec_ext!(glam::Vec2, glam::Vec3, glam::Vec4);
