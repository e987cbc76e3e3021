//! The HLSL printer: one file per module holding every entry point, in Direct3D 11's binding
//! model, printed from the IR as the WGSL is.
//!
//! naga's HLSL back end targets wgpu's D3D12 model: samplers go through a heap indexed by a
//! buffer in register space 255, which neither Unity nor Direct3D 11 can fill, and it writes a
//! file per entry point that redefines the module's constants. This printer writes what an
//! engine's HLSL compiler takes as one program:
//! - every binding in a register of its class numbered as its WGSL binding (`b0` for the
//!   uniform block at binding 0, `t1` for the texture at binding 1, `s6` for the sampler at 6),
//!   so one number names a slot in every language, and glslang maps the file to the same
//!   Vulkan bindings as the package's SPIR-V; a group other than 0 adds `spaceN` (shader model
//!   5.1);
//! - a uniform block as `cbuffer <name> { <Type> <name>; }`, named as the manifest names it,
//!   each struct a block holds padded so that HLSL's packing puts every member at the WGSL
//!   offset the host writes (`_pad<offset>` members);
//! - matrices as the transpose HLSL's `row_major` storage reads WGSL's columns into (`m[i]`
//!   is column `i`), so `m * v` prints as `mul(v, m)`;
//! - overrides as `static const` of the key's values;
//! - each sampler named with its filter and wrap (`linear_sampler_linear_repeat`), the words
//!   Unity reads an inline sampler state from (a sampler no texture is named after);
//! - a struct built in an expression through a `make_<Struct>` function, which HLSL needs
//!   (its constructor syntax is for numeric types only);
//! - a `[shader("…")]` attribute per entry point for Slang, which finds entry points by it,
//!   under `#ifdef __SLANG__` (FXC and DXC do not read it).

use crate::wgsl::{float_literal, needs_parens};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use nimbus_dsl::ir::{
    AddressMode, BinaryOp, Block, Builtin, ExprId, ExprKind, FilterMode, Function, GlobalKind, Io,
    Literal, Module, SampleKind, SamplerDesc, Scalar, Stage, Stmt, StructDef, Type, UnaryOp,
};
use nimbus_dsl::layout::struct_layout;

use crate::error::CodegenError;
use crate::manifest::{BindingManifest, ManifestBinding, ManifestField, ManifestStruct};
use crate::wgsl_spelling::wgsl_type;

/// Keywords, types and intrinsics of HLSL (FXC, DXC) and Slang that a WGSL identifier may
/// spell: such a name gets a trailing `_`.
#[rustfmt::skip]
const RESERVED: &[&str] = &[
    // Keywords and storage classes.
    "AppendStructuredBuffer", "BlendState", "Buffer", "ByteAddressBuffer", "ComputeShader",
    "ConsumeStructuredBuffer", "DepthStencilState", "DepthStencilView", "DomainShader",
    "GeometryShader", "HullShader", "InputPatch", "LineStream", "NULL", "OutputPatch",
    "PixelShader", "PointStream", "RWBuffer", "RWByteAddressBuffer", "RWStructuredBuffer",
    "RWTexture1D", "RWTexture1DArray", "RWTexture2D", "RWTexture2DArray", "RWTexture3D",
    "RasterizerState", "RenderTargetView", "SamplerComparisonState", "SamplerState",
    "StructuredBuffer", "Texture1D", "Texture1DArray", "Texture2D", "Texture2DArray",
    "Texture2DMS", "Texture2DMSArray", "Texture3D", "TextureCube", "TextureCubeArray",
    "TriangleStream", "VertexShader", "asm", "asm_fragment", "associatedtype", "bool", "break",
    "case", "cbuffer", "centroid", "class", "column_major", "compile", "compile_fragment", "const",
    "continue", "default", "discard", "do", "double", "dword", "else", "export", "extension",
    "extern", "false", "float", "for", "func", "fxgroup", "groupshared", "half", "if", "import",
    "in", "inline", "inout", "int", "interface", "internal", "let", "line", "lineadj", "linear",
    "matrix", "min10float", "min12int", "min16float", "min16int", "min16uint", "module",
    "namespace", "nointerpolation", "noperspective", "out", "override", "packoffset", "pass",
    "pixelfragment", "point", "precise", "private", "property", "public", "register", "return",
    "row_major", "sample", "sampler", "shared", "snorm", "stateblock", "stateblock_state",
    "static", "string", "struct", "switch", "tbuffer", "technique", "technique10", "technique11",
    "texture", "this", "triangle", "triangleadj", "true", "typedef", "uint", "uniform", "unorm",
    "unsigned", "var", "vector", "vertexfragment", "void", "volatile", "where", "while",
    // Intrinsic functions (a function of the module by such a name would overload them).
    "abs", "acos", "all", "any", "asdouble", "asfloat", "asin", "asint", "asuint", "atan", "atan2",
    "ceil", "clamp", "clip", "cos", "cosh", "countbits", "cross", "ddx", "ddy", "degrees",
    "determinant", "distance", "dot", "dst", "exp", "exp2", "f16tof32", "f32tof16", "faceforward",
    "firstbithigh", "firstbitlow", "floor", "fma", "fmod", "frac", "frexp", "fwidth", "isfinite",
    "isinf", "isnan", "ldexp", "length", "lerp", "lit", "log", "log10", "log2", "mad", "max",
    "min", "modf", "mul", "noise", "normalize", "pow", "radians", "rcp", "reflect", "refract",
    "reversebits", "round", "rsqrt", "saturate", "sign", "sin", "sincos", "sinh", "smoothstep",
    "sqrt", "step", "tan", "tanh", "transpose", "trunc",
];

/// What a numeric type name of HLSL looks like (`float3`, `uint2x2`, `half4`): never taken.
fn numeric_type_name(name: &str) -> bool {
    let rest = ["float", "int", "uint", "bool", "half", "double", "dword"]
        .iter()
        .find_map(|p| name.strip_prefix(p));
    rest.is_some_and(|r| {
        let b = r.as_bytes();
        matches!(b, [n] if (b'1'..=b'4').contains(n))
            || matches!(b, [n, b'x', m] if (b'1'..=b'4').contains(n) && (b'1'..=b'4').contains(m))
    })
}

fn reserved(name: &str) -> bool {
    RESERVED.contains(&name) || numeric_type_name(name)
}

/// `float`, `int`, `uint`, `bool`.
pub fn hlsl_scalar(s: Scalar) -> &'static str {
    match s {
        Scalar::F32 => "float",
        Scalar::I32 => "int",
        Scalar::U32 => "uint",
        Scalar::Bool => "bool",
    }
}

/// The HLSL spelling of a value type (arrays are spelled at their declarator).
fn hlsl_type(ty: Type, names: &Names) -> String {
    match ty {
        Type::Scalar(s) => hlsl_scalar(s).to_string(),
        Type::Vector(n, s) => format!("{}{n}", hlsl_scalar(s)),
        Type::Matrix(n) => format!("float{n}x{n}"),
        Type::Struct(def) => names.get(def.name).to_string(),
        Type::Array(elem, _) => hlsl_type(*elem, names),
        Type::RuntimeArray(s) => hlsl_scalar(s).to_string(),
        Type::Texture2d => "Texture2D<float4>".to_string(),
        Type::Texture3d => "Texture3D<float4>".to_string(),
        Type::Sampler => "SamplerState".to_string(),
    }
}

/// `row_major ` for a matrix (or array of them) in memory: WGSL's columns are then the rows
/// `m[i]` reads, the transpose every product here is printed for.
fn major(ty: Type) -> &'static str {
    match ty {
        Type::Matrix(_) | Type::Array(Type::Matrix(_), _) => "row_major ",
        _ => "",
    }
}

/// `name` or `name[4]`, as a declarator of `ty`.
fn declarator(ty: Type, name: &str) -> String {
    match ty {
        Type::Array(_, n) => format!("{name}[{n}]"),
        _ => name.to_string(),
    }
}

/// HLSL's reinterpretation of bits as `to` (`asfloat`, `asint`, `asuint`).
pub(crate) fn hlsl_bitcast(to: Scalar) -> &'static str {
    match to {
        Scalar::F32 => "asfloat",
        Scalar::I32 => "asint",
        Scalar::U32 | Scalar::Bool => "asuint",
    }
}

/// HLSL's name of a built-in (`lerp`, `frac`, `rsqrt`, `mad`).
pub(crate) fn hlsl_builtin(b: Builtin) -> &'static str {
    match b {
        Builtin::Abs => "abs",
        Builtin::Ceil => "ceil",
        Builtin::Clamp => "clamp",
        Builtin::Cos => "cos",
        Builtin::Cross => "cross",
        Builtin::Distance => "distance",
        Builtin::Dot => "dot",
        Builtin::Exp => "exp",
        Builtin::Exp2 => "exp2",
        Builtin::Floor => "floor",
        Builtin::Fract => "frac",
        Builtin::InverseSqrt => "rsqrt",
        Builtin::Length => "length",
        Builtin::Log => "log",
        Builtin::Log2 => "log2",
        Builtin::Max => "max",
        Builtin::Min => "min",
        Builtin::Mix => "lerp",
        Builtin::Normalize => "normalize",
        Builtin::Pow => "pow",
        Builtin::Round => "round",
        Builtin::Select => "select",
        Builtin::Sign => "sign",
        Builtin::Sin => "sin",
        Builtin::Smoothstep => "smoothstep",
        Builtin::Sqrt => "sqrt",
        Builtin::Step => "step",
        Builtin::Tan => "tan",
        Builtin::Trunc => "trunc",
        Builtin::Atan2 => "atan2",
        Builtin::Acos => "acos",
        Builtin::Asin => "asin",
        Builtin::Atan => "atan",
        Builtin::Fma => "mad",
        Builtin::Saturate => "saturate",
        Builtin::Pack4x8Unorm => PACK4X8UNORM,
    }
}

/// WGSL's `pack4x8unorm` has no HLSL intrinsic: the file defines it when a function calls it.
const PACK4X8UNORM: &str = "nimbus_pack4x8unorm";

fn literal(l: Literal) -> Option<String> {
    Some(match l {
        Literal::F32(bits) => return float_literal(f32::from_bits(bits)),
        Literal::I32(i32::MIN) => "(-2147483647 - 1)".to_string(),
        Literal::I32(v) => v.to_string(),
        Literal::U32(v) => format!("{v}u"),
        Literal::Bool(v) => v.to_string(),
    })
}

/// The register a binding takes: its class letter and its WGSL binding number.
pub fn register(kind: &GlobalKind, ty: Type) -> Option<String> {
    let (class, group, binding) = match *kind {
        GlobalKind::Uniform { group, binding } => ('b', group, binding),
        GlobalKind::Storage {
            group,
            binding,
            read_write: true,
        } => ('u', group, binding),
        GlobalKind::Storage { group, binding, .. } => ('t', group, binding),
        GlobalKind::Handle { group, binding } if ty == Type::Sampler => ('s', group, binding),
        GlobalKind::Handle { group, binding } => ('t', group, binding),
        _ => return None,
    };
    Some(if group == 0 {
        format!("register({class}{binding})")
    } else {
        format!("register({class}{binding}, space{group})")
    })
}

/// HLSL names of the module's identifiers: each as WGSL has it unless HLSL reserves it.
struct Names {
    renamed: BTreeMap<String, String>,
}

impl Names {
    fn of(module: &Module) -> Names {
        let mut all: BTreeSet<String> = BTreeSet::new();
        for s in &module.structs {
            all.insert(s.name.to_string());
            all.extend(s.fields.iter().map(|f| f.name.to_string()));
        }
        all.extend(module.globals.iter().map(|g| g.name.clone()));
        for f in &module.functions {
            all.insert(f.name.clone());
            all.extend(f.params.iter().map(|p| p.name.clone()));
            all.extend(f.locals.iter().map(|l| l.name.clone()));
        }
        // What the printer itself declares: a module identifier spelled so is renamed.
        let generated = |name: &str| {
            name == PACK4X8UNORM
                || name.starts_with("_pad")
                || name
                    .strip_prefix("make_")
                    .is_some_and(|s| module.structs.iter().any(|d| d.name == s))
        };
        let mut taken = all.clone();
        let mut renamed = BTreeMap::new();
        // Unity creates a sampler the file declares but no texture names from the words in its
        // name ("inline sampler states"): filter first, then wrap.
        for g in module.globals.iter().filter(|g| g.ty == Type::Sampler) {
            let desc = g.sampler.unwrap_or(SamplerDesc::LINEAR_REPEAT);
            let filter = match desc.filter {
                FilterMode::Nearest => "point",
                FilterMode::Linear => "linear",
            };
            let wrap = match desc.address {
                AddressMode::Repeat => "repeat",
                AddressMode::ClampToEdge => "clamp",
                AddressMode::MirrorRepeat => "mirror",
            };
            let mut new = format!("{}_{filter}_{wrap}", g.name);
            while taken.contains(&new) {
                new.push('_');
            }
            taken.insert(new.clone());
            renamed.insert(g.name.clone(), new);
        }
        let reserved_names: Vec<&String> = all
            .iter()
            .filter(|n| (reserved(n) || generated(n)) && !renamed.contains_key(*n))
            .collect();
        for name in reserved_names {
            let mut new = format!("{name}_");
            while taken.contains(&new) || reserved(&new) {
                new.push('_');
            }
            taken.insert(new.clone());
            renamed.insert(name.clone(), new);
        }
        Names { renamed }
    }

    fn get<'a>(&'a self, name: &'a str) -> &'a str {
        self.renamed.get(name).map_or(name, String::as_str)
    }
}

/// HLSL's packing of a cbuffer member: `(offset, size)` after `offset` (the end of the previous
/// member). Vectors do not cross a 16-byte register; matrices, arrays and structs start one.
fn hlsl_place(ty: Type, offset: u32, padded: &BTreeMap<&'static str, u32>) -> (u32, u32) {
    let next_register = offset.div_ceil(16) * 16;
    match ty {
        Type::Scalar(_) | Type::Vector(..) => {
            let size = 4 * ty.components().unwrap_or(1);
            if offset / 16 != (offset + size - 1) / 16 {
                (next_register, size)
            } else {
                (offset, size)
            }
        }
        // `row_major floatNxN`: N registers, each holding a row of N floats.
        Type::Matrix(n) => (next_register, 16 * (u32::from(n) - 1) + 4 * u32::from(n)),
        Type::Array(elem, n) => {
            // Each element starts a register; the last is not padded.
            let (_, elem_size) = hlsl_place(*elem, 0, padded);
            let stride = elem_size.div_ceil(16) * 16;
            (next_register, stride * n.saturating_sub(1) + elem_size)
        }
        Type::Struct(def) => (next_register, padded.get(def.name).copied().unwrap_or(0)),
        _ => (offset, 0),
    }
}

/// One member of a printed struct: a field, or padding of `float`s.
enum Member {
    Field(usize),
    Pad { offset: u32 },
}

/// The members of each struct, with padding where HLSL's packing would put a field before the
/// WGSL offset. Structs in dependency order.
fn struct_members(
    order: &[&'static StructDef],
) -> Result<BTreeMap<&'static str, Vec<Member>>, String> {
    let mut members = BTreeMap::new();
    let mut sizes = BTreeMap::new();
    for def in order {
        let (_, _, offsets) = struct_layout(def);
        let mut list = Vec::new();
        let mut at = 0;
        for (i, (field, want)) in def.fields.iter().zip(offsets).enumerate() {
            loop {
                let (place, _) = hlsl_place(field.ty, at, &sizes);
                if place >= want {
                    if place > want {
                        return Err(format!(
                            "HLSL packs `{}.{}` at byte {place}, past its WGSL offset {want}",
                            def.name, field.name
                        ));
                    }
                    break;
                }
                list.push(Member::Pad { offset: at });
                at += 4;
            }
            let (place, size) = hlsl_place(field.ty, at, &sizes);
            list.push(Member::Field(i));
            at = place + size;
        }
        members.insert(def.name, list);
        sizes.insert(def.name, at);
    }
    Ok(members)
}

/// The module's structs, each after the structs its fields hold.
fn struct_order(module: &Module) -> Vec<&'static StructDef> {
    fn visit(def: &'static StructDef, out: &mut Vec<&'static StructDef>) {
        if out.iter().any(|d| std::ptr::eq(*d, def)) {
            return;
        }
        for f in def.fields {
            let mut ty = f.ty;
            while let Type::Array(elem, _) = ty {
                ty = *elem;
            }
            if let Type::Struct(inner) = ty {
                visit(inner, out);
            }
        }
        out.push(def);
    }
    let mut out = Vec::new();
    for s in &module.structs {
        visit(s, &mut out);
    }
    out
}

/// HLSL's semantic for an entry point's parameter or result.
fn semantic(io: Io, stage: Stage, output: bool) -> String {
    match io {
        Io::Position => "SV_Position".to_string(),
        Io::VertexIndex => "SV_VertexID".to_string(),
        Io::GlobalInvocationId => "SV_DispatchThreadID".to_string(),
        Io::Location(n) if output && stage == Stage::Fragment => format!("SV_Target{n}"),
        Io::Location(n) => format!("TEXCOORD{n}"),
    }
}

/// Prints `module` (specialised and named for WGSL) as one HLSL file, with the manifest a host
/// binds it by.
pub fn print_module(
    module: &Module,
    variant: &str,
) -> Result<(String, BindingManifest), CodegenError> {
    let fail = |message: String| CodegenError::Hlsl {
        module: module.name.clone(),
        variant: variant.to_string(),
        message,
    };
    let order = struct_order(module);
    let members = struct_members(&order).map_err(fail)?;
    let mut p = Printer {
        module,
        names: Names::of(module),
        out: String::new(),
        indent: 0,
    };
    p.header(variant);
    p.helpers(&order, &members)?;
    p.globals();
    for f in &module.functions {
        p.function(f)?;
    }
    while p.out.ends_with("\n\n") {
        p.out.pop();
    }
    let manifest = p.manifest(variant, &order);
    Ok((p.out, manifest))
}

struct Printer<'m> {
    module: &'m Module,
    names: Names,
    out: String,
    indent: usize,
}

impl Printer<'_> {
    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn doc(&mut self, doc: &str) {
        for d in doc.lines() {
            self.line(format!("// {d}").trim_end());
        }
    }

    fn header(&mut self, variant: &str) {
        let m = self.module;
        self.line(&format!(
            "// Generated by Nimbus from module `{}`, key `{variant}`. Do not edit: change the Rust source.",
            m.name
        ));
        if m.globals.iter().any(|g| g.binding().is_some()) {
            self.line(
                "// HLSL shader model 5.0, Direct3D 11 registers: each binding in the register of \
                 its class numbered as its WGSL binding.",
            );
        }
        for d in &m.doc {
            self.line(format!("// {d}").trim_end());
        }
        self.out.push('\n');
    }

    /// Structs, and the functions HLSL needs beside them: a `make_` per struct an expression
    /// builds, the packing intrinsic WGSL has and HLSL lacks.
    fn helpers(
        &mut self,
        order: &[&'static StructDef],
        members: &BTreeMap<&'static str, Vec<Member>>,
    ) -> Result<(), CodegenError> {
        let mut built = BTreeSet::new();
        let mut packs = false;
        for f in &self.module.functions {
            for e in &f.exprs {
                match e.kind {
                    ExprKind::Construct(Type::Struct(def), _) => {
                        built.insert(def.name);
                    }
                    ExprKind::Builtin(Builtin::Pack4x8Unorm, _) => packs = true,
                    _ => {}
                }
            }
        }
        for def in order {
            self.doc(def.doc);
            self.line(&format!("struct {} {{", self.names.get(def.name)));
            self.indent += 1;
            for m in members.get(def.name).into_iter().flatten() {
                match *m {
                    Member::Pad { offset } => self.line(&format!("float _pad{offset};")),
                    Member::Field(i) => {
                        let field = &def.fields[i];
                        self.doc(field.doc);
                        let decl = format!(
                            "{}{} {};",
                            major(field.ty),
                            hlsl_type(field.ty, &self.names),
                            declarator(field.ty, self.names.get(field.name))
                        );
                        self.line(&decl);
                    }
                }
            }
            self.indent -= 1;
            self.line("};");
            self.out.push('\n');
            if built.contains(def.name) {
                let name = self.names.get(def.name).to_string();
                // Parameters by position: a field may be named like the local.
                let params: Vec<String> = def
                    .fields
                    .iter()
                    .enumerate()
                    .map(|(i, f)| {
                        let ty = hlsl_type(f.ty, &self.names);
                        format!("{ty} {}", declarator(f.ty, &format!("f{i}")))
                    })
                    .collect();
                self.line(&format!("{name} make_{name}({}) {{", params.join(", ")));
                self.indent += 1;
                self.line(&format!("{name} value = ({name})0;"));
                for (i, f) in def.fields.iter().enumerate() {
                    let n = self.names.get(f.name).to_string();
                    self.line(&format!("value.{n} = f{i};"));
                }
                self.line("return value;");
                self.indent -= 1;
                self.line("}");
                self.out.push('\n');
            }
        }
        if packs {
            self.line("// WGSL's pack4x8unorm: four [0, 1] values to bytes, x in the lowest.");
            self.line(&format!("uint {PACK4X8UNORM}(float4 v) {{"));
            self.indent += 1;
            // floor(0.5 + x): halves round up, as WGSL says (HLSL's round goes to even).
            self.line("uint4 b = (uint4)floor(0.5 + saturate(v) * 255.0);");
            self.line("return b.x | (b.y << 8) | (b.z << 16) | (b.w << 24);");
            self.indent -= 1;
            self.line("}");
            self.out.push('\n');
        }
        Ok(())
    }

    fn globals(&mut self) {
        let m = self.module;
        if m.globals.is_empty() {
            return;
        }
        for i in crate::lower::declaration_order(m) {
            let g = &m.globals[i];
            self.doc(&g.doc);
            let name = self.names.get(&g.name).to_string();
            let ty = hlsl_type(g.ty, &self.names);
            let reg = register(&g.kind, g.ty).unwrap_or_default();
            let decl = match &g.kind {
                GlobalKind::Uniform { .. } => {
                    format!(
                        "cbuffer {name} : {reg} {{ {}{ty} {}; }};",
                        major(g.ty),
                        declarator(g.ty, &name)
                    )
                }
                GlobalKind::Storage { read_write, .. } => {
                    let class = if *read_write {
                        "RWStructuredBuffer"
                    } else {
                        "StructuredBuffer"
                    };
                    format!("{class}<{ty}> {name} : {reg};")
                }
                GlobalKind::Handle { .. } => format!("{ty} {name} : {reg};"),
                GlobalKind::Override { default: value } | GlobalKind::Const { value } => {
                    format!(
                        "static const {ty} {} = {};",
                        declarator(g.ty, &name),
                        literal(*value).unwrap_or_else(|| "0.0".into())
                    )
                }
                GlobalKind::Private => {
                    format!("static {ty} {} = ({ty})0;", declarator(g.ty, &name))
                }
            };
            self.line(&decl);
        }
        self.out.push('\n');
    }

    fn function(&mut self, f: &Function) -> Result<(), CodegenError> {
        let entry = self.module.entry_point(&f.name);
        for d in &f.doc {
            self.line(format!("// {d}").trim_end());
        }
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
                let sem = entry
                    .and_then(|e| e.inputs.get(i).map(|io| (io, e.stage)))
                    .map(|(io, stage)| format!(" : {}", semantic(*io, stage, false)))
                    .unwrap_or_default();
                format!(
                    "{} {}{sem}",
                    hlsl_type(p.ty, &self.names),
                    declarator(p.ty, self.names.get(&p.name))
                )
            })
            .collect();
        let result = f
            .result
            .map_or_else(|| "void".to_string(), |t| hlsl_type(t, &self.names));
        let result_sem = entry
            .and_then(|e| e.output.map(|io| (io, e.stage)))
            .map(|(io, stage)| format!(" : {}", semantic(io, stage, true)))
            .unwrap_or_default();
        if let Some(e) = entry {
            self.line("#ifdef __SLANG__");
            self.line(&format!("[shader(\"{}\")]", e.stage.name()));
            self.line("#endif");
            if e.stage == Stage::Compute {
                let [x, y, z] = e.workgroup_size;
                self.line(&format!("[numthreads({x}, {y}, {z})]"));
            }
        }
        let name = self.names.get(&f.name).to_string();
        self.line(&format!(
            "{result} {name}({}){result_sem} {{",
            params.join(", ")
        ));
        self.indent += 1;
        self.block(f, &f.body)?;
        self.indent -= 1;
        self.line("}");
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

    fn local_decl(&self, f: &Function, local: nimbus_dsl::ir::LocalId) -> (String, String) {
        let l = f.local(local);
        (
            hlsl_type(l.ty, &self.names),
            declarator(l.ty, self.names.get(&l.name)),
        )
    }

    fn stmt(&mut self, f: &Function, stmt: &Stmt) -> Result<(), CodegenError> {
        match stmt {
            Stmt::Let { local, value, .. } => {
                let v = self.expr(f, *value)?;
                let (ty, name) = self.local_decl(f, *local);
                self.line(&format!("const {ty} {name} = {v};"));
            }
            Stmt::Var { local, init, .. } => {
                let (ty, name) = self.local_decl(f, *local);
                let v = match init {
                    Some(i) => self.expr(f, *i)?,
                    // WGSL zero-initialises a `var`; HLSL leaves it undefined.
                    None => format!("({ty})0"),
                };
                self.line(&format!("{ty} {name} = {v};"));
            }
            Stmt::Assign { local, value, .. } => {
                let v = self.expr(f, *value)?;
                let name = self.names.get(&f.local(*local).name).to_string();
                self.line(&format!("{name} = {v};"));
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
                self.line(&format!("if ({c}) {{"));
                self.if_rest(f, then, otherwise)?;
            }
            Stmt::For {
                counter,
                start,
                end,
                body,
                ..
            } => {
                let (ty, name) = self.local_decl(f, *counter);
                let a = self.expr(f, *start)?;
                let b = self.expr(f, *end)?;
                let one = if f.local(*counter).ty == Type::I32 {
                    "1"
                } else {
                    "1u"
                };
                self.line(&format!(
                    "for ({ty} {name} = {a}; {name} < {b}; {name} += {one}) {{"
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
        Ok(())
    }

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
                    ..
                },
            ] => {
                let c = self.expr(f, *cond)?;
                self.line(&format!("}} else if ({c}) {{"));
                self.if_rest(f, t2, o2)?;
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

    fn operand(
        &mut self,
        f: &Function,
        id: ExprId,
        parent: BinaryOp,
        right: bool,
    ) -> Result<String, CodegenError> {
        let s = self.expr(f, id)?;
        Ok(match f.expr(id).kind {
            ExprKind::Binary(op, a, b)
                if needs_parens(parent, op, right) && !is_mul_call(f, op, a, b) =>
            {
                format!("({s})")
            }
            _ => s,
        })
    }

    fn postfix_base(&mut self, f: &Function, id: ExprId) -> Result<String, CodegenError> {
        let s = self.expr(f, id)?;
        Ok(match f.expr(id).kind {
            ExprKind::Binary(op, a, b) if !is_mul_call(f, op, a, b) => format!("({s})"),
            ExprKind::Unary(..) | ExprKind::Convert(..) | ExprKind::Construct(..) => {
                format!("({s})")
            }
            _ => s,
        })
    }

    fn args(&mut self, f: &Function, args: &[ExprId]) -> Result<String, CodegenError> {
        let mut v = Vec::with_capacity(args.len());
        for a in args {
            v.push(self.expr(f, *a)?);
        }
        Ok(v.join(", "))
    }

    fn expr(&mut self, f: &Function, id: ExprId) -> Result<String, CodegenError> {
        let e = f.expr(id);
        Ok(match &e.kind {
            ExprKind::Literal(l) => literal(*l).ok_or_else(|| CodegenError::NonFiniteLiteral {
                function: f.rust_name.clone(),
                loc: f.loc,
            })?,
            ExprKind::Arg(i) => self.names.get(&f.params[*i as usize].name).to_string(),
            ExprKind::Local(l) => self.names.get(&f.local(*l).name).to_string(),
            ExprKind::Global(g) => self
                .names
                .get(&self.module.globals[g.0 as usize].name)
                .to_string(),
            ExprKind::Unary(op, a) => {
                let inner = self.expr(f, *a)?;
                let inner = match f.expr(*a).kind {
                    ExprKind::Binary(..) | ExprKind::Unary(..) => format!("({inner})"),
                    ExprKind::Literal(Literal::F32(b)) if f32::from_bits(b) < 0.0 => {
                        format!("({inner})")
                    }
                    ExprKind::Literal(Literal::I32(v)) if v < 0 => format!("({inner})"),
                    _ => inner,
                };
                let sym = match op {
                    UnaryOp::Neg => "-",
                    UnaryOp::Not => "!",
                };
                format!("{sym}{inner}")
            }
            ExprKind::Binary(op, a, b) => {
                if is_mul_call(f, *op, *a, *b) {
                    // The HLSL matrix is WGSL's transposed: `m * v` is `mul(v, m)`.
                    let l = self.expr(f, *a)?;
                    let r = self.expr(f, *b)?;
                    format!("mul({r}, {l})")
                } else {
                    let l = self.operand(f, *a, *op, false)?;
                    let r = self.operand(f, *b, *op, true)?;
                    format!("{l} {} {r}", crate::wgsl_spelling::wgsl_operator(*op))
                }
            }
            ExprKind::Builtin(Builtin::Select, args) if args.len() == 3 => {
                let (fa, t, c) = (args[0], args[1], args[2]);
                self.select(f, fa, t, c)?
            }
            ExprKind::Builtin(Builtin::Sign, args) => {
                // HLSL's sign returns integers.
                format!(
                    "(({})sign({}))",
                    hlsl_type(e.ty, &self.names),
                    self.args(f, args)?
                )
            }
            ExprKind::Builtin(b, args) => format!("{}({})", hlsl_builtin(*b), self.args(f, args)?),
            ExprKind::Call(name, args) => {
                let a = self.args(f, args)?;
                format!("{}({a})", self.names.get(name))
            }
            ExprKind::Construct(ty, args) => self.construct(f, *ty, args)?,
            ExprKind::Swizzle(v, idx) => {
                let base = self.postfix_base(f, *v)?;
                let s: String = idx
                    .iter()
                    .map(|i| ['x', 'y', 'z', 'w'][*i as usize])
                    .collect();
                format!("{base}.{s}")
            }
            ExprKind::Member(v, i) => {
                let base = self.postfix_base(f, *v)?;
                let name = match f.expr(*v).ty {
                    Type::Struct(def) => self.names.get(def.fields[*i as usize].name),
                    _ => "?",
                };
                format!("{base}.{name}")
            }
            ExprKind::Index(a, i) => {
                let base = self.postfix_base(f, *a)?;
                format!("{base}[{}]", self.expr(f, *i)?)
            }
            ExprKind::Convert(_, a) => {
                format!("({})({})", hlsl_type(e.ty, &self.names), self.expr(f, *a)?)
            }
            ExprKind::Bitcast(to, a) => {
                format!("{}({})", hlsl_bitcast(*to), self.expr(f, *a)?)
            }
            ExprKind::Select {
                if_false,
                if_true,
                cond,
            } => self.select(f, *if_false, *if_true, *cond)?,
            ExprKind::Sample {
                texture,
                sampler,
                coords,
                kind,
            } => {
                let t = self.postfix_base(f, *texture)?;
                let s = self.expr(f, *sampler)?;
                let c = self.expr(f, *coords)?;
                match kind {
                    SampleKind::Level(l) => {
                        format!("{t}.SampleLevel({s}, {c}, {})", self.expr(f, *l)?)
                    }
                    SampleKind::Implicit => format!("{t}.Sample({s}, {c})"),
                }
            }
            ExprKind::Load {
                texture,
                texel,
                level,
            } => {
                let t = self.postfix_base(f, *texture)?;
                let n = match f.expr(*texture).ty {
                    Type::Texture3d => 3,
                    _ => 2,
                };
                let texel = self.expr(f, *texel)?;
                let level = self.expr(f, *level)?;
                format!("{t}.Load(int{}((int{n})({texel}), (int)({level})))", n + 1)
            }
        })
    }

    /// WGSL's `select(f, t, c)`: the component-wise `c ? t : f` of shader model 5.
    fn select(
        &mut self,
        f: &Function,
        if_false: ExprId,
        if_true: ExprId,
        cond: ExprId,
    ) -> Result<String, CodegenError> {
        let c = self.expr(f, cond)?;
        let t = self.expr(f, if_true)?;
        let e = self.expr(f, if_false)?;
        Ok(format!("(({c}) ? ({t}) : ({e}))"))
    }

    fn construct(
        &mut self,
        f: &Function,
        ty: Type,
        args: &[ExprId],
    ) -> Result<String, CodegenError> {
        let a = self.args(f, args)?;
        Ok(match ty {
            Type::Struct(def) => format!("make_{}({a})", self.names.get(def.name)),
            Type::Array(..) => {
                return Err(CodegenError::Hlsl {
                    module: self.module.name.clone(),
                    variant: String::new(),
                    message: format!(
                        "`{}` builds a `{}` in an expression, which HLSL cannot",
                        f.rust_name,
                        wgsl_type(ty)
                    ),
                });
            }
            // One argument: a splat or a conversion, both casts in HLSL (`float3(x)` is not).
            _ if args.len() == 1 => format!("(({})({a}))", hlsl_type(ty, &self.names)),
            // No argument: the zero value.
            _ if args.is_empty() => format!("(({})0)", hlsl_type(ty, &self.names)),
            _ => format!("{}({a})", hlsl_type(ty, &self.names)),
        })
    }

    fn manifest(&self, variant: &str, order: &[&'static StructDef]) -> BindingManifest {
        let m = self.module;
        let mut bindings = Vec::new();
        for g in &m.globals {
            let Some((group, binding)) = g.binding() else {
                continue;
            };
            let kind = match (&g.kind, g.ty) {
                (GlobalKind::Uniform { .. }, _) => "uniform",
                (GlobalKind::Storage { .. }, _) => "storage",
                (_, Type::Sampler) => "sampler",
                _ => "texture",
            };
            bindings.push(ManifestBinding {
                name: g.name.clone(),
                kind,
                group,
                binding,
                wgsl_type: wgsl_type(g.ty),
                target_name: format!(
                    "{} : {}",
                    self.names.get(&g.name),
                    register(&g.kind, g.ty).unwrap_or_default()
                ),
                sampler: g.sampler.map(|d| crate::manifest::ManifestSampler {
                    address_mode: d.address.name(),
                    filter: d.filter.name(),
                }),
            });
        }
        bindings.sort_by_key(|b| (b.group, b.binding));
        let structs = order
            .iter()
            .map(|def| {
                let (_, size, offsets) = struct_layout(def);
                ManifestStruct {
                    name: def.name.to_string(),
                    size,
                    fields: def
                        .fields
                        .iter()
                        .zip(offsets)
                        .map(|(field, offset)| ManifestField {
                            name: field.name.to_string(),
                            target_name: self.names.get(field.name).to_string(),
                            wgsl_type: wgsl_type(field.ty),
                            offset,
                        })
                        .collect(),
                }
            })
            .collect();
        let mut overrides: Vec<_> = crate::backend::default_constants(m)
            .into_iter()
            .map(|(name, value)| crate::manifest::ManifestOverride { name, value })
            .collect();
        overrides.sort_by(|a, b| a.name.cmp(&b.name));
        BindingManifest {
            module: m.name.clone(),
            variant: variant.to_string(),
            target: crate::target::Target::Hlsl.name().to_string(),
            entry_points: m
                .entry_points
                .iter()
                .map(|e| (e.stage.name().to_string(), e.function.clone()))
                .collect(),
            bindings,
            combined_samplers: Vec::new(),
            buffer_sizes: None,
            structs,
            overrides,
        }
    }
}

/// Whether `a op b` is a matrix product, which HLSL writes as `mul`.
fn is_mul_call(f: &Function, op: BinaryOp, a: ExprId, b: ExprId) -> bool {
    op == BinaryOp::Mul
        && (matches!(f.expr(a).ty, Type::Matrix(_)) && !matches!(f.expr(b).ty, Type::Scalar(_))
            || matches!(f.expr(b).ty, Type::Matrix(_)) && !matches!(f.expr(a).ty, Type::Scalar(_)))
}
