//! The JavaScript twin of shader functions: host code for engines whose host is JavaScript
//! (three.js, WebGPU in a browser), printed from the same recorded IR as the shaders.
//!
//! What a host computes once per frame or when the sun moves (the sun's and sky's irradiance,
//! the shadow cascades) is a `#[shader_fn]` like any other; its CPU twin serves Nimbus's own
//! runtime, and this printer gives a JavaScript host the same function, so no formula is
//! written twice. Values map to plain JavaScript: scalars to numbers (`u32`/`i32` arithmetic
//! wraps as WGSL's does), vectors to arrays, matrices to arrays of column arrays, structs to
//! objects with the Rust field names, fixed-size arrays to arrays. Operations on vectors and
//! matrices go through a small prelude the module carries. Textures, samplers and bindings have
//! no meaning on a host: a function that reads one is refused, naming it.

use crate::wgsl_spelling::{wgsl_scalar, wgsl_type};
use std::collections::BTreeSet;
use std::fmt::Write as _;

use nimbus_dsl::ir::{
    BinaryOp, Block, Builtin, ExprId, ExprKind, Function, GlobalKind, Literal, Module, Scalar,
    Stmt, Type, UnaryOp,
};

use crate::error::CodegenError;

/// Helpers the printed functions call: element-wise arithmetic with scalar broadcast, the
/// built-ins on vectors, matrix products and WGSL's integer and conversion rules.
const PRELUDE: &str = r#"const nb = {
  map: (a, f) => (Array.isArray(a) ? a.map((x) => nb.map(x, f)) : f(a)),
  zip: (a, b, f) => {
    if (Array.isArray(a) && Array.isArray(b)) return a.map((x, i) => nb.zip(x, b[i], f));
    if (Array.isArray(a)) return a.map((x) => nb.zip(x, b, f));
    if (Array.isArray(b)) return b.map((y) => nb.zip(a, y, f));
    return f(a, b);
  },
  zip3: (a, b, c, f) => {
    const n = [a, b, c].find(Array.isArray);
    if (!n) return f(a, b, c);
    const at = (v, i) => (Array.isArray(v) ? v[i] : v);
    return n.map((_, i) => nb.zip3(at(a, i), at(b, i), at(c, i), f));
  },
  f32: Math.fround,
  u32: (x) => x >>> 0,
  i32: (x) => x | 0,
  toU32: (x) => (Number.isNaN(x) ? 0 : Math.min(Math.max(Math.trunc(x), 0), 4294967295)),
  toI32: (x) => (Number.isNaN(x) ? 0 : Math.min(Math.max(Math.trunc(x), -2147483648), 2147483647)),
  udiv: (a, b) => (b === 0 ? a : Math.trunc(a / b) >>> 0),
  idiv: (a, b) => (b === 0 ? a : Math.trunc(a / b) | 0),
  urem: (a, b) => (b === 0 ? 0 : (a % b) >>> 0),
  irem: (a, b) => (b === 0 ? 0 : (a % b) | 0),
  frem: (a, b) => a - b * Math.trunc(a / b),
  dot: (a, b) => a.reduce((s, x, i) => s + x * b[i], 0),
  length: (a) => Math.sqrt(nb.dot(a, a)),
  normalize: (a) => { const l = nb.length(a); return a.map((x) => x / l); },
  cross: (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]],
  clamp: (x, lo, hi) => Math.min(Math.max(x, lo), hi),
  mix: (a, b, t) => a + (b - a) * t,
  smoothstep: (e0, e1, x) => { const t = nb.clamp((x - e0) / (e1 - e0), 0, 1); return t * t * (3 - 2 * t); },
  step: (e, x) => (x < e ? 0 : 1),
  fract: (x) => x - Math.floor(x),
  sign: (x) => (x > 0 ? 1 : x < 0 ? -1 : 0),
  saturate: (x) => Math.min(Math.max(x, 0), 1),
  round: (x) => { const f = Math.floor(x); const d = x - f; return d < 0.5 ? f : d > 0.5 ? f + 1 : (f % 2 === 0 ? f : f + 1); },
  inverseSqrt: (x) => 1 / Math.sqrt(x),
  matVec: (m, v) => m[0].map((_, r) => m.reduce((s, col, c) => s + col[r] * v[c], 0)),
  vecMat: (v, m) => m.map((col) => nb.dot(v, col)),
  matMat: (a, b) => b.map((col) => nb.matVec(a, col)),
  bits: new DataView(new ArrayBuffer(4)),
  bitcast: (x, to) => {
    if (Array.isArray(x)) return x.map((y) => nb.bitcast(y, to));
    const v = nb.bits;
    if (Number.isInteger(x) && to === 'f32') { v.setUint32(0, x >>> 0); return v.getFloat32(0); }
    v.setFloat32(0, x);
    return to === 'u32' ? v.getUint32(0) : to === 'i32' ? v.getInt32(0) : x;
  },
};
"#;

/// Prints `exports` and every function and constant they reach as an ES module. An export
/// may also name a constant the module's functions read (`TOP_ALTITUDE`): it is exported as
/// the `const` it prints as.
pub fn print_js(module: &Module, exports: &[&str]) -> Result<String, CodegenError> {
    let by_name = |n: &str| module.functions.iter().find(|f| f.name == n);
    let is_const = |n: &str| {
        module
            .globals
            .iter()
            .any(|g| g.name == n && matches!(g.kind, GlobalKind::Const { .. }))
    };
    // Callees before callers: the order the recorder keeps; walk what the exports reach.
    let mut needed = BTreeSet::new();
    let mut stack: Vec<String> = exports
        .iter()
        .filter(|n| !is_const(n))
        .map(|s| s.to_string())
        .collect();
    while let Some(name) = stack.pop() {
        let Some(f) = by_name(&name) else {
            return Err(host_error(
                &name,
                "is neither a function nor a constant of the module",
            ));
        };
        if needed.insert(name.clone()) {
            for e in &f.exprs {
                if let ExprKind::Call(callee, _) = &e.kind {
                    stack.push(callee.clone());
                }
            }
        }
    }
    let mut out = String::from(
        "// Generated by Nimbus: the JavaScript twins of shader functions. Do not edit: change \
         the Rust source.\n",
    );
    out.push_str(PRELUDE);
    for g in &module.globals {
        if let GlobalKind::Const { value } = g.kind {
            let export = if exports.contains(&g.name.as_str()) {
                "export "
            } else {
                ""
            };
            let _ = writeln!(out, "{export}const {} = {};", g.name, literal(value));
        }
    }
    for f in &module.functions {
        if !needed.contains(&f.name) {
            continue;
        }
        let mut p = Printer {
            module,
            f,
            out: String::new(),
            indent: 1,
        };
        p.body(&f.body)?;
        let params: Vec<&str> = f.params.iter().map(|p| p.name.as_str()).collect();
        let export = if exports.contains(&f.name.as_str()) {
            "export "
        } else {
            ""
        };
        out.push('\n');
        for line in &f.doc {
            let _ = writeln!(out, "// {line}");
        }
        let _ = writeln!(
            out,
            "{export}function {}({}) {{\n{}}}",
            f.name,
            params.join(", "),
            p.out
        );
    }
    Ok(out)
}

fn host_error(function: &str, why: &str) -> CodegenError {
    CodegenError::Host {
        function: function.to_string(),
        reason: why.to_string(),
    }
}

fn literal(l: Literal) -> String {
    match l {
        Literal::F32(bits) => {
            let v = f32::from_bits(bits);
            if v.is_finite() {
                format!("{v:?}")
            } else if v.is_nan() {
                "NaN".into()
            } else if v > 0.0 {
                "Infinity".into()
            } else {
                "-Infinity".into()
            }
        }
        Literal::I32(v) => v.to_string(),
        Literal::U32(v) => v.to_string(),
        Literal::Bool(b) => b.to_string(),
    }
}

fn scalar_of(ty: Type) -> Option<Scalar> {
    match ty {
        Type::Scalar(s) | Type::Vector(_, s) => Some(s),
        _ => None,
    }
}

struct Printer<'a> {
    module: &'a Module,
    f: &'a Function,
    out: String,
    indent: usize,
}

impl Printer<'_> {
    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn body(&mut self, block: &Block) -> Result<(), CodegenError> {
        for stmt in block {
            self.stmt(stmt)?;
        }
        Ok(())
    }

    fn nested(&mut self, block: &Block) -> Result<(), CodegenError> {
        self.indent += 1;
        self.body(block)?;
        self.indent -= 1;
        Ok(())
    }

    fn stmt(&mut self, stmt: &Stmt) -> Result<(), CodegenError> {
        let f = self.f;
        match stmt {
            Stmt::Let { local, value, .. } => {
                let v = self.expr(*value)?;
                self.line(&format!("const {} = {v};", f.local(*local).name));
            }
            Stmt::Var { local, init, .. } => {
                let l = f.local(*local);
                let v = match init {
                    Some(i) => self.expr(*i)?,
                    None => zero(l.ty),
                };
                self.line(&format!("let {} = {v};", l.name));
            }
            Stmt::Assign { local, value, .. } => {
                let v = self.expr(*value)?;
                self.line(&format!("{} = {v};", f.local(*local).name));
            }
            Stmt::Store { .. } => {
                return Err(host_error(&f.name, "writes a storage buffer"));
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                let c = self.expr(*cond)?;
                self.line(&format!("if ({c}) {{"));
                self.nested(then)?;
                if otherwise.is_empty() {
                    self.line("}");
                } else {
                    self.line("} else {");
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
                let n = &f.local(*counter).name;
                let (a, b) = (self.expr(*start)?, self.expr(*end)?);
                self.line(&format!("for (let {n} = {a}; {n} < {b}; {n} += 1) {{"));
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

    fn args(&mut self, args: &[ExprId]) -> Result<Vec<String>, CodegenError> {
        args.iter().map(|a| self.expr(*a)).collect()
    }

    fn expr(&mut self, id: ExprId) -> Result<String, CodegenError> {
        let f = self.f;
        let e = f.expr(id);
        Ok(match &e.kind {
            ExprKind::Literal(l) => literal(*l),
            ExprKind::Arg(i) => f.params[*i as usize].name.clone(),
            ExprKind::Local(l) => f.local(*l).name.clone(),
            ExprKind::Global(g) => {
                let global = &self.module.globals[g.0 as usize];
                match global.kind {
                    GlobalKind::Const { .. } => global.name.clone(),
                    _ => {
                        return Err(host_error(
                            &f.name,
                            &format!("reads `{}`, a binding the host does not have", global.name),
                        ));
                    }
                }
            }
            ExprKind::Unary(op, a) => {
                let inner = self.expr(*a)?;
                match (op, f.expr(*a).ty) {
                    (UnaryOp::Neg, Type::Scalar(_)) => format!("(-{inner})"),
                    (UnaryOp::Neg, _) => format!("nb.map({inner}, (x) => -x)"),
                    (UnaryOp::Not, Type::Scalar(_)) => format!("(!{inner})"),
                    (UnaryOp::Not, _) => format!("nb.map({inner}, (x) => !x)"),
                }
            }
            ExprKind::Binary(op, a, b) => self.binary(*op, *a, *b, e.ty)?,
            ExprKind::Builtin(b, args) => self.builtin(*b, args)?,
            ExprKind::Call(name, args) => format!("{name}({})", self.args(args)?.join(", ")),
            ExprKind::Construct(ty, args) => {
                let a = self.args(args)?;
                match ty {
                    Type::Vector(n, _)
                        if args.len() == 1 && matches!(f.expr(args[0]).ty, Type::Scalar(_)) =>
                    {
                        format!("Array({n}).fill({})", a[0])
                    }
                    Type::Vector(..) => {
                        // Components and smaller vectors, flattened in order.
                        let parts: Vec<String> = args
                            .iter()
                            .zip(&a)
                            .map(|(id, s)| match f.expr(*id).ty {
                                Type::Vector(..) => format!("...{s}"),
                                _ => s.clone(),
                            })
                            .collect();
                        format!("[{}]", parts.join(", "))
                    }
                    Type::Matrix(_) | Type::Array(..) => format!("[{}]", a.join(", ")),
                    Type::Struct(def) => {
                        let fields: Vec<String> = def
                            .fields
                            .iter()
                            .zip(&a)
                            .map(|(field, v)| format!("{}: {v}", field.name))
                            .collect();
                        format!("{{ {} }}", fields.join(", "))
                    }
                    other => {
                        return Err(host_error(
                            &f.name,
                            &format!("constructs a {}", wgsl_type(*other)),
                        ));
                    }
                }
            }
            ExprKind::Swizzle(v, idx) => {
                let base = self.expr(*v)?;
                if idx.len() == 1 {
                    format!("{base}[{}]", idx[0])
                } else {
                    let comps: Vec<String> = idx.iter().map(|i| format!("v[{i}]")).collect();
                    format!("((v) => [{}])({base})", comps.join(", "))
                }
            }
            ExprKind::Member(v, i) => {
                let base = self.expr(*v)?;
                let name = match f.expr(*v).ty {
                    Type::Struct(def) => def.fields[*i as usize].name,
                    _ => return Err(host_error(&f.name, "reads a member of a non-struct")),
                };
                format!("{base}.{name}")
            }
            ExprKind::Index(a, i) => format!("{}[{}]", self.expr(*a)?, self.expr(*i)?),
            ExprKind::Convert(s, a) => {
                let inner = self.expr(*a)?;
                let from_float = scalar_of(f.expr(*a).ty) == Some(Scalar::F32);
                let conv = match (s, from_float) {
                    (Scalar::F32, _) => "(x) => Number(x)",
                    (Scalar::U32, true) => "nb.toU32",
                    (Scalar::U32, false) => "nb.u32",
                    (Scalar::I32, true) => "nb.toI32",
                    (Scalar::I32, false) => "nb.i32",
                    (Scalar::Bool, _) => "(x) => x !== 0",
                };
                format!("nb.map({inner}, {conv})")
            }
            ExprKind::Bitcast(s, a) => {
                format!("nb.bitcast({}, '{}')", self.expr(*a)?, wgsl_scalar(*s))
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => {
                let (fa, tr, c) = (
                    self.expr(*if_false)?,
                    self.expr(*if_true)?,
                    self.expr(*cond)?,
                );
                if matches!(f.expr(*cond).ty, Type::Scalar(_)) {
                    format!("({c} ? {tr} : {fa})")
                } else {
                    format!("nb.zip3({fa}, {tr}, {c}, (f, t, c) => (c ? t : f))")
                }
            }
            ExprKind::Sample { .. } | ExprKind::Load { .. } => {
                return Err(host_error(&f.name, "reads a texture"));
            }
        })
    }

    fn binary(
        &mut self,
        op: BinaryOp,
        a: ExprId,
        b: ExprId,
        ty: Type,
    ) -> Result<String, CodegenError> {
        let f = self.f;
        let (ta, tb) = (f.expr(a).ty, f.expr(b).ty);
        let (x, y) = (self.expr(a)?, self.expr(b)?);
        // Matrix products first: they are not element-wise.
        if op == BinaryOp::Mul {
            match (ta, tb) {
                (Type::Matrix(_), Type::Vector(..)) => return Ok(format!("nb.matVec({x}, {y})")),
                (Type::Vector(..), Type::Matrix(_)) => return Ok(format!("nb.vecMat({x}, {y})")),
                (Type::Matrix(_), Type::Matrix(_)) => return Ok(format!("nb.matMat({x}, {y})")),
                _ => {}
            }
        }
        let scalar = scalar_of(ty).or(scalar_of(ta)).unwrap_or(Scalar::F32);
        let both_scalar = matches!((ta, tb), (Type::Scalar(_), Type::Scalar(_)));
        let wrap = |e: String| match scalar {
            Scalar::U32 => format!("nb.u32({e})"),
            Scalar::I32 => format!("nb.i32({e})"),
            _ => e,
        };
        let operand_scalar = scalar_of(ta).unwrap_or(Scalar::F32);
        let js = |p: &str, q: &str| -> String {
            match op {
                BinaryOp::Add => wrap(format!("{p} + {q}")),
                BinaryOp::Sub => wrap(format!("{p} - {q}")),
                BinaryOp::Mul => match scalar {
                    Scalar::U32 => format!("nb.u32(Math.imul({p}, {q}))"),
                    Scalar::I32 => format!("Math.imul({p}, {q})"),
                    _ => format!("{p} * {q}"),
                },
                BinaryOp::Div => match scalar {
                    Scalar::U32 => format!("nb.udiv({p}, {q})"),
                    Scalar::I32 => format!("nb.idiv({p}, {q})"),
                    _ => format!("{p} / {q}"),
                },
                BinaryOp::Rem => match scalar {
                    Scalar::U32 => format!("nb.urem({p}, {q})"),
                    Scalar::I32 => format!("nb.irem({p}, {q})"),
                    _ => format!("nb.frem({p}, {q})"),
                },
                BinaryOp::Lt => format!("{p} < {q}"),
                BinaryOp::Le => format!("{p} <= {q}"),
                BinaryOp::Gt => format!("{p} > {q}"),
                BinaryOp::Ge => format!("{p} >= {q}"),
                BinaryOp::Eq => format!("{p} === {q}"),
                BinaryOp::Ne => format!("{p} !== {q}"),
                BinaryOp::And => format!("{p} && {q}"),
                BinaryOp::Or => format!("{p} || {q}"),
                BinaryOp::BitAnd => wrap(format!("{p} & {q}")),
                BinaryOp::BitOr => wrap(format!("{p} | {q}")),
                BinaryOp::BitXor => wrap(format!("{p} ^ {q}")),
                BinaryOp::Shl => wrap(format!("{p} << {q}")),
                BinaryOp::Shr => match operand_scalar {
                    Scalar::U32 => format!("({p} >>> {q})"),
                    _ => format!("({p} >> {q})"),
                },
            }
        };
        Ok(if both_scalar {
            format!("({})", js(&x, &y))
        } else {
            format!("nb.zip({x}, {y}, (p, q) => {})", js("p", "q"))
        })
    }

    fn builtin(&mut self, b: Builtin, args: &[ExprId]) -> Result<String, CodegenError> {
        let f = self.f;
        let a = self.args(args)?;
        let is_vec = |i: usize| matches!(f.expr(args[i]).ty, Type::Vector(..));
        // On scalars a built-in is a plain call; on vectors it maps over the components.
        let scalars = args
            .iter()
            .all(|id| matches!(f.expr(*id).ty, Type::Scalar(_)));
        let call = |name: &str, args: &[String]| {
            if name.starts_with('(') {
                format!("({name})({})", args.join(", "))
            } else {
                format!("{name}({})", args.join(", "))
            }
        };
        let unary = |name: &str| {
            if scalars {
                call(name, &a[..1])
            } else {
                format!("nb.map({}, {name})", a[0])
            }
        };
        let zip = |name: &str| {
            if scalars {
                call(name, &a[..2])
            } else {
                format!("nb.zip({}, {}, {name})", a[0], a[1])
            }
        };
        let zip3 = |name: &str| {
            if scalars {
                call(name, &a[..3])
            } else {
                format!("nb.zip3({}, {}, {}, {name})", a[0], a[1], a[2])
            }
        };
        Ok(match b {
            Builtin::Abs => unary("Math.abs"),
            Builtin::Ceil => unary("Math.ceil"),
            Builtin::Floor => unary("Math.floor"),
            Builtin::Trunc => unary("Math.trunc"),
            Builtin::Round => unary("nb.round"),
            Builtin::Fract => unary("nb.fract"),
            Builtin::Sign => unary("nb.sign"),
            Builtin::Sqrt => unary("Math.sqrt"),
            Builtin::InverseSqrt => unary("nb.inverseSqrt"),
            Builtin::Exp => unary("Math.exp"),
            Builtin::Exp2 => unary("(x) => 2 ** x"),
            Builtin::Log => unary("Math.log"),
            Builtin::Log2 => unary("Math.log2"),
            Builtin::Sin => unary("Math.sin"),
            Builtin::Cos => unary("Math.cos"),
            Builtin::Tan => unary("Math.tan"),
            Builtin::Asin => unary("Math.asin"),
            Builtin::Acos => unary("Math.acos"),
            Builtin::Atan => unary("Math.atan"),
            Builtin::Saturate => unary("nb.saturate"),
            Builtin::Atan2 => zip("Math.atan2"),
            Builtin::Pow => zip("Math.pow"),
            Builtin::Min => zip("Math.min"),
            Builtin::Max => zip("Math.max"),
            Builtin::Step => zip("nb.step"),
            Builtin::Clamp => zip3("nb.clamp"),
            Builtin::Mix => zip3("nb.mix"),
            Builtin::Smoothstep => zip3("nb.smoothstep"),
            Builtin::Fma => zip3("(x, y, z) => x * y + z"),
            Builtin::Select => zip3("(f, t, c) => (c ? t : f)"),
            Builtin::Dot => format!("nb.dot({}, {})", a[0], a[1]),
            Builtin::Cross => format!("nb.cross({}, {})", a[0], a[1]),
            Builtin::Length if is_vec(0) => format!("nb.length({})", a[0]),
            Builtin::Length => format!("Math.abs({})", a[0]),
            Builtin::Distance if is_vec(0) => {
                format!("nb.length(nb.zip({}, {}, (p, q) => p - q))", a[0], a[1])
            }
            Builtin::Distance => format!("Math.abs({} - {})", a[0], a[1]),
            Builtin::Normalize => format!("nb.normalize({})", a[0]),
            Builtin::Pack4x8Unorm => {
                return Err(host_error(&f.name, "packs texels (pack4x8unorm)"));
            }
        })
    }
}

/// The zero value of a type, for a `var` declared without a value.
fn zero(ty: Type) -> String {
    match ty {
        Type::Scalar(Scalar::Bool) => "false".into(),
        Type::Scalar(_) => "0".into(),
        Type::Vector(n, _) => format!("Array({n}).fill(0)"),
        Type::Matrix(n) => format!("Array.from({{ length: {n} }}, () => Array({n}).fill(0))"),
        Type::Array(elem, n) => format!("Array.from({{ length: {n} }}, () => {})", zero(*elem)),
        Type::Struct(def) => {
            let fields: Vec<String> = def
                .fields
                .iter()
                .map(|f| format!("{}: {}", f.name, zero(f.ty)))
                .collect();
            format!("{{ {} }}", fields.join(", "))
        }
        _ => "null".into(),
    }
}
