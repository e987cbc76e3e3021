//! `#[shader_fn]`: signature checks and the generated shader-twin module.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::{Attribute, FnArg, ItemFn, Pat, ReturnType, Type};

use crate::transform::Transformer;

/// The `#[doc = "..."]` lines of an item, trimmed of the one leading space rustdoc adds.
pub(crate) fn doc_lines(attrs: &[Attribute]) -> Vec<String> {
    attrs
        .iter()
        .filter(|a| a.path().is_ident("doc"))
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(
                    s.value()
                        .strip_prefix(' ')
                        .unwrap_or(&s.value())
                        .to_string(),
                ),
                _ => None,
            },
            _ => None,
        })
        .collect()
}

/// Strips `&` and `&mut` from a parameter type: the shader twin passes handles by value.
fn strip_ref(ty: &Type) -> &Type {
    match ty {
        Type::Reference(r) => strip_ref(&r.elem),
        Type::Paren(p) => strip_ref(&p.elem),
        other => other,
    }
}

struct Param {
    name: syn::Ident,
    ty: Type,
    spec: bool,
}

pub(crate) fn expand(attr: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    if !attr.is_empty() {
        return Err(syn::Error::new_spanned(
            attr,
            "#[shader_fn] takes no arguments (mark generation-time parameters with #[spec])",
        ));
    }
    let mut func: ItemFn = syn::parse2(item)?;
    let sig = &func.sig;
    if let Some(t) = &sig.asyncness {
        return Err(syn::Error::new_spanned(t, "a #[shader_fn] cannot be async"));
    }
    if let Some(t) = &sig.unsafety {
        return Err(syn::Error::new_spanned(
            t,
            "a #[shader_fn] cannot be unsafe",
        ));
    }
    if !sig.generics.params.is_empty() {
        return Err(syn::Error::new_spanned(
            &sig.generics,
            "a #[shader_fn] cannot be generic: use a #[spec] parameter for generation-time choices",
        ));
    }
    if let Some(v) = &sig.variadic {
        return Err(syn::Error::new_spanned(
            v,
            "a #[shader_fn] cannot be variadic",
        ));
    }
    let ret_ty = match &sig.output {
        ReturnType::Type(_, ty) => (**ty).clone(),
        ReturnType::Default => {
            return Err(syn::Error::new_spanned(
                &sig.ident,
                "a #[shader_fn] must return a value (shader functions are pure)",
            ));
        }
    };

    let mut params = Vec::new();
    for arg in &sig.inputs {
        match arg {
            FnArg::Receiver(r) => {
                return Err(syn::Error::new_spanned(
                    r,
                    "a #[shader_fn] cannot take `self`: write a free function",
                ));
            }
            FnArg::Typed(pt) => {
                let Pat::Ident(pi) = &*pt.pat else {
                    return Err(syn::Error::new_spanned(
                        &pt.pat,
                        "#[shader_fn] parameters must be plain names",
                    ));
                };
                if let Some(m) = &pi.mutability {
                    return Err(syn::Error::new_spanned(
                        m,
                        "#[shader_fn] parameters cannot be `mut`: bind a `let mut` copy in the body",
                    ));
                }
                let spec = pt.attrs.iter().any(|a| a.path().is_ident("spec"));
                if let Some(a) = pt.attrs.iter().find(|a| !a.path().is_ident("spec")) {
                    return Err(syn::Error::new_spanned(
                        a,
                        "the only parameter attribute #[shader_fn] knows is #[spec]",
                    ));
                }
                params.push(Param {
                    name: pi.ident.clone(),
                    ty: strip_ref(&pt.ty).clone(),
                    spec,
                });
            }
        }
    }

    // The shader twin's body. Parameters are declared names: only a name declared nowhere in
    // the function is a constant item.
    let mut tr = Transformer::new();
    for p in &params {
        tr.declare_param(p.name.to_string());
    }
    let body = tr.function_body(&func.block)?;

    // CPU twin: the function as written, minus our parameter attributes.
    for arg in &mut func.sig.inputs {
        if let FnArg::Typed(pt) = arg {
            pt.attrs.retain(|a| !a.path().is_ident("spec"));
        }
    }

    let vis = &func.vis;
    let ident = &func.sig.ident;
    let name_str = ident.to_string();
    let docs = doc_lines(&func.attrs);
    let fn_span = func.sig.ident.span();
    let loc = quote_spanned! {fn_span=>
        ::nimbus_dsl::ir::SourceLoc::new(::core::file!(), ::core::line!(), ::core::column!())
    };

    let dsl_ty = |ty: &Type| quote! { <#ty as ::nimbus_dsl::ShaderType>::Dsl };
    let mut shader_params = Vec::new();
    let mut conversions = Vec::new();
    let mut header_params = Vec::new();
    let mut rebinds = Vec::new();
    let mut arg_ids = Vec::new();
    let mut spec_suffixes = Vec::new();
    let mut spec_notes = Vec::new();
    let mut const_params = Vec::new();
    let mut call_ids_args = Vec::new();
    let mut arg_index = 0usize;
    for p in &params {
        let n = &p.name;
        let ty = &p.ty;
        let n_str = n.to_string();
        if p.spec {
            shader_params.push(quote! { #n: #ty });
            spec_suffixes.push(quote! { ::nimbus_dsl::SpecValue::suffix(&#n) });
            spec_notes.push(quote! {
                ::std::format!("{} = {}", #n_str, ::nimbus_dsl::SpecValue::label(&#n))
            });
        } else {
            let d = dsl_ty(ty);
            shader_params.push(quote! { #n: impl ::core::convert::Into<#d> });
            conversions.push(quote! { let #n: #d = ::core::convert::Into::into(#n); });
            header_params.push(quote! {
                ::nimbus_dsl::ir::Param {
                    name: ::nimbus_dsl::record::sanitize(#n_str),
                    ty: <#d as ::nimbus_dsl::Value>::TYPE,
                }
            });
            let i = arg_index;
            rebinds.push(quote! { let #n: #d = ::nimbus_dsl::Value::from_id(__args[#i]); });
            arg_ids.push(quote! { ::nimbus_dsl::Value::id(#n) });
            const_params.push(quote! { (#n_str, <#d as ::nimbus_dsl::Value>::TYPE) });
            call_ids_args.push(quote! { <#d as ::nimbus_dsl::Value>::from_id(args[#i]) });
            arg_index += 1;
        }
    }
    let ret_dsl = dsl_ty(&ret_ty);
    let doc_tokens = docs.iter().map(|d| quote! { #d.to_string() });
    let has_spec = !spec_suffixes.is_empty();
    let name_expr = if has_spec {
        quote! {{
            let mut __n = ::std::string::String::from(#name_str);
            #(
                let __s = #spec_suffixes;
                if !__s.is_empty() {
                    __n.push('_');
                    __n.push_str(&__s);
                }
            )*
            ::nimbus_dsl::record::sanitize(&__n)
        }}
    } else {
        quote! { ::nimbus_dsl::record::sanitize(#name_str) }
    };
    // Only non-specialised functions get the id-level entry used by test harnesses.
    let call_ids = if has_spec {
        quote! {}
    } else {
        quote! {
            /// Calls the shader twin with recorded argument expressions (for harnesses that
            /// build kernels around a function from its signature alone).
            pub fn call_ids(args: &[::nimbus_dsl::ir::ExprId]) -> ::nimbus_dsl::ir::ExprId {
                ::nimbus_dsl::Value::id(shader(#(#call_ids_args),*))
            }
        }
    };
    let mod_doc =
        format!("Shader twin of [`{name_str}`](fn@{name_str}) (generated by `#[shader_fn]`).");
    // The name a call in another shader function resolves to (see `nimbus_dsl::twin`).
    let twin_name = syn::Ident::new(&format!("__shader_twin_{name_str}"), ident.span());

    Ok(quote! {
        #func

        #[doc = #mod_doc]
        #[allow(non_snake_case, unused_imports, unused_variables, unused_braces, unused_parens, private_interfaces, clippy::all)]
        #vis mod #ident {
            use super::*;
            use ::nimbus_dsl::twin::*;

            /// The Rust name of the function.
            pub const NAME: &str = #name_str;
            /// Parameters that are shader values (not `#[spec]`), with their shader types.
            pub const PARAMS: &[(&str, ::nimbus_dsl::ir::Type)] = &[#(#const_params),*];
            /// The shader type of the result.
            pub const RESULT: ::nimbus_dsl::ir::Type = <#ret_dsl as ::nimbus_dsl::Value>::TYPE;

            type __Ret = #ret_dsl;

            /// Records a call (and, on first use in a module, the definition) of this function.
            pub fn shader(#(#shader_params),*) -> #ret_dsl {
                #(#conversions)*
                let __header = ::nimbus_dsl::record::FunctionHeader {
                    name: #name_expr,
                    rust_name: ::std::string::String::from(#name_str),
                    doc: ::std::vec![#(#doc_tokens),*],
                    specialised: ::std::vec![#(#spec_notes),*],
                    params: ::std::vec![#(#header_params),*],
                    result: ::core::option::Option::Some(<#ret_dsl as ::nimbus_dsl::Value>::TYPE),
                    loc: #loc,
                };
                let __callee = ::nimbus_dsl::record::ensure_function(__header, move |__args| {
                    #(#rebinds)*
                    #body
                });
                <#ret_dsl as ::nimbus_dsl::Value>::from_id(::nimbus_dsl::record::push_expr(
                    ::nimbus_dsl::ir::ExprKind::Call(__callee, ::std::vec![#(#arg_ids),*]),
                    <#ret_dsl as ::nimbus_dsl::Value>::TYPE,
                ))
            }

            #call_ids
        }

        #[doc(hidden)]
        #[allow(unused_imports)]
        #vis use #ident::shader as #twin_name;
    })
}
