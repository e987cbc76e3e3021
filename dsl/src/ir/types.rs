//! Shader types as the IR sees them, in no target's spelling (the WGSL printer and the naga
//! lowering each say them their own way). Every value the DSL records carries one of these, so
//! no consumer has to infer a type and naga never sees an abstract literal it could misread.

/// A scalar kind. Only the 32-bit kinds every target supports (no f16, no f64).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub enum Scalar {
    F32,
    I32,
    U32,
    Bool,
}

/// One field of a [`StructDef`].
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct FieldDef {
    pub name: &'static str,
    pub ty: Type,
    /// Doc comment of the Rust field, printed above the WGSL member.
    pub doc: &'static str,
}

/// A struct type declared once in Rust (`#[derive(ShaderStruct)]`) and printed as a WGSL struct.
#[derive(Debug, Eq)]
pub struct StructDef {
    pub name: &'static str,
    pub doc: &'static str,
    pub fields: &'static [FieldDef],
}

/// The same definition is nearly always the same static: compared by address first. Recording
/// and lowering compare and hash types at every binding read and every value (the uniform
/// block's type holds every member's name and doc), and a deep comparison there was a tenth
/// of a key's generation time.
impl PartialEq for StructDef {
    fn eq(&self, other: &Self) -> bool {
        core::ptr::eq(self, other)
            || (self.name == other.name && self.doc == other.doc && self.fields == other.fields)
    }
}

/// By name alone: equal definitions have equal names, and a struct's name is what tells two
/// apart in any one module (the printers declare each once, by name).
impl core::hash::Hash for StructDef {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.name.hash(state);
    }
}

/// A shader type.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Type {
    Scalar(Scalar),
    /// `vecN<scalar>` with N in 2..=4.
    Vector(u8, Scalar),
    /// `matCxR<f32>`; only square 3×3 and 4×4 are exposed by the DSL.
    Matrix(u8),
    Struct(&'static StructDef),
    /// `array<T, N>`: a fixed-size array of constructible values.
    Array(&'static Type, u32),
    /// `array<scalar>` in a storage buffer (runtime sized).
    RuntimeArray(Scalar),
    Texture2d,
    Texture3d,
    Sampler,
}

impl Type {
    pub const F32: Type = Type::Scalar(Scalar::F32);
    pub const I32: Type = Type::Scalar(Scalar::I32);
    pub const U32: Type = Type::Scalar(Scalar::U32);
    pub const BOOL: Type = Type::Scalar(Scalar::Bool);

    /// The scalar kind of a scalar or vector; `None` for anything else.
    pub fn scalar(self) -> Option<Scalar> {
        match self {
            Type::Scalar(s) | Type::Vector(_, s) => Some(s),
            Type::Matrix(_) => Some(Scalar::F32),
            _ => None,
        }
    }

    /// Number of scalar components of a scalar, vector or matrix.
    pub fn components(self) -> Option<u32> {
        match self {
            Type::Scalar(_) => Some(1),
            Type::Vector(n, _) => Some(u32::from(n)),
            Type::Matrix(n) => Some(u32::from(n) * u32::from(n)),
            _ => None,
        }
    }

    /// Whether values of this type may be held in a `let`/`var` and passed by value.
    pub fn is_constructible(self) -> bool {
        matches!(
            self,
            Type::Scalar(_)
                | Type::Vector(..)
                | Type::Matrix(_)
                | Type::Struct(_)
                | Type::Array(..)
        )
    }
}
