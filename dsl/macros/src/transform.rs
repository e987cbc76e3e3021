//! Rewrites a `#[shader_fn]` body into its shader twin.
//!
//! Only what Rust cannot overload is rewritten; each rewrite goes to a function in
//! `nimbus_dsl::{control, ops}` that records a statement for DSL values and simply computes for
//! plain Rust values. Unsupported syntax is refused here, with the error on that syntax.

use std::collections::HashMap;

use proc_macro2::{Span, TokenStream};
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;
use syn::{BinOp, Block, Expr, Lit, Pat, Stmt, UnOp};

fn unsupported(node: impl quote::ToTokens, what: &str) -> syn::Error {
    syn::Error::new_spanned(node, format!("{what} is not supported in a #[shader_fn]"))
}

fn loc(span: Span) -> TokenStream {
    quote_spanned! {span=>
        ::nimbus_dsl::ir::SourceLoc::new(::core::file!(), ::core::line!(), ::core::column!())
    }
}

pub(crate) struct Transformer {
    /// Scopes of local names: `true` for `let mut` (a recorded `var`).
    scopes: Vec<HashMap<String, bool>>,
}

impl Transformer {
    pub(crate) fn new() -> Self {
        Self {
            scopes: vec![HashMap::new()],
        }
    }

    fn is_mutable(&self, name: &str) -> bool {
        for scope in self.scopes.iter().rev() {
            if let Some(m) = scope.get(name) {
                return *m;
            }
        }
        false
    }

    /// Whether `name` is a parameter or a local in scope (not a constant item).
    fn is_declared(&self, name: &str) -> bool {
        self.scopes.iter().any(|s| s.contains_key(name))
    }

    /// Declares a parameter of the function.
    pub(crate) fn declare_param(&mut self, name: String) {
        self.declare(name, false);
    }

    fn declare(&mut self, name: String, mutable: bool) {
        if let Some(scope) = self.scopes.last_mut() {
            scope.insert(name, mutable);
        }
    }

    /// The function body: statements, then the tail converted to the result type.
    pub(crate) fn function_body(&mut self, block: &Block) -> syn::Result<TokenStream> {
        let (stmts, tail) = self.block_parts(block)?;
        let tail = tail.unwrap_or_else(|| quote! { () });
        Ok(quote! {
            #(#stmts)*
            ::nimbus_dsl::control::tail::<__Ret, _>(#tail)
        })
    }

    /// A block's statements and its tail expression, in a new scope.
    fn block_parts(
        &mut self,
        block: &Block,
    ) -> syn::Result<(Vec<TokenStream>, Option<TokenStream>)> {
        self.scopes.push(HashMap::new());
        let result = self.block_parts_inner(block);
        self.scopes.pop();
        result
    }

    fn block_parts_inner(
        &mut self,
        block: &Block,
    ) -> syn::Result<(Vec<TokenStream>, Option<TokenStream>)> {
        let mut out = Vec::new();
        let mut tail = None;
        let n = block.stmts.len();
        for (i, stmt) in block.stmts.iter().enumerate() {
            let last = i + 1 == n;
            match stmt {
                Stmt::Local(local) => out.push(self.local(local)?),
                Stmt::Expr(e, Some(_)) => out.push(self.statement_expr(e)?),
                Stmt::Expr(e, None) if last => tail = Some(self.expr(e)?),
                Stmt::Expr(e, None) => {
                    // `if`/`for` blocks without a semicolon in statement position.
                    out.push(self.statement_expr(e)?);
                }
                Stmt::Item(item) => {
                    return Err(unsupported(item, "an item declared inside the body"));
                }
                Stmt::Macro(m) => return Err(unsupported(m, "a macro call")),
            }
        }
        Ok((out, tail))
    }

    fn block(&mut self, block: &Block) -> syn::Result<TokenStream> {
        let (stmts, tail) = self.block_parts(block)?;
        let tail = tail.unwrap_or_else(|| quote! { () });
        Ok(quote! { { #(#stmts)* #tail } })
    }

    /// An expression used as a statement (its value, if any, is dropped).
    fn statement_expr(&mut self, e: &Expr) -> syn::Result<TokenStream> {
        match e {
            Expr::Return(r) => {
                let l = loc(r.span());
                let value = match &r.expr {
                    Some(v) => self.expr(v)?,
                    None => return Err(unsupported(r, "a `return` without a value")),
                };
                Ok(quote! {
                    ::nimbus_dsl::control::ret::<__Ret>(#l, ::core::convert::Into::<__Ret>::into(#value));
                })
            }
            other => {
                let t = self.expr(other)?;
                Ok(quote! { let _ = #t; })
            }
        }
    }

    fn local(&mut self, local: &syn::Local) -> syn::Result<TokenStream> {
        let (ident, mutable, ty) = match &local.pat {
            Pat::Ident(pi) => (&pi.ident, pi.mutability.is_some(), None),
            Pat::Type(pt) => match &*pt.pat {
                Pat::Ident(pi) => (&pi.ident, pi.mutability.is_some(), Some(&*pt.ty)),
                other => {
                    return Err(unsupported(other, "a destructuring pattern"));
                }
            },
            other => return Err(unsupported(other, "a destructuring pattern")),
        };
        if let Some(pi) = match &local.pat {
            Pat::Ident(pi) => Some(pi),
            _ => None,
        } && let Some(r) = &pi.by_ref
        {
            return Err(unsupported(r, "a `ref` binding"));
        }
        let Some(init) = &local.init else {
            return Err(syn::Error::new_spanned(
                local,
                "a `let` in a #[shader_fn] needs an initial value",
            ));
        };
        if let Some((_, diverge)) = &init.diverge {
            return Err(unsupported(diverge, "`let ... else`"));
        }
        let value = self.expr(&init.expr)?;
        let name = ident.to_string();
        let l = loc(local.span());
        let tokens = match (mutable, ty) {
            (false, None) => {
                quote! { let #ident = ::nimbus_dsl::control::bind(#name, #l, #value); }
            }
            (false, Some(ty)) => quote! {
                let #ident: <#ty as ::nimbus_dsl::ShaderType>::Dsl = ::nimbus_dsl::control::bind(
                    #name, #l, ::core::convert::Into::<<#ty as ::nimbus_dsl::ShaderType>::Dsl>::into(#value));
            },
            (true, None) => {
                quote! { let #ident = ::nimbus_dsl::control::var(#name, #l, #value); }
            }
            (true, Some(ty)) => quote! {
                let #ident = ::nimbus_dsl::control::var_typed::<<#ty as ::nimbus_dsl::ShaderType>::Dsl>(#name, #l, #value);
            },
        };
        self.declare(name, mutable);
        Ok(tokens)
    }

    fn mutable_target(&self, e: &Expr) -> syn::Result<syn::Ident> {
        if let Expr::Path(p) = e
            && let Some(id) = p.path.get_ident()
            && self.is_mutable(&id.to_string())
        {
            return Ok(id.clone());
        }
        Err(syn::Error::new_spanned(
            e,
            "only a `let mut` local can be assigned in a #[shader_fn] (no fields, no parameters)",
        ))
    }

    pub(crate) fn expr(&mut self, e: &Expr) -> syn::Result<TokenStream> {
        Ok(match e {
            Expr::Lit(lit) => match &lit.lit {
                Lit::Float(f) if f.suffix().is_empty() => {
                    let v = syn::LitFloat::new(&format!("{}f32", f.base10_digits()), f.span());
                    quote! { #v }
                }
                Lit::Float(f) if f.suffix() == "f32" => quote! { #f },
                Lit::Float(f) => return Err(unsupported(f, "a non-f32 float literal")),
                Lit::Int(_) | Lit::Bool(_) => quote! { #lit },
                other => return Err(unsupported(other, "this kind of literal")),
            },
            Expr::Path(p) => {
                if p.qself.is_some() {
                    return Err(unsupported(p, "a qualified path"));
                }
                let local = p.path.get_ident().map(|id| (id, id.to_string()));
                match local {
                    Some((id, name)) if self.is_mutable(&name) => quote! { #id.get() },
                    Some((_, name)) if self.is_declared(&name) => quote! { #p },
                    _ => {
                        // Not a local: a constant (`INV_PI`, `f32::consts::PI`, `Vec3::ZERO`,
                        // `Toggle::Shadows`). What it becomes is decided by its type, not its
                        // spelling: see `nimbus_dsl::constant`.
                        let name = p
                            .path
                            .segments
                            .last()
                            .map(|s| s.ident.to_string())
                            .unwrap_or_default();
                        quote! {
                            {
                                #[allow(unused_imports)]
                                use ::nimbus_dsl::constant::{
                                    LiftedConst as _, NamedConst as _, PlainConst as _,
                                };
                                #[allow(clippy::needless_borrow)]
                                let value = (&&&::nimbus_dsl::constant::ConstProbe(#name, #p))
                                    .shader_value();
                                value
                            }
                        }
                    }
                }
            }
            Expr::Paren(p) => {
                let inner = self.expr(&p.expr)?;
                quote! { (#inner) }
            }
            Expr::Group(g) => self.expr(&g.expr)?,
            Expr::Reference(r) => self.expr(&r.expr)?,
            Expr::Unary(u) => {
                let inner = self.expr(&u.expr)?;
                match u.op {
                    UnOp::Deref(_) => inner,
                    UnOp::Neg(_) => quote! { (-#inner) },
                    UnOp::Not(_) => quote! { (!#inner) },
                    _ => return Err(unsupported(u, "this unary operator")),
                }
            }
            Expr::Binary(b) => self.binary(b)?,
            Expr::Assign(a) => {
                let target = self.mutable_target(&a.left)?;
                let value = self.expr(&a.right)?;
                let l = loc(a.span());
                quote! { #target.set(#l, #value) }
            }
            Expr::Cast(c) => {
                let inner = self.expr(&c.expr)?;
                let ty = &c.ty;
                quote! {
                    ::nimbus_dsl::ops::cast::<<#ty as ::nimbus_dsl::ShaderType>::Dsl, _>(#inner)
                }
            }
            Expr::Call(call) => self.call(call)?,
            Expr::MethodCall(m) => {
                let receiver = self.expr(&m.receiver)?;
                let args = m
                    .args
                    .iter()
                    .map(|a| self.expr(a))
                    .collect::<syn::Result<Vec<_>>>()?;
                let method = &m.method;
                let turbofish = &m.turbofish;
                quote! { #receiver.#method #turbofish (#(#args),*) }
            }
            Expr::Field(f) => {
                let base = self.expr(&f.base)?;
                let member = &f.member;
                quote! { #base.#member }
            }
            Expr::If(i) => self.if_expr(i)?,
            Expr::Block(b) => {
                if let Some(l) = &b.label {
                    return Err(unsupported(l, "a labelled block"));
                }
                if b.block.stmts.is_empty() {
                    quote! { () }
                } else {
                    self.block(&b.block)?
                }
            }
            Expr::ForLoop(f) => self.for_loop(f)?,
            Expr::Break(b) => {
                if let Some(label) = &b.label {
                    return Err(unsupported(label, "a labelled `break`"));
                }
                if let Some(v) = &b.expr {
                    return Err(unsupported(v, "`break` with a value"));
                }
                let l = loc(b.span());
                quote! { ::nimbus_dsl::control::brk(#l) }
            }
            Expr::Continue(c) => {
                if let Some(label) = &c.label {
                    return Err(unsupported(label, "a labelled `continue`"));
                }
                let l = loc(c.span());
                quote! { ::nimbus_dsl::control::cont(#l) }
            }
            Expr::Return(r) => {
                let l = loc(r.span());
                let Some(v) = &r.expr else {
                    return Err(unsupported(r, "a `return` without a value"));
                };
                let value = self.expr(v)?;
                quote! {{
                    ::nimbus_dsl::control::ret::<__Ret>(#l, ::core::convert::Into::<__Ret>::into(#value));
                    ::nimbus_dsl::control::unreachable::<__Ret>()
                }}
            }
            Expr::Match(m) => {
                // Only generation-time values can be matched: a DSL value has no patterns, so
                // rustc rejects a match on one.
                let scrutinee = self.expr(&m.expr)?;
                let mut arms = Vec::new();
                for arm in &m.arms {
                    if let Some((_, guard)) = &arm.guard {
                        return Err(unsupported(guard, "a match guard"));
                    }
                    let pat = &arm.pat;
                    self.scopes.push(HashMap::new());
                    let body = self.expr(&arm.body);
                    self.scopes.pop();
                    let body = body?;
                    arms.push(quote! { #pat => #body, });
                }
                quote! { match #scrutinee { #(#arms)* } }
            }
            Expr::While(w) => {
                return Err(syn::Error::new_spanned(
                    w.while_token,
                    "`while` loops are not supported in a #[shader_fn]: every shader loop needs a bound, write `for i in 0..N` with `break`",
                ));
            }
            Expr::Loop(l) => {
                return Err(syn::Error::new_spanned(
                    l.loop_token,
                    "`loop` is not supported in a #[shader_fn]: every shader loop needs a bound, write `for i in 0..N` with `break`",
                ));
            }
            Expr::Closure(c) => return Err(unsupported(c, "a closure")),
            Expr::Tuple(t) => return Err(unsupported(t, "a tuple")),
            Expr::Array(a) => return Err(unsupported(a, "an array")),
            Expr::Index(i) => {
                let base = self.expr(&i.expr)?;
                // Rust indexes with `usize`, the shader with `u32`: `a[i as usize]` on the CPU is
                // `a[i]` in the shader.
                let index = match &*i.index {
                    Expr::Cast(c) if matches!(&*c.ty, syn::Type::Path(t) if t.path.is_ident("usize")) => {
                        self.expr(&c.expr)?
                    }
                    other => self.expr(other)?,
                };
                quote! { ::nimbus_dsl::ops::index(#base, #index) }
            }
            Expr::Struct(st) => {
                if let Some(rest) = &st.rest {
                    return Err(unsupported(rest, "`..` in a struct literal"));
                }
                if st.qself.is_some() {
                    return Err(unsupported(st, "a qualified struct path"));
                }
                let path = &st.path;
                let mut sets = Vec::new();
                for field in &st.fields {
                    let member = &field.member;
                    let value = self.expr(&field.expr)?;
                    sets.push(quote! { __s.#member = ::core::convert::Into::into(#value); });
                }
                quote! {{
                    let mut __s = <#path as ::nimbus_dsl::ShaderType>::Dsl::__uninit();
                    #(#sets)*
                    __s.__finish()
                }}
            }
            Expr::Try(t) => return Err(unsupported(t, "the `?` operator")),
            Expr::Macro(m) => return Err(unsupported(m, "a macro call")),
            Expr::Range(r) => return Err(unsupported(r, "a range outside a `for` loop")),
            Expr::Let(l) => return Err(unsupported(l, "`if let`")),
            Expr::Unsafe(u) => return Err(unsupported(u, "an `unsafe` block")),
            other => return Err(unsupported(other, "this expression")),
        })
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> syn::Result<TokenStream> {
        let compound = match b.op {
            BinOp::AddAssign(_) => Some(quote! { + }),
            BinOp::SubAssign(_) => Some(quote! { - }),
            BinOp::MulAssign(_) => Some(quote! { * }),
            BinOp::DivAssign(_) => Some(quote! { / }),
            BinOp::RemAssign(_) => Some(quote! { % }),
            BinOp::BitAndAssign(_) => Some(quote! { & }),
            BinOp::BitOrAssign(_) => Some(quote! { | }),
            BinOp::BitXorAssign(_) => Some(quote! { ^ }),
            BinOp::ShlAssign(_) => Some(quote! { << }),
            BinOp::ShrAssign(_) => Some(quote! { >> }),
            _ => None,
        };
        if let Some(op) = compound {
            let target = self.mutable_target(&b.left)?;
            let value = self.expr(&b.right)?;
            let l = loc(b.span());
            return Ok(quote! { #target.set(#l, #target.get() #op (#value)) });
        }
        let l = self.expr(&b.left)?;
        let r = self.expr(&b.right)?;
        let func = match b.op {
            BinOp::Lt(_) => Some(quote! { lt }),
            BinOp::Le(_) => Some(quote! { le }),
            BinOp::Gt(_) => Some(quote! { gt }),
            BinOp::Ge(_) => Some(quote! { ge }),
            BinOp::Eq(_) => Some(quote! { eq }),
            BinOp::Ne(_) => Some(quote! { ne }),
            BinOp::And(_) => Some(quote! { and }),
            BinOp::Or(_) => Some(quote! { or }),
            _ => None,
        };
        Ok(match func {
            Some(f) => quote! { ::nimbus_dsl::ops::#f(#l, #r) },
            None => {
                let op = &b.op;
                quote! { (#l #op #r) }
            }
        })
    }

    fn call(&mut self, call: &syn::ExprCall) -> syn::Result<TokenStream> {
        let args = call
            .args
            .iter()
            .map(|a| self.expr(a))
            .collect::<syn::Result<Vec<_>>>()?;
        let Expr::Path(p) = &*call.func else {
            return Err(unsupported(&call.func, "calling a computed function value"));
        };
        if p.qself.is_some() {
            return Err(unsupported(p, "a qualified path call"));
        }
        // Resolved by declaration (see `nimbus_dsl::twin`): a single name's twin is the module
        // of that name, a path's is `__shader_twin_<last>` beside it, whether the path names a
        // module or a type. rustc resolves either; a function without a twin fails at this call.
        let mut path = p.path.clone();
        if path.segments.len() == 1 {
            return Ok(quote! { #path::shader(#(#args),*) });
        }
        if let Some(last) = path.segments.last_mut() {
            last.ident =
                syn::Ident::new(&format!("__shader_twin_{}", last.ident), last.ident.span());
        }
        Ok(quote! { #path(#(#args),*) })
    }

    fn if_expr(&mut self, i: &syn::ExprIf) -> syn::Result<TokenStream> {
        let cond = self.expr(&i.cond)?;
        let then = self.block(&i.then_branch)?;
        let otherwise = match &i.else_branch {
            Some((_, e)) => self.expr(e)?,
            None => quote! { () },
        };
        let l = loc(i.span());
        Ok(quote! {
            ::nimbus_dsl::control::branch(#l, #cond, || #then, || #otherwise)
        })
    }

    fn for_loop(&mut self, f: &syn::ExprForLoop) -> syn::Result<TokenStream> {
        if let Some(label) = &f.label {
            return Err(unsupported(label, "a labelled loop"));
        }
        let Pat::Ident(pi) = &*f.pat else {
            return Err(unsupported(&f.pat, "a pattern other than a name in `for`"));
        };
        // `for i in unroll(a..b)`: the same range, its body recorded once per counter value;
        // `unroll_known(a..b)`: so where the bounds are known at generation, else a loop.
        let marker = |call: &syn::ExprCall, name: &str| {
            call.args.len() == 1 && matches!(&*call.func, Expr::Path(p) if p.path.is_ident(name))
        };
        let (unrolled, ranged) = match &*f.expr {
            Expr::Call(call) if marker(call, "unroll") => (Some(true), &call.args[0]),
            Expr::Call(call) if marker(call, "unroll_known") => (Some(false), &call.args[0]),
            other => (None, other),
        };
        let Expr::Range(range) = ranged else {
            return Err(syn::Error::new_spanned(
                &f.expr,
                "a #[shader_fn] `for` loop must iterate a range `start..end` (or `unroll(start..end)`)",
            ));
        };
        let (Some(start), Some(end)) = (&range.start, &range.end) else {
            return Err(syn::Error::new_spanned(
                range,
                "a #[shader_fn] `for` range needs both bounds (`start..end`)",
            ));
        };
        if let syn::RangeLimits::Closed(c) = range.limits {
            return Err(syn::Error::new_spanned(
                c,
                "use a half-open range `start..end` in a #[shader_fn] `for` loop",
            ));
        }
        let start = self.expr(start)?;
        let end = self.expr(end)?;
        let ident = &pi.ident;
        let name = ident.to_string();
        self.scopes.push(HashMap::new());
        self.declare(name.clone(), false);
        let body = self.block(&f.body);
        self.scopes.pop();
        let body = body?;
        let l = loc(f.span());
        Ok(if unrolled == Some(true) {
            quote! {
                ::nimbus_dsl::control::unrolled_range(#name, #l, (#start, #end), |#ident| { let _ = #body; })
            }
        } else if unrolled == Some(false) {
            quote! {
                ::nimbus_dsl::control::unrolled_range_if_known(#name, #l, (#start, #end), |#ident| { let _ = #body; })
            }
        } else {
            quote! {
                ::nimbus_dsl::control::for_range(#name, #l, (#start, #end), |#ident| { let _ = #body; })
            }
        })
    }
}
