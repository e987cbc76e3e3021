//! The C# twin of shader functions: host code for Unity, printed from the same recorded IR as
//! the shaders (as [`crate::js`] prints it for JavaScript hosts).
//!
//! Values map to Unity.Mathematics, whose types and functions are HLSL's (`float3`, `uint2`,
//! `float4x4` with columns as WGSL's, `math.lerp`, `math.frac`), so a printed function reads as
//! its shader and computes what it does in f32: scalars to `float`/`int`/`uint` (C#'s unchecked
//! integer arithmetic wraps as WGSL's does), structs to C# structs with the Rust field names.
//! Every built-in is called as `math.<name>` and every vector is built with `new`, so no local
//! of the function can hide one. Textures, samplers and bindings have no meaning on a host: a
//! function that reads one is refused, naming it.

use crate::wgsl::needs_parens;
use std::fmt::Write as _;

use nimbus_dsl::ir::{
    BinaryOp, Block, Builtin, ExprId, ExprKind, Function, GlobalKind, Literal, Module, Scalar,
    Stmt, StructDef, Type, UnaryOp,
};

use crate::error::CodegenError;
use crate::host_functions::reached;

/// C#'s keywords: an identifier spelled as one is written `@name`.
#[rustfmt::skip]
const KEYWORDS: &[&str] = &[
    "abstract", "as", "base", "bool", "break", "byte", "case", "catch", "char", "checked",
    "class", "const", "continue", "decimal", "default", "delegate", "do", "double", "else",
    "enum", "event", "explicit", "extern", "false", "finally", "fixed", "float", "for",
    "foreach", "goto", "if", "implicit", "in", "int", "interface", "internal", "is", "lock",
    "long", "namespace", "new", "null", "object", "operator", "out", "override", "params",
    "private", "protected", "public", "readonly", "ref", "return", "sbyte", "sealed", "short",
    "sizeof", "stackalloc", "static", "string", "struct", "switch", "this", "throw", "true",
    "try", "typeof", "uint", "ulong", "unchecked", "unsafe", "ushort", "using", "virtual",
    "void", "volatile", "while",
];

fn ident(name: &str) -> String {
    if KEYWORDS.contains(&name) {
        format!("@{name}")
    } else if name == "math" || name.starts_with("nimbus_") {
        // A local `math` would hide Unity.Mathematics' class; `nimbus_` names the helpers.
        format!("{name}_")
    } else {
        name.to_string()
    }
}

/// WGSL's integer division and remainder, which C# would throw on: `a / 0` is `a`, `a % 0` is
/// 0, and the most negative `i32` divided by -1 is itself (remainder 0). Printed into a class
/// that divides integers.
const INTEGER_DIVISION: &str =
    "        static uint nimbus_div(uint a, uint b) => b == 0u ? a : a / b;
        static uint nimbus_rem(uint a, uint b) => b == 0u ? 0u : a % b;
        static int nimbus_div(int a, int b) => b == 0 || (a == int.MinValue && b == -1) ? a : a / b;
        static int nimbus_rem(int a, int b) => b == 0 || (a == int.MinValue && b == -1) ? 0 : a % b;
";

fn scalar(s: Scalar) -> &'static str {
    match s {
        Scalar::F32 => "float",
        Scalar::I32 => "int",
        Scalar::U32 => "uint",
        Scalar::Bool => "bool",
    }
}

fn cs_type(ty: Type) -> Result<String, String> {
    Ok(match ty {
        Type::Scalar(s) => scalar(s).to_string(),
        Type::Vector(n, s) => format!("{}{n}", scalar(s)),
        Type::Matrix(n) => format!("float{n}x{n}"),
        Type::Struct(def) => ident(def.name),
        Type::Array(elem, _) => format!("{}[]", cs_type(*elem)?),
        other => return Err(format!("has a {other:?}, which a host does not")),
    })
}

fn literal(l: Literal) -> String {
    match l {
        Literal::F32(bits) => {
            let v = f32::from_bits(bits);
            if v.is_nan() {
                "float.NaN".into()
            } else if v.is_infinite() {
                if v > 0.0 {
                    "float.PositiveInfinity".into()
                } else {
                    "float.NegativeInfinity".into()
                }
            } else {
                format!("{}f", crate::wgsl::float_literal(v).unwrap_or_default())
            }
        }
        Literal::I32(i32::MIN) => "int.MinValue".into(),
        Literal::I32(v) => v.to_string(),
        Literal::U32(v) => format!("{v}u"),
        Literal::Bool(v) => v.to_string(),
    }
}

/// Unity.Mathematics' name of a built-in (`math.<name>`): HLSL's, as that library follows it;
/// it has no `pack4x8unorm`.
fn builtin(b: Builtin) -> Option<&'static str> {
    match b {
        Builtin::Pack4x8Unorm => None,
        _ => Some(crate::hlsl::hlsl_builtin(b)),
    }
}

/// Prints `exports` and every function they reach as a static C# class `class` in namespace
/// `Nimbus`, with the module's constants and the structs the functions use. An export may name
/// a constant (`TOP_ALTITUDE`): it is public.
pub fn print_csharp(
    module: &Module,
    exports: &[&str],
    class: &str,
) -> Result<String, CodegenError> {
    let needed = reached(module, exports)?;
    let refuse = |function: &str, reason: String| CodegenError::Host {
        function: function.to_string(),
        reason,
    };
    let mut out = String::from(
        "// Generated by Nimbus: the C# twins of shader functions, for Unity (Unity.Mathematics). \
         Do not edit: change the Rust source.\n",
    );
    for d in &module.doc {
        let _ = writeln!(out, "// {d}");
    }
    out.push_str("using Unity.Mathematics;\n\nnamespace Nimbus\n{\n");
    // The structs the printed functions take or return, each once.
    let mut structs: Vec<&'static StructDef> = Vec::new();
    for f in module.functions.iter().filter(|f| needed.contains(&f.name)) {
        let types = f
            .params
            .iter()
            .map(|p| p.ty)
            .chain(f.result)
            .chain(f.locals.iter().map(|l| l.ty))
            .chain(f.exprs.iter().map(|e| e.ty));
        for ty in types {
            collect_structs(ty, &mut structs);
        }
    }
    for def in &structs {
        for d in def.doc.lines() {
            let _ = writeln!(out, "    // {d}");
        }
        let _ = writeln!(out, "    public struct {}\n    {{", ident(def.name));
        for field in def.fields {
            for d in field.doc.lines() {
                let _ = writeln!(out, "        // {d}");
            }
            let ty = cs_type(field.ty).map_err(|e| refuse(def.name, e))?;
            let _ = writeln!(out, "        public {ty} {};", ident(field.name));
        }
        out.push_str("    }\n\n");
    }
    let _ = writeln!(out, "    public static class {class}\n    {{");
    let divides = module
        .functions
        .iter()
        .filter(|f| needed.contains(&f.name))
        .flat_map(|f| f.exprs.iter())
        .any(|e| integer_division(&e.kind, e.ty));
    if divides {
        out.push_str(INTEGER_DIVISION);
    }
    for g in &module.globals {
        if let GlobalKind::Const { value } = g.kind {
            let public = if exports.contains(&g.name.as_str()) {
                "public "
            } else {
                ""
            };
            let ty = cs_type(g.ty).map_err(|e| refuse(&g.name, e))?;
            let _ = writeln!(
                out,
                "        {public}const {ty} {} = {};",
                ident(&g.name),
                literal(value)
            );
        }
    }
    for f in module.functions.iter().filter(|f| needed.contains(&f.name)) {
        let mut p = Printer {
            module,
            f,
            out: String::new(),
            indent: 3,
        };
        p.block(&f.body)?;
        let public = if exports.contains(&f.name.as_str()) {
            "public "
        } else {
            ""
        };
        let params = f
            .params
            .iter()
            .map(|p| Ok(format!("{} {}", cs_type(p.ty)?, ident(&p.name))))
            .collect::<Result<Vec<_>, String>>()
            .map_err(|e| refuse(&f.name, e))?;
        let result = match f.result {
            Some(t) => cs_type(t).map_err(|e| refuse(&f.name, e))?,
            None => "void".to_string(),
        };
        out.push('\n');
        for d in &f.doc {
            let _ = writeln!(out, "        // {d}");
        }
        let _ = writeln!(
            out,
            "        {public}static {result} {}({})\n        {{\n{}        }}",
            ident(&f.name),
            params.join(", "),
            p.out
        );
    }
    out.push_str("    }\n}\n");
    Ok(out)
}

/// `ty`'s struct, and the structs its fields hold, each once, inner ones first.
fn collect_structs(ty: Type, out: &mut Vec<&'static StructDef>) {
    match ty {
        Type::Struct(def) if !out.iter().any(|s| std::ptr::eq(*s, def)) => {
            for f in def.fields {
                collect_structs(f.ty, out);
            }
            out.push(def);
        }
        Type::Array(elem, _) => collect_structs(*elem, out),
        _ => {}
    }
}

/// Whether an expression divides or takes the remainder of scalar integers.
fn integer_division(kind: &ExprKind, ty: Type) -> bool {
    matches!(kind, ExprKind::Binary(BinaryOp::Div | BinaryOp::Rem, ..))
        && matches!(ty, Type::Scalar(Scalar::I32 | Scalar::U32))
}

struct Printer<'a> {
    module: &'a Module,
    f: &'a Function,
    out: String,
    indent: usize,
}

impl Printer<'_> {
    fn refuse(&self, reason: impl Into<String>) -> CodegenError {
        CodegenError::Host {
            function: self.f.name.clone(),
            reason: reason.into(),
        }
    }

    fn ty(&self, ty: Type) -> Result<String, CodegenError> {
        cs_type(ty).map_err(|e| self.refuse(e))
    }

    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn block(&mut self, block: &Block) -> Result<(), CodegenError> {
        for stmt in block {
            self.stmt(stmt)?;
            if stmt.diverges() {
                break;
            }
        }
        Ok(())
    }

    fn nested(&mut self, block: &Block) -> Result<(), CodegenError> {
        self.indent += 1;
        self.block(block)?;
        self.indent -= 1;
        Ok(())
    }

    fn stmt(&mut self, stmt: &Stmt) -> Result<(), CodegenError> {
        let f = self.f;
        match stmt {
            Stmt::Let { local, value, .. }
            | Stmt::Var {
                local,
                init: Some(value),
                ..
            } => {
                let l = f.local(*local);
                let v = self.expr(*value)?;
                let ty = self.ty(l.ty)?;
                self.line(&format!("{ty} {} = {v};", ident(&l.name)));
            }
            Stmt::Var {
                local, init: None, ..
            } => {
                let l = f.local(*local);
                let ty = self.ty(l.ty)?;
                self.line(&format!("{ty} {} = default({ty});", ident(&l.name)));
            }
            Stmt::Assign { local, value, .. } => {
                let v = self.expr(*value)?;
                self.line(&format!("{} = {v};", ident(&f.local(*local).name)));
            }
            Stmt::Store { .. } => return Err(self.refuse("writes a storage buffer")),
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                let c = self.expr(*cond)?;
                self.line(&format!("if ({c})"));
                self.line("{");
                self.nested(then)?;
                self.line("}");
                if !otherwise.is_empty() {
                    self.line("else");
                    self.line("{");
                    self.nested(otherwise)?;
                    self.line("}");
                }
            }
            Stmt::For {
                counter,
                start,
                end,
                body,
                ..
            } => {
                let l = f.local(*counter);
                let (n, ty) = (ident(&l.name), self.ty(l.ty)?);
                let (a, b) = (self.expr(*start)?, self.expr(*end)?);
                self.line(&format!("for ({ty} {n} = {a}; {n} < {b}; {n}++)"));
                self.line("{");
                self.nested(body)?;
                self.line("}");
            }
            Stmt::Break { .. } => self.line("break;"),
            Stmt::Continue { .. } => self.line("continue;"),
            Stmt::Return { value, .. } => match value {
                Some(v) => {
                    let v = self.expr(*v)?;
                    self.line(&format!("return {v};"));
                }
                None => self.line("return;"),
            },
        }
        Ok(())
    }

    fn args(&mut self, args: &[ExprId]) -> Result<String, CodegenError> {
        let v: Result<Vec<String>, CodegenError> = args.iter().map(|a| self.expr(*a)).collect();
        Ok(v?.join(", "))
    }

    fn operand(
        &mut self,
        id: ExprId,
        parent: BinaryOp,
        right: bool,
    ) -> Result<String, CodegenError> {
        let s = self.expr(id)?;
        Ok(match self.f.expr(id).kind {
            ExprKind::Binary(op, ..) if needs_parens(parent, op, right) => format!("({s})"),
            ExprKind::Select { .. } => format!("({s})"),
            _ => s,
        })
    }

    fn postfix_base(&mut self, id: ExprId) -> Result<String, CodegenError> {
        let s = self.expr(id)?;
        Ok(match self.f.expr(id).kind {
            ExprKind::Binary(..) | ExprKind::Unary(..) | ExprKind::Convert(..) => format!("({s})"),
            _ => s,
        })
    }

    fn expr(&mut self, id: ExprId) -> Result<String, CodegenError> {
        let f = self.f;
        let e = f.expr(id);
        Ok(match &e.kind {
            ExprKind::Literal(l) => literal(*l),
            ExprKind::Arg(i) => ident(&f.params[*i as usize].name),
            ExprKind::Local(l) => ident(&f.local(*l).name),
            ExprKind::Global(g) => {
                let global = &self.module.globals[g.0 as usize];
                match global.kind {
                    GlobalKind::Const { .. } => ident(&global.name),
                    _ => {
                        return Err(self.refuse(format!(
                            "reads `{}`, a binding the host does not have",
                            global.name
                        )));
                    }
                }
            }
            ExprKind::Unary(op, a) => {
                let inner = match f.expr(*a).kind {
                    // `--1.0f` would be a decrement.
                    ExprKind::Literal(Literal::F32(b)) if f32::from_bits(b).is_sign_negative() => {
                        format!("({})", self.expr(*a)?)
                    }
                    ExprKind::Literal(Literal::I32(v)) if v < 0 => format!("({})", self.expr(*a)?),
                    _ => self.postfix_base(*a)?,
                };
                match op {
                    UnaryOp::Neg => format!("-{inner}"),
                    UnaryOp::Not => format!("!{inner}"),
                }
            }
            ExprKind::Binary(op, a, b) => {
                let (ta, tb) = (f.expr(*a).ty, f.expr(*b).ty);
                let product = *op == BinaryOp::Mul
                    && (matches!(ta, Type::Matrix(_)) && !matches!(tb, Type::Scalar(_))
                        || matches!(tb, Type::Matrix(_)) && !matches!(ta, Type::Scalar(_)));
                if product {
                    format!("math.mul({}, {})", self.expr(*a)?, self.expr(*b)?)
                } else if matches!(op, BinaryOp::Shl | BinaryOp::Shr) {
                    // C# shifts by an `int` count; WGSL's is unsigned.
                    let l = self.operand(*a, *op, false)?;
                    let r = self.expr(*b)?;
                    let count = match tb {
                        Type::Vector(n, _) => format!("(int{n})({r})"),
                        _ => format!("(int)({r})"),
                    };
                    let sym = if *op == BinaryOp::Shl { "<<" } else { ">>" };
                    format!("{l} {sym} {count}")
                } else if integer_division(&e.kind, e.ty) {
                    let helper = if *op == BinaryOp::Div {
                        "nimbus_div"
                    } else {
                        "nimbus_rem"
                    };
                    format!("{helper}({}, {})", self.expr(*a)?, self.expr(*b)?)
                } else {
                    let l = self.operand(*a, *op, false)?;
                    let r = self.operand(*b, *op, true)?;
                    format!("{l} {} {r}", crate::wgsl_spelling::wgsl_operator(*op))
                }
            }
            ExprKind::Builtin(Builtin::Select, args) if args.len() == 3 => {
                self.select(args[0], args[1], args[2])?
            }
            ExprKind::Builtin(b, args) => {
                let Some(name) = builtin(*b) else {
                    return Err(self.refuse("packs texels (pack4x8unorm)"));
                };
                format!("math.{name}({})", self.args(args)?)
            }
            ExprKind::Call(name, args) => format!("{}({})", ident(name), self.args(args)?),
            ExprKind::Construct(ty, args) => match ty {
                Type::Struct(def) => {
                    let mut fields = Vec::new();
                    for (field, a) in def.fields.iter().zip(args) {
                        fields.push(format!("{} = {}", ident(field.name), self.expr(*a)?));
                    }
                    format!("new {} {{ {} }}", ident(def.name), fields.join(", "))
                }
                Type::Array(elem, _) => {
                    format!("new {}[] {{ {} }}", self.ty(**elem)?, self.args(args)?)
                }
                _ => format!("new {}({})", self.ty(*ty)?, self.args(args)?),
            },
            ExprKind::Swizzle(v, idx) => {
                let base = self.postfix_base(*v)?;
                let s: String = idx
                    .iter()
                    .map(|i| ['x', 'y', 'z', 'w'][*i as usize])
                    .collect();
                format!("{base}.{s}")
            }
            ExprKind::Member(v, i) => {
                let base = self.postfix_base(*v)?;
                let Type::Struct(def) = f.expr(*v).ty else {
                    return Err(self.refuse("reads a member of a non-struct"));
                };
                format!("{base}.{}", ident(def.fields[*i as usize].name))
            }
            ExprKind::Index(a, i) => {
                let base = self.postfix_base(*a)?;
                format!("{base}[(int)({})]", self.expr(*i)?)
            }
            ExprKind::Convert(to, a) => self.convert(*to, *a, e.ty)?,
            ExprKind::Bitcast(to, a) => {
                let func = crate::hlsl::hlsl_bitcast(*to);
                format!("math.{func}({})", self.expr(*a)?)
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => self.select(*if_false, *if_true, *cond)?,
            ExprKind::Sample { .. } | ExprKind::Load { .. } => {
                return Err(self.refuse("reads a texture"));
            }
        })
    }

    /// WGSL's `select(f, t, c)`: `c ? t : f` on a scalar condition, `math.select` per component.
    fn select(
        &mut self,
        if_false: ExprId,
        if_true: ExprId,
        cond: ExprId,
    ) -> Result<String, CodegenError> {
        let (fa, t, c) = (self.expr(if_false)?, self.expr(if_true)?, self.expr(cond)?);
        Ok(if matches!(self.f.expr(cond).ty, Type::Scalar(_)) {
            format!("({c} ? {t} : {fa})")
        } else {
            format!("math.select({fa}, {t}, {c})")
        })
    }

    /// A value conversion: a cast, except to and from `bool`, which C# does not cast.
    fn convert(&mut self, to: Scalar, a: ExprId, ty: Type) -> Result<String, CodegenError> {
        let from = self.f.expr(a).ty.scalar();
        let inner = self.expr(a)?;
        let target = self.ty(ty)?;
        Ok(match (from, to, ty) {
            (Some(Scalar::Bool), _, Type::Scalar(_)) => {
                format!("({inner} ? ({target})1 : ({target})0)")
            }
            (Some(Scalar::Bool), _, _) => {
                format!("math.select(new {target}(0), new {target}(1), {inner})")
            }
            (_, Scalar::Bool, Type::Scalar(_)) => format!("(({inner}) != 0)"),
            // WGSL saturates a float converted to an integer (C#'s cast is unspecified out of
            // range): the limits are the largest floats inside each range.
            (Some(Scalar::F32), Scalar::U32, Type::Scalar(_)) => {
                format!("(uint)math.clamp({inner}, 0.0f, 4294967040.0f)")
            }
            (Some(Scalar::F32), Scalar::I32, Type::Scalar(_)) => {
                format!("(int)math.clamp({inner}, -2147483648.0f, 2147483520.0f)")
            }
            (_, Scalar::Bool, _) => return Err(self.refuse("converts a vector to booleans")),
            _ => format!("({target})({inner})"),
        })
    }
}
