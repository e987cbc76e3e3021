//! How a call in a `#[shader_fn]` body finds its shader twin: by declaration, not by spelling.
//!
//! A procedural macro sees tokens, not items, so it cannot know whether `a::b(x)` names an
//! associated function of a type `a` or a function `b` in a module `a`, or whether `helper(x)`
//! is a `#[shader_fn]` at all. Instead of guessing, the macro rewrites every call into a name
//! that rustc resolves as it resolves any other, and whoever declares a function with a shader
//! twin declares the twin under that name:
//!
//! - a call by a single name, `f(x)`, becomes `f::shader(x)`: the twin lives in a module named
//!   like the function, so `use path::f;` brings both (functions and modules live in different
//!   namespaces). `#[shader_fn] fn f` declares `mod f`; the built-ins that are one generic
//!   function for both twins (`mix`, `smoothstep`, ...) and the vector constructors (`vec3`,
//!   ...) have theirs below.
//! - a call by a path, `a::b(x)`, becomes `a::__shader_twin_b(x)`, which works whether `a` is a
//!   module or a type: `#[shader_fn] fn b` declares `__shader_twin_b` beside `b`, and the Rust
//!   types whose associated functions have twins (`Vec3::new`, `Mat4::from_cols`, `f32::max`)
//!   declare them through the traits below, implemented on the Rust type itself.
//!
//! Every shader-twin module imports this module, so these are in scope wherever the macro's
//! output is. Calling a plain Rust function fails to compile at the call (rustc cannot find
//! `helper::shader` or `__shader_twin_helper`): mark the function `#[shader_fn]`, or compute the
//! value outside the shader function and pass it in. A user's own function with the name of a
//! built-in here makes the call ambiguous, which rustc reports, rather than silently picking one.

use crate::value::{F32, I32, Mat3, Mat4, U32, Vec3, Vec4};

macro_rules! twin_modules {
    ($($(#[$doc:meta])* $name:ident => $twin:path;)+) => {$(
        $(#[$doc])*
        pub mod $name {
            pub use $twin as shader;
        }
    )+};
}

twin_modules! {
    /// Twin of `mix` (the same generic function).
    mix => crate::builtins::mix;
    /// Twin of `smoothstep` (the same generic function).
    smoothstep => crate::builtins::smoothstep;
    /// Twin of `step` (the same generic function).
    step => crate::builtins::step;
    /// Twin of `select` (the same generic function).
    select => crate::builtins::select;
    /// Twin of `pack4x8unorm` (the same generic function).
    pack4x8unorm => crate::builtins::pack4x8unorm;
    /// Twin of glam's `vec2`.
    vec2 => crate::value::vec2;
    /// Twin of glam's `vec3`.
    vec3 => crate::value::vec3;
    /// Twin of glam's `vec4`.
    vec4 => crate::value::vec4;
    /// Twin of glam's `ivec2`.
    ivec2 => crate::value::ivec2;
    /// Twin of glam's `ivec3`.
    ivec3 => crate::value::ivec3;
    /// Twin of glam's `ivec4`.
    ivec4 => crate::value::ivec4;
    /// Twin of glam's `uvec2`.
    uvec2 => crate::value::uvec2;
    /// Twin of glam's `uvec3`.
    uvec3 => crate::value::uvec3;
    /// Twin of glam's `uvec4`.
    uvec4 => crate::value::uvec4;
}

/// Twins of a glam vector type's constructors (`Vec3::splat(v)`).
pub trait VectorTwin {
    /// The DSL vector.
    type Dsl;
    /// Its component type.
    type Scalar;
    /// Twin of `splat`.
    fn __shader_twin_splat(v: impl Into<Self::Scalar>) -> Self::Dsl;
}

/// Twin of a two-component glam vector's `new`.
pub trait Vector2Twin: VectorTwin {
    /// Twin of `new`.
    fn __shader_twin_new(x: impl Into<Self::Scalar>, y: impl Into<Self::Scalar>) -> Self::Dsl;
}

/// Twin of a three-component glam vector's `new`.
pub trait Vector3Twin: VectorTwin {
    /// Twin of `new`.
    fn __shader_twin_new(
        x: impl Into<Self::Scalar>,
        y: impl Into<Self::Scalar>,
        z: impl Into<Self::Scalar>,
    ) -> Self::Dsl;
}

/// Twin of a four-component glam vector's `new`.
pub trait Vector4Twin: VectorTwin {
    /// Twin of `new`.
    fn __shader_twin_new(
        x: impl Into<Self::Scalar>,
        y: impl Into<Self::Scalar>,
        z: impl Into<Self::Scalar>,
        w: impl Into<Self::Scalar>,
    ) -> Self::Dsl;
}

macro_rules! vector_twin {
    ($new:ident, $glam:ty => $dsl:ident, $scalar:ident, [$($c:ident),+]) => {
        impl VectorTwin for $glam {
            type Dsl = crate::value::$dsl;
            type Scalar = $scalar;
            fn __shader_twin_splat(v: impl Into<$scalar>) -> Self::Dsl {
                crate::value::$dsl::splat(v)
            }
        }

        impl $new for $glam {
            fn __shader_twin_new($($c: impl Into<$scalar>),+) -> Self::Dsl {
                crate::value::$dsl::new($($c),+)
            }
        }
    };
}

vector_twin!(Vector2Twin, glam::Vec2 => Vec2, F32, [x, y]);
vector_twin!(Vector2Twin, glam::IVec2 => IVec2, I32, [x, y]);
vector_twin!(Vector2Twin, glam::UVec2 => UVec2, U32, [x, y]);
vector_twin!(Vector3Twin, glam::Vec3 => Vec3, F32, [x, y, z]);
vector_twin!(Vector3Twin, glam::IVec3 => IVec3, I32, [x, y, z]);
vector_twin!(Vector3Twin, glam::UVec3 => UVec3, U32, [x, y, z]);
vector_twin!(Vector4Twin, glam::Vec4 => Vec4, F32, [x, y, z, w]);
vector_twin!(Vector4Twin, glam::IVec4 => IVec4, I32, [x, y, z, w]);
vector_twin!(Vector4Twin, glam::UVec4 => UVec4, U32, [x, y, z, w]);

/// Twin of `Mat3::from_cols`.
pub trait Mat3Twin {
    /// Twin of `from_cols`.
    fn __shader_twin_from_cols(x: impl Into<Vec3>, y: impl Into<Vec3>, z: impl Into<Vec3>) -> Mat3;
}

impl Mat3Twin for glam::Mat3 {
    fn __shader_twin_from_cols(x: impl Into<Vec3>, y: impl Into<Vec3>, z: impl Into<Vec3>) -> Mat3 {
        Mat3::from_cols(x, y, z)
    }
}

/// Twin of `Mat4::from_cols`.
pub trait Mat4Twin {
    /// Twin of `from_cols`.
    fn __shader_twin_from_cols(
        x: impl Into<Vec4>,
        y: impl Into<Vec4>,
        z: impl Into<Vec4>,
        w: impl Into<Vec4>,
    ) -> Mat4;
}

impl Mat4Twin for glam::Mat4 {
    fn __shader_twin_from_cols(
        x: impl Into<Vec4>,
        y: impl Into<Vec4>,
        z: impl Into<Vec4>,
        w: impl Into<Vec4>,
    ) -> Mat4 {
        Mat4::from_cols(x, y, z, w)
    }
}

/// Twins of the scalar functions Rust code also calls through the type (`f32::max(a, b)`).
pub trait ScalarTwin {
    /// The DSL scalar.
    type Dsl;
    /// Twin of `min`.
    fn __shader_twin_min(a: impl Into<Self::Dsl>, b: impl Into<Self::Dsl>) -> Self::Dsl;
    /// Twin of `max`.
    fn __shader_twin_max(a: impl Into<Self::Dsl>, b: impl Into<Self::Dsl>) -> Self::Dsl;
    /// Twin of `clamp`.
    fn __shader_twin_clamp(
        x: impl Into<Self::Dsl>,
        lo: impl Into<Self::Dsl>,
        hi: impl Into<Self::Dsl>,
    ) -> Self::Dsl;
}

macro_rules! scalar_twins {
    ($($rust:ty => $dsl:ident;)+) => {$(
        impl ScalarTwin for $rust {
            type Dsl = $dsl;
            fn __shader_twin_min(a: impl Into<$dsl>, b: impl Into<$dsl>) -> $dsl {
                a.into().min(b)
            }
            fn __shader_twin_max(a: impl Into<$dsl>, b: impl Into<$dsl>) -> $dsl {
                a.into().max(b)
            }
            fn __shader_twin_clamp(
                x: impl Into<$dsl>,
                lo: impl Into<$dsl>,
                hi: impl Into<$dsl>,
            ) -> $dsl {
                x.into().clamp(lo, hi)
            }
        }
    )+};
}

scalar_twins! {
    f32 => F32;
    i32 => I32;
    u32 => U32;
}
