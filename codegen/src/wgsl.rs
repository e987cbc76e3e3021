//! The WGSL printer: the primary output people review, so it is written for reading.
//!
//! Names and doc comments come from the Rust source, expressions get only the parentheses WGSL
//! needs, formatting is fixed, and a span table maps every printed statement back to the
//! `#[shader_fn]` and Rust line it came from (see [`SpanTable`]).

use crate::wgsl_spelling::{wgsl_builtin, wgsl_operator, wgsl_type};
use std::fmt::Write as _;
use std::ops::Range;
use std::sync::Arc;

use nimbus_dsl::ir::{
    BinaryOp, Block, ExprId, ExprKind, Function, GlobalKind, Io, Literal, Module, SampleKind,
    SourceLoc, Stmt, Type, UnaryOp,
};

use crate::error::CodegenError;

/// Where one range of printed WGSL came from.
#[derive(Clone, Debug, PartialEq)]
pub struct SpanEntry {
    pub range: Range<usize>,
    /// WGSL name of the function (or `<module>` for declarations). Shared by every statement
    /// of the function: an entry per statement, two strings copied for each, had been a
    /// tenth of the print.
    pub function: Arc<str>,
    /// Rust name of the `#[shader_fn]` (or entry point).
    pub rust_name: Arc<str>,
    pub loc: SourceLoc,
}

/// Printed-byte-range → source table for one printed module.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpanTable {
    entries: Vec<SpanEntry>,
}

impl SpanTable {
    /// The innermost entry containing byte `offset`.
    pub fn lookup(&self, offset: usize) -> Option<&SpanEntry> {
        self.entries
            .iter()
            .filter(|e| e.range.start <= offset && offset < e.range.end.max(e.range.start + 1))
            .min_by_key(|e| e.range.end - e.range.start)
    }

    /// The entry of a whole function by WGSL name.
    pub fn function(&self, name: &str) -> Option<&SpanEntry> {
        self.entries
            .iter()
            .filter(|e| &*e.function == name)
            .max_by_key(|e| e.range.end - e.range.start)
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// Operator precedence classes (WGSL forbids mixing some of them without parentheses).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Prec {
    Or = 1,
    And = 2,
    Bitwise = 3,
    Relational = 4,
    Shift = 5,
    Additive = 6,
    Multiplicative = 7,
}

fn prec(op: BinaryOp) -> Prec {
    match op {
        BinaryOp::Or => Prec::Or,
        BinaryOp::And => Prec::And,
        BinaryOp::BitAnd | BinaryOp::BitOr | BinaryOp::BitXor => Prec::Bitwise,
        BinaryOp::Shl | BinaryOp::Shr => Prec::Shift,
        BinaryOp::Add | BinaryOp::Sub => Prec::Additive,
        BinaryOp::Mul | BinaryOp::Div | BinaryOp::Rem => Prec::Multiplicative,
        _ => Prec::Relational,
    }
}

/// Whether `id` prints a `<` comparison outside any parentheses or brackets of its own, which a
/// later `>` in the same argument list would close as a template list.
fn opens_template(f: &Function, id: ExprId) -> bool {
    match f.expr(id).kind {
        ExprKind::Binary(BinaryOp::Lt, ..) => true,
        ExprKind::Binary(op, a, b) => {
            let bare = |child: ExprId, right: bool| match f.expr(child).kind {
                ExprKind::Binary(c, ..) if needs_parens(op, c, right) => false,
                _ => opens_template(f, child),
            };
            bare(a, false) || bare(b, true)
        }
        _ => false,
    }
}

/// Whether a binary child needs parentheses under parent `op` (on the right when `right`).
pub(crate) fn needs_parens(parent: BinaryOp, child: BinaryOp, right: bool) -> bool {
    let (p, c) = (prec(parent), prec(child));
    match p {
        Prec::Additive | Prec::Multiplicative => c < p || (right && c == p),
        // Shift and bitwise operands are unary expressions in WGSL's grammar; bitwise chains of
        // the same operator are allowed on the left.
        Prec::Shift => true,
        Prec::Bitwise => parent != child || right,
        Prec::Relational => c <= Prec::Relational,
        Prec::And | Prec::Or => {
            if c >= Prec::Relational {
                false
            } else {
                parent != child || right
            }
        }
    }
}

/// WGSL's attribute for an entry point's parameter or result.
fn io_attribute(io: Io) -> String {
    match io {
        Io::Position => "@builtin(position)".to_string(),
        Io::VertexIndex => "@builtin(vertex_index)".to_string(),
        Io::GlobalInvocationId => "@builtin(global_invocation_id)".to_string(),
        Io::Location(n) => format!("@location({n})"),
    }
}

pub(crate) fn float_literal(v: f32) -> Option<String> {
    if !v.is_finite() {
        return None;
    }
    let s = format!("{v:?}");
    // `{:?}` prints the shortest string that round-trips in f32 ("0.75", "1e-6", "6400000.0").
    Some(if s.contains(['.', 'e']) {
        s
    } else {
        format!("{s}.0")
    })
}

fn literal(l: Literal) -> Option<String> {
    Some(match l {
        Literal::F32(bits) => return float_literal(f32::from_bits(bits)),
        Literal::I32(i32::MIN) => "i32(-2147483647 - 1)".to_string(),
        Literal::I32(v) => format!("{v}i"),
        Literal::U32(v) => format!("{v}u"),
        Literal::Bool(v) => v.to_string(),
    })
}

const SWIZZLE: [char; 4] = ['x', 'y', 'z', 'w'];

struct Printer<'m> {
    module: &'m Module,
    out: String,
    spans: Vec<SpanEntry>,
    indent: usize,
    /// The WGSL and Rust names of the function being printed, for its spans.
    names: (Arc<str>, Arc<str>),
}

/// Prints a specialised module as WGSL, with its span table.
pub fn print_module(module: &Module, variant: &str) -> Result<(String, SpanTable), CodegenError> {
    let mut p = Printer {
        module,
        out: String::new(),
        spans: Vec::new(),
        indent: 0,
        names: (Arc::from(""), Arc::from("")),
    };
    p.module_header(variant);
    for s in &module.structs {
        p.struct_decl(s);
    }
    p.globals();
    for f in &module.functions {
        p.function(f)?;
    }
    // One trailing newline, no trailing blank line.
    while p.out.ends_with("\n\n") {
        p.out.pop();
    }
    Ok((p.out, SpanTable { entries: p.spans }))
}

impl Printer<'_> {
    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn module_header(&mut self, variant: &str) {
        let m = self.module;
        self.line(&format!(
            "// Generated by Nimbus from module `{}`, key `{variant}`. Do not edit: change the Rust source.",
            m.name
        ));
        for d in &m.doc {
            self.line(format!("// {d}").trim_end());
        }
        self.out.push('\n');
    }

    fn doc(&mut self, doc: &str) {
        for d in doc.lines() {
            self.line(format!("/// {d}").trim_end());
        }
    }

    fn struct_decl(&mut self, s: &nimbus_dsl::ir::StructDef) {
        self.doc(s.doc);
        self.line(&format!("struct {} {{", s.name));
        self.indent += 1;
        for f in s.fields {
            self.doc(f.doc);
            self.line(&format!("{}: {},", f.name, wgsl_type(f.ty)));
        }
        self.indent -= 1;
        self.line("}");
        self.out.push('\n');
    }

    fn globals(&mut self) {
        let m = self.module;
        if m.globals.is_empty() {
            return;
        }
        let order = crate::lower::declaration_order(m)
            .into_iter()
            .map(|i| &m.globals[i]);
        for g in order {
            self.doc(&g.doc);
            let decl = match &g.kind {
                GlobalKind::Uniform { group, binding } => format!(
                    "@group({group}) @binding({binding}) var<uniform> {}: {};",
                    g.name,
                    wgsl_type(g.ty)
                ),
                GlobalKind::Storage {
                    group,
                    binding,
                    read_write,
                } => format!(
                    "@group({group}) @binding({binding}) var<storage, {}> {}: {};",
                    if *read_write { "read_write" } else { "read" },
                    g.name,
                    wgsl_type(g.ty)
                ),
                GlobalKind::Handle { group, binding } => format!(
                    "@group({group}) @binding({binding}) var {}: {};",
                    g.name,
                    wgsl_type(g.ty)
                ),
                GlobalKind::Override { default } => format!(
                    "override {}: {} = {};",
                    g.name,
                    wgsl_type(g.ty),
                    literal(*default).unwrap_or_else(|| "0.0".into())
                ),
                GlobalKind::Const { value } => format!(
                    "const {}: {} = {};",
                    g.name,
                    wgsl_type(g.ty),
                    literal(*value).unwrap_or_else(|| "0.0".into())
                ),
                GlobalKind::Private => format!("var<private> {}: {};", g.name, wgsl_type(g.ty)),
            };
            self.line(&decl);
        }
        self.out.push('\n');
    }

    fn function(&mut self, f: &Function) -> Result<(), CodegenError> {
        let start = self.out.len();
        self.names = (Arc::from(f.name.as_str()), Arc::from(f.rust_name.as_str()));
        let entry = self.module.entry_point(&f.name);
        for d in &f.doc {
            self.line(format!("/// {d}").trim_end());
        }
        // The file but not the line: a line number would churn every snapshot on unrelated edits.
        let mut origin = format!("// nimbus: `{}` from {}", f.rust_name, f.loc.file);
        if !f.specialised.is_empty() {
            let _ = write!(origin, ", specialised for {}", f.specialised.join(", "));
        }
        self.line(&origin);
        let params: Vec<String> = f
            .params
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let attr = entry
                    .and_then(|e| e.inputs.get(i))
                    .map(|a| format!("{} ", io_attribute(*a)))
                    .unwrap_or_default();
                format!("{attr}{}: {}", p.name, wgsl_type(p.ty))
            })
            .collect();
        let result = match (f.result, entry.and_then(|e| e.output)) {
            (Some(t), Some(io)) => format!(" -> {} {}", io_attribute(io), wgsl_type(t)),
            (Some(t), None) => format!(" -> {}", wgsl_type(t)),
            (None, _) => String::new(),
        };
        if let Some(e) = entry {
            let stage = e.stage.name();
            if e.stage == nimbus_dsl::ir::Stage::Compute {
                let [x, y, z] = e.workgroup_size;
                self.line(&format!("@{stage} @workgroup_size({x}, {y}, {z})"));
            } else {
                self.line(&format!("@{stage}"));
            }
        }
        self.line(&format!("fn {}({}){result} {{", f.name, params.join(", ")));
        self.indent += 1;
        self.block(f, &f.body)?;
        self.indent -= 1;
        self.line("}");
        self.spans.push(SpanEntry {
            range: start..self.out.len(),
            function: self.names.0.clone(),
            rust_name: self.names.1.clone(),
            loc: f.loc,
        });
        self.out.push('\n');
        Ok(())
    }

    fn block(&mut self, f: &Function, block: &Block) -> Result<(), CodegenError> {
        for stmt in block {
            self.stmt(f, stmt)?;
            if stmt.diverges() {
                break;
            }
        }
        Ok(())
    }

    fn span(&mut self, start: usize, loc: SourceLoc) {
        self.spans.push(SpanEntry {
            range: start..self.out.len(),
            function: self.names.0.clone(),
            rust_name: self.names.1.clone(),
            loc,
        });
    }

    fn stmt(&mut self, f: &Function, stmt: &Stmt) -> Result<(), CodegenError> {
        let start = self.out.len();
        match stmt {
            Stmt::Let { local, value, .. } => {
                let v = self.expr(f, *value)?;
                self.line(&format!("let {} = {v};", f.local(*local).name));
            }
            Stmt::Var { local, init, .. } => {
                let l = f.local(*local);
                match init {
                    Some(i) => {
                        let v = self.expr(f, *i)?;
                        self.line(&format!("var {}: {} = {v};", l.name, wgsl_type(l.ty)));
                    }
                    None => self.line(&format!("var {}: {};", l.name, wgsl_type(l.ty))),
                }
            }
            Stmt::Assign { local, value, .. } => {
                let v = self.expr(f, *value)?;
                self.line(&format!("{} = {v};", f.local(*local).name));
            }
            Stmt::Store { target, value, .. } => {
                let t = self.expr(f, *target)?;
                let v = self.expr(f, *value)?;
                self.line(&format!("{t} = {v};"));
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                let c = self.expr(f, *cond)?;
                self.line(&format!("if {c} {{"));
                self.if_rest(f, then, otherwise)?;
            }
            Stmt::For {
                counter,
                start: from,
                end,
                body,
                ..
            } => {
                let l = f.local(*counter);
                let a = self.expr(f, *from)?;
                let b = self.expr(f, *end)?;
                let one = if l.ty == Type::I32 { "1i" } else { "1u" };
                self.line(&format!(
                    "for (var {n}: {t} = {a}; {n} < {b}; {n} += {one}) {{",
                    n = l.name,
                    t = wgsl_type(l.ty)
                ));
                self.indent += 1;
                self.block(f, body)?;
                self.indent -= 1;
                self.line("}");
            }
            Stmt::Break { .. } => self.line("break;"),
            Stmt::Continue { .. } => self.line("continue;"),
            Stmt::Return { value, .. } => match value {
                Some(v) => {
                    let v = self.expr(f, *v)?;
                    self.line(&format!("return {v};"));
                }
                None => self.line("return;"),
            },
        }
        self.span(start, stmt.loc());
        Ok(())
    }

    /// The arms of an `if` whose header line is printed; folds `else { if .. }` into `else if`.
    fn if_rest(
        &mut self,
        f: &Function,
        then: &Block,
        otherwise: &Block,
    ) -> Result<(), CodegenError> {
        self.indent += 1;
        self.block(f, then)?;
        self.indent -= 1;
        match otherwise.as_slice() {
            [] => self.line("}"),
            [
                Stmt::If {
                    cond,
                    then: t2,
                    otherwise: o2,
                    loc,
                },
            ] => {
                let start = self.out.len();
                let c = self.expr(f, *cond)?;
                self.line(&format!("}} else if {c} {{"));
                self.if_rest(f, t2, o2)?;
                self.span(start, *loc);
            }
            _ => {
                self.line("} else {");
                self.indent += 1;
                self.block(f, otherwise)?;
                self.indent -= 1;
                self.line("}");
            }
        }
        Ok(())
    }

    /// `id` printed as one expression (a statement's: one string per statement, not per node).
    fn expr(&mut self, f: &Function, id: ExprId) -> Result<String, CodegenError> {
        let mut out = String::new();
        self.write_expr(&mut out, f, id)?;
        Ok(out)
    }

    /// `id` in parentheses when `wrap` says so.
    fn write_wrapped(
        &self,
        out: &mut String,
        f: &Function,
        id: ExprId,
        wrap: bool,
    ) -> Result<(), CodegenError> {
        if wrap {
            out.push('(');
        }
        self.write_expr(out, f, id)?;
        if wrap {
            out.push(')');
        }
        Ok(())
    }

    /// An operand of `parent`, parenthesised where precedence needs it.
    fn write_operand(
        &self,
        out: &mut String,
        f: &Function,
        id: ExprId,
        parent: BinaryOp,
        right: bool,
    ) -> Result<(), CodegenError> {
        let wrap =
            matches!(f.expr(id).kind, ExprKind::Binary(op, ..) if needs_parens(parent, op, right));
        self.write_wrapped(out, f, id, wrap)
    }

    /// The base of a swizzle, member or index, parenthesised if it is an operation.
    fn write_postfix_base(
        &self,
        out: &mut String,
        f: &Function,
        id: ExprId,
    ) -> Result<(), CodegenError> {
        let wrap = matches!(f.expr(id).kind, ExprKind::Binary(..) | ExprKind::Unary(..));
        self.write_wrapped(out, f, id, wrap)
    }

    /// `name(args)`.
    fn write_call(
        &self,
        out: &mut String,
        f: &Function,
        name: &str,
        args: &[ExprId],
    ) -> Result<(), CodegenError> {
        out.push_str(name);
        out.push('(');
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            // WGSL reads `name < … , … >` as a template list: `select(a < b, a > c, s)` does
            // not parse. An argument before the last with a `<` of its own is parenthesised.
            self.write_wrapped(out, f, *a, i + 1 < args.len() && opens_template(f, *a))?;
        }
        out.push(')');
        Ok(())
    }

    fn write_expr(&self, out: &mut String, f: &Function, id: ExprId) -> Result<(), CodegenError> {
        let e = f.expr(id);
        match &e.kind {
            ExprKind::Literal(l) => {
                out.push_str(&literal(*l).ok_or_else(|| CodegenError::NonFiniteLiteral {
                    function: f.rust_name.clone(),
                    loc: f.loc,
                })?);
            }
            ExprKind::Arg(i) => out.push_str(&f.params[*i as usize].name),
            ExprKind::Local(l) => out.push_str(&f.local(*l).name),
            ExprKind::Global(g) => out.push_str(&self.module.globals[g.0 as usize].name),
            ExprKind::Unary(op, a) => {
                out.push_str(match op {
                    UnaryOp::Neg => "-",
                    UnaryOp::Not => "!",
                });
                let wrap = match f.expr(*a).kind {
                    ExprKind::Binary(..) | ExprKind::Unary(..) => true,
                    ExprKind::Literal(Literal::F32(b)) => f32::from_bits(b) < 0.0,
                    ExprKind::Literal(Literal::I32(v)) => v < 0,
                    _ => false,
                };
                self.write_wrapped(out, f, *a, wrap)?;
            }
            ExprKind::Binary(op, a, b) => {
                self.write_operand(out, f, *a, *op, false)?;
                out.push(' ');
                out.push_str(wgsl_operator(*op));
                out.push(' ');
                self.write_operand(out, f, *b, *op, true)?;
            }
            ExprKind::Builtin(b, args) => self.write_call(out, f, wgsl_builtin(*b), args)?,
            ExprKind::Call(name, args) => self.write_call(out, f, name, args)?,
            ExprKind::Construct(ty, args) => self.write_call(out, f, &wgsl_type(*ty), args)?,
            ExprKind::Swizzle(v, idx) => {
                self.write_postfix_base(out, f, *v)?;
                out.push('.');
                out.extend(idx.iter().map(|i| SWIZZLE[*i as usize]));
            }
            ExprKind::Member(v, i) => {
                self.write_postfix_base(out, f, *v)?;
                out.push('.');
                out.push_str(match f.expr(*v).ty {
                    Type::Struct(def) => def.fields[*i as usize].name,
                    _ => "?",
                });
            }
            ExprKind::Index(a, i) => {
                self.write_postfix_base(out, f, *a)?;
                out.push('[');
                self.write_expr(out, f, *i)?;
                out.push(']');
            }
            ExprKind::Convert(_, a) => self.write_call(out, f, &wgsl_type(e.ty), &[*a])?,
            ExprKind::Bitcast(_, a) => {
                out.push_str("bitcast<");
                out.push_str(&wgsl_type(e.ty));
                out.push('>');
                self.write_wrapped(out, f, *a, true)?;
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => self.write_call(out, f, "select", &[*if_false, *if_true, *cond])?,
            ExprKind::Sample {
                texture,
                sampler,
                coords,
                kind,
            } => match kind {
                SampleKind::Level(l) => self.write_call(
                    out,
                    f,
                    "textureSampleLevel",
                    &[*texture, *sampler, *coords, *l],
                )?,
                SampleKind::Implicit => {
                    self.write_call(out, f, "textureSample", &[*texture, *sampler, *coords])?
                }
            },
            ExprKind::Load {
                texture,
                texel,
                level,
            } => self.write_call(out, f, "textureLoad", &[*texture, *texel, *level])?,
        }
        Ok(())
    }
}
