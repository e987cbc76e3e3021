//! Named module constants. A Rust `const` that a `#[shader_fn]` reads by name (`INV_FOUR_PI`,
//! `f32::consts::PI`) prints as a WGSL `const` of that name, not as a bare number at each use.
//! The macro knows the path is not a local or a parameter (it tracks those), so it is an item;
//! what it becomes is decided by its type, not its spelling:
//!
//! - `f32`, `i32` and `u32` constants become named constants ([`NamedConst`]), and a
//!   [`Binding`](crate::Binding) static becomes a module binding;
//! - glam vectors and matrices (`Vec3::ZERO`) become DSL values ([`LiftedConst`]);
//! - anything else (a `bool` or an enum a generation-time branch tests) stays the plain Rust
//!   value it is ([`PlainConst`]).
//!
//! The dispatch is by method resolution on a probe
//! (`(&&&ConstProbe(name, value)).shader_value()`): each tier is implemented one reference
//! deeper than the next, so the first that applies wins. The CPU twin reads the Rust item itself.

use crate::ir::{ExprKind, Global, GlobalKind, Literal};
use crate::record::{self, push_expr};
use crate::value::{F32, I32, Lift, ShaderType, U32, Value};

/// A constant the macro met in a `#[shader_fn]` body: its Rust name and value.
pub struct ConstProbe<T>(pub &'static str, pub T);

/// Constants that print as named WGSL constants.
pub trait NamedConst {
    type Out;
    fn shader_value(&self) -> Self::Out;
}

/// Vector and matrix constants: the DSL value of the same components.
pub trait LiftedConst {
    type Out;
    fn shader_value(&self) -> Self::Out;
}

/// Every other constant: its value, as the Rust code uses it.
pub trait PlainConst {
    type Out;
    fn shader_value(&self) -> Self::Out;
}

impl<T: Copy> PlainConst for ConstProbe<T> {
    type Out = T;
    fn shader_value(&self) -> T {
        self.1
    }
}

fn named<V: Value>(name: &'static str, value: Literal) -> V {
    let global = Global {
        name: record::sanitize(name),
        ty: V::TYPE,
        kind: GlobalKind::Const { value },
        doc: String::new(),
        sampler: None,
    };
    let id = match record::add_global(global) {
        Ok(id) => id,
        Err(reason) => {
            record::push_error(format!("constant `{name}`: {reason}"));
            return V::from_id(push_expr(ExprKind::Literal(value), V::TYPE));
        }
    };
    V::from_id(push_expr(ExprKind::Global(id), V::TYPE))
}

macro_rules! named_const {
    ($($t:ty => $dsl:ty, $lit:expr;)*) => {$(
        impl NamedConst for &&ConstProbe<$t> {
            type Out = $dsl;
            fn shader_value(&self) -> $dsl {
                named(self.0, $lit(self.1))
            }
        }
    )*};
}

named_const! {
    f32 => F32, Literal::f32;
    i32 => I32, Literal::I32;
    u32 => U32, Literal::U32;
}

macro_rules! lifted_const {
    ($($t:ty),*) => {$(
        impl LiftedConst for &ConstProbe<$t> {
            type Out = <$t as ShaderType>::Dsl;
            fn shader_value(&self) -> Self::Out {
                self.1.lift()
            }
        }
    )*};
}

lifted_const!(
    glam::Vec2,
    glam::Vec3,
    glam::Vec4,
    glam::IVec2,
    glam::IVec3,
    glam::IVec4,
    glam::UVec2,
    glam::UVec3,
    glam::UVec4,
    glam::Mat3,
    glam::Mat4
);

#[cfg(test)]
mod tests {
    use super::{ConstProbe, LiftedConst as _, NamedConst as _, PlainConst as _};

    #[test]
    #[allow(
        clippy::needless_borrow,
        reason = "the probe is called as the macro writes it"
    )]
    fn plain_values_stay_plain() {
        // Outside a recording only the plain dispatch can run: bools and enums keep their value.
        assert!((&&&ConstProbe("FLAG", true)).shader_value());
        assert_eq!((&&&ConstProbe("N", 3usize)).shader_value(), 3);
    }

    #[test]
    #[allow(
        clippy::needless_borrow,
        reason = "the probe is called as the macro writes it"
    )]
    fn scalar_types_are_named() {
        // The named dispatch is chosen by type; its output is a recorded value.
        fn out_type<T>(_: &dyn Fn() -> T) -> &'static str {
            std::any::type_name::<T>()
        }
        let ty = out_type(&|| (&&&ConstProbe("X", 1.0f32)).shader_value());
        assert!(ty.ends_with("F32"), "{ty}");
        let ty = out_type(&|| (&&&ConstProbe("ZERO", glam::Vec3::ZERO)).shader_value());
        assert!(ty.ends_with("Vec3") && ty.contains("nimbus_dsl"), "{ty}");
    }
}
