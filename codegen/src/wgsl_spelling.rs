//! How WGSL spells the IR's types, operators, built-in functions and stages. The IR itself is
//! target-neutral; this table is the printer's (and the manifests', which name WGSL types for
//! WebGPU hosts), as naga keeps each language's spelling in its back end.

use nimbus_dsl::ir::{BinaryOp, Builtin, Scalar, Type};

/// `f32`, `i32`, `u32`, `bool`.
pub fn wgsl_scalar(s: Scalar) -> &'static str {
    match s {
        Scalar::F32 => "f32",
        Scalar::I32 => "i32",
        Scalar::U32 => "u32",
        Scalar::Bool => "bool",
    }
}

/// `vec3<f32>`, `mat4x4<f32>`, a struct's name, `texture_2d<f32>`...
pub fn wgsl_type(ty: Type) -> String {
    match ty {
        Type::Scalar(s) => wgsl_scalar(s).to_string(),
        Type::Vector(n, s) => format!("vec{n}<{}>", wgsl_scalar(s)),
        Type::Matrix(n) => format!("mat{n}x{n}<f32>"),
        Type::Struct(def) => def.name.to_string(),
        Type::Array(elem, n) => format!("array<{}, {n}>", wgsl_type(*elem)),
        Type::RuntimeArray(s) => format!("array<{}>", wgsl_scalar(s)),
        Type::Texture2d => "texture_2d<f32>".to_string(),
        Type::Texture3d => "texture_3d<f32>".to_string(),
        Type::Sampler => "sampler".to_string(),
    }
}

/// The operator's symbol.
pub fn wgsl_operator(op: BinaryOp) -> &'static str {
    match op {
        BinaryOp::Add => "+",
        BinaryOp::Sub => "-",
        BinaryOp::Mul => "*",
        BinaryOp::Div => "/",
        BinaryOp::Rem => "%",
        BinaryOp::Lt => "<",
        BinaryOp::Le => "<=",
        BinaryOp::Gt => ">",
        BinaryOp::Ge => ">=",
        BinaryOp::Eq => "==",
        BinaryOp::Ne => "!=",
        BinaryOp::And => "&&",
        BinaryOp::Or => "||",
        BinaryOp::BitAnd => "&",
        BinaryOp::BitOr => "|",
        BinaryOp::BitXor => "^",
        BinaryOp::Shl => "<<",
        BinaryOp::Shr => ">>",
    }
}

/// The built-in function's WGSL name (`inverseSqrt`, `pack4x8unorm`...).
pub fn wgsl_builtin(b: Builtin) -> &'static str {
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
        Builtin::Fract => "fract",
        Builtin::InverseSqrt => "inverseSqrt",
        Builtin::Length => "length",
        Builtin::Log => "log",
        Builtin::Log2 => "log2",
        Builtin::Max => "max",
        Builtin::Min => "min",
        Builtin::Mix => "mix",
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
        Builtin::Fma => "fma",
        Builtin::Saturate => "saturate",
        Builtin::Pack4x8Unorm => "pack4x8unorm",
    }
}
