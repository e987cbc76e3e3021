//! nimbus-macros: `#[shader_fn]` and `#[derive(ShaderStruct)]`.
//!
//! `#[shader_fn]` keeps the function exactly as written (the CPU twin) and adds a hidden module
//! of the same name holding the shader twin: the same body, rewritten only where Rust cannot
//! overload (comparisons, `&&`, `as`, `let`, `if`, `for`, `return`), run over the DSL types to
//! record IR. Everything else (arithmetic, method calls, field access) is left as written and
//! resolved by the DSL types' own impls, so rustc type-checks both twins.

mod shader_fn;
mod shader_struct;
mod transform;

use proc_macro::TokenStream;

/// Marks a function as a shader function: it stays an ordinary Rust function and also gets a
/// shader twin, `name::shader(..)`, that records it into the module being built.
///
/// Parameters marked `#[spec]` are generation-time values: plain Rust values while the shader
/// is generated (an `if` on them keeps only the taken branch), and one specialised copy of the
/// function is emitted per distinct value.
#[proc_macro_attribute]
pub fn shader_fn(attr: TokenStream, item: TokenStream) -> TokenStream {
    shader_fn::expand(attr.into(), item.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// Derives the shader twin of a plain struct of shader types (a uniform block): a WGSL struct
/// declaration, a DSL value type with the same field names, and the `ShaderType` link.
#[proc_macro_derive(ShaderStruct)]
pub fn derive_shader_struct(item: TokenStream) -> TokenStream {
    shader_struct::expand(item.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}
