//! The traits that tie CPU types to DSL types.

use crate::ir::{ExprId, Type};

/// A recorded shader value: a typed handle to an expression.
pub trait Value: Copy {
    /// The shader type of every value of this Rust type.
    const TYPE: Type;
    /// The expression this value stands for.
    fn id(self) -> ExprId;
    /// Wraps an expression of type [`Value::TYPE`].
    fn from_id(id: ExprId) -> Self;
}

/// A CPU type with a shader twin: `f32` ↔ [`crate::shader::F32`], `glam::Vec3` ↔
/// [`crate::shader::Vec3`], a `#[derive(ShaderStruct)]` struct ↔ its generated twin.
///
/// `#[shader_fn]` maps every parameter type through this trait, so the macro never needs to
/// know type names.
pub trait ShaderType {
    type Dsl: Value;
}

/// A CPU value that can become a shader constant (`Vec3::ZERO`, `f32::MAX`, ...).
pub trait Lift: ShaderType {
    fn lift(self) -> Self::Dsl;
}

/// Turns a CPU constant into its shader twin (used by `#[shader_fn]` for paths like
/// `Vec3::ZERO`).
pub fn lift<T: Lift>(v: T) -> T::Dsl {
    v.lift()
}

/// A generation-time parameter value (`#[spec]`). Each distinct value gives its own specialised
/// copy of the function, named with [`SpecValue::suffix`].
pub trait SpecValue: Copy + std::fmt::Debug {
    /// Short identifier fragment, e.g. `dual_lobe` or `4`, appended to the function name. An
    /// empty suffix keeps the name as is; the recorder then refuses a second, different value
    /// in the same module rather than silently reusing the first copy.
    fn suffix(&self) -> String;

    /// How the value reads in the generated code's comments (`specialised for key = …`): a
    /// short name a reviewer can scan, never a `Debug` dump.
    fn label(&self) -> String;
}

impl SpecValue for bool {
    fn suffix(&self) -> String {
        if *self { "on".into() } else { "off".into() }
    }

    fn label(&self) -> String {
        self.to_string()
    }
}

macro_rules! spec_int {
    ($($t:ty),*) => {$(
        impl SpecValue for $t {
            fn suffix(&self) -> String {
                self.to_string()
            }

            fn label(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
spec_int!(u8, u16, u32, usize, i32);
