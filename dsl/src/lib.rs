//! nimbus-dsl: a typed shader DSL embedded in Rust.
//!
//! A shader function is written once as an ordinary Rust function over `f32` and glam types and
//! marked `#[shader_fn]`. It compiles as that Rust function (the CPU twin, used by tests and
//! reference renders) and, through the macro, as a recorder of the same body over the DSL types
//! in [`shader`] (the shader twin), which builds the [`ir`] that codegen prints as WGSL.
//!
//! ```
//! use nimbus_dsl::prelude::*;
//!
//! /// Linear ramp used in docs.
//! #[shader_fn]
//! pub fn ramp(x: f32, slope: f32) -> f32 {
//!     (x * slope).clamp(0.0, 1.0)
//! }
//!
//! assert_eq!(ramp(0.25, 2.0), 0.5); // the CPU twin is a plain function
//! ```

extern crate self as nimbus_dsl;

mod binding;
pub mod builtins;
pub mod constant;
pub mod control;
pub mod cpu;
mod host;
pub mod ir;
pub mod layout;
mod module;
pub mod ops;
pub mod record;
pub mod twin;
pub mod value;
mod variant;

pub use binding::{Binding, BoundGuard, CpuBindings, ShaderBinding};
pub use host::HostFn;
pub use module::{DslError, GlobalRef, ModuleBuilder};
pub use nimbus_macros::{ShaderStruct, shader_fn};
pub use value::{Lift, ShaderType, SpecValue, Value, lift};
pub use variant::ShaderVariant;

/// The DSL value types (shader twins of `f32`, glam vectors, textures...).
pub mod shader {
    pub use crate::value::{
        Array, Bool, F32, I32, IVec2, IVec3, IVec4, Mat3, Mat4, Sampler, StorageArray, Texture2d,
        Texture3d, U32, UVec2, UVec3, UVec4, Vec2, Vec3, Vec4, ivec2, ivec3, ivec4, uvec2, uvec3,
        uvec4, vec2, vec3, vec4,
    };
}

/// What a file of shader functions imports: the macros, the built-ins that work on both CPU and
/// DSL values, and the CPU extension methods (`fract_gl`, `saturate`, ...).
pub mod prelude {
    pub use crate::builtins::{mix, pack4x8unorm, select, smoothstep, step};
    pub use crate::control::{unroll, unroll_known};
    pub use crate::value::CpuVecExt;
    pub use crate::value::scalar_ext::CpuScalarExt;
    pub use crate::{ShaderStruct, shader_fn};
    pub use glam::FloatExt as _;
    pub use glam::swizzles::{Vec3Swizzles as _, Vec4Swizzles as _};
    pub use glam::{Vec2, Vec3, Vec4, vec2, vec3, vec4};
}
