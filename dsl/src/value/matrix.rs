//! Matrix values, twins of glam's column-major `Mat3` and `Mat4`.

use super::{IntoValueOf, Lift, ShaderType, Value, Vec3, Vec4, impl_binop};
use crate::ir::{ExprId, ExprKind, Literal, Type};
use crate::record::push_expr;

macro_rules! matrix {
    ($(#[$doc:meta])* $name:ident, $glam:ty, $n:literal, $col:ident, [$($c:ident),+]) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name(ExprId);

        impl Value for $name {
            const TYPE: Type = Type::Matrix($n);
            fn id(self) -> ExprId {
                self.0
            }
            fn from_id(id: ExprId) -> Self {
                Self(id)
            }
        }

        impl ShaderType for $glam {
            type Dsl = $name;
        }

        impl Lift for $glam {
            fn lift(self) -> $name {
                $name::from_cols($(self.$c),+)
            }
        }

        impl From<$glam> for $name {
            fn from(m: $glam) -> Self {
                m.lift()
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
            /// Builds a matrix from its columns (glam and WGSL are both column-major).
            pub fn from_cols($($c: impl Into<$col>),+) -> Self {
                let args = vec![$($c.into().id()),+];
                Self(push_expr(ExprKind::Construct(Self::TYPE, args), Self::TYPE))
            }

            /// Column `index` (glam's `col`; a constant index, as the CPU twin's `usize`).
            pub fn col(self, index: usize) -> $col {
                debug_assert!(index < $n, "a matrix of {} columns has no column {index}", $n);
                let at = push_expr(ExprKind::Literal(Literal::U32(index as u32)), Type::U32);
                $col::from_id(push_expr(ExprKind::Index(self.0, at), <$col as Value>::TYPE))
            }
        }

        impl_binop!($name, $col => $col; Mul mul Mul);
        impl_binop!($name, $name => $name; Mul mul Mul);
    };
}

matrix!(
    /// Twin of `glam::Mat3`.
    Mat3, glam::Mat3, 3, Vec3, [x_axis, y_axis, z_axis]
);
matrix!(
    /// Twin of `glam::Mat4`.
    Mat4, glam::Mat4, 4, Vec4, [x_axis, y_axis, z_axis, w_axis]
);
