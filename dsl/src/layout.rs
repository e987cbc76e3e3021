//! Uniform buffer layout, derived from the one Rust definition of each `ShaderStruct`: WGSL's
//! alignment and size rules for the uniform address space, and the bytes of a CPU value laid out
//! by them. A test checks every offset against naga's own layout of the generated WGSL.

use crate::ir::{Scalar, StructDef, Type};

fn round_up(align: u32, n: u32) -> u32 {
    n.div_ceil(align) * align
}

/// `(alignment, size)` of a type in the uniform address space.
pub fn align_size(ty: Type) -> (u32, u32) {
    match ty {
        Type::Scalar(_) => (4, 4),
        Type::Vector(2, _) => (8, 8),
        Type::Vector(3, _) => (16, 12),
        Type::Vector(_, _) => (16, 16),
        Type::Matrix(n) => {
            // Columns are vecN, each padded to its alignment.
            let (col_align, col_size) = align_size(Type::Vector(n, Scalar::F32));
            (col_align, round_up(col_align, col_size) * u32::from(n))
        }
        Type::Struct(def) => {
            let (align, size, _) = struct_layout(def);
            (align, size)
        }
        Type::Array(elem, n) => {
            let (align, stride) = array_stride(*elem);
            (align, stride * n)
        }
        _ => (4, 0),
    }
}

/// `(alignment, stride)` of the elements of a uniform array: both rounded up to 16, as the
/// uniform address space requires.
pub fn array_stride(elem: Type) -> (u32, u32) {
    let (a, s) = align_size(elem);
    let align = round_up(16, a);
    (align, round_up(align, s))
}

/// Alignment, size and member offsets of a struct. Struct members of struct type are aligned
/// to 16, as the uniform address space requires; the struct itself is as aligned as its most
/// aligned member (WGSL's AlignOf), so `{vec2, f32, f32, f32}` is 24 bytes, as naga lays it out.
/// (A std140 host, WebGL's, rounds a block up to 16 bytes: engine packages pad for it.)
pub fn struct_layout(def: &StructDef) -> (u32, u32, Vec<u32>) {
    let mut offset = 0;
    let mut align = 4;
    let mut offsets = Vec::with_capacity(def.fields.len());
    for f in def.fields {
        let (a, s) = align_size(f.ty);
        let a = if matches!(f.ty, Type::Struct(_) | Type::Array(..)) {
            round_up(16, a)
        } else {
            a
        };
        offset = round_up(a, offset);
        offsets.push(offset);
        offset += s;
        align = align.max(a);
    }
    (align, round_up(align, offset), offsets)
}

/// A write that does not fit the buffer it was given. The buffers `to_uniform_bytes` makes are
/// sized by the same type's layout, so this names a layout that disagrees with its own writer,
/// or a caller's buffer that is too short: either way the bytes would be wrong, not just short.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "uniform write of {len} bytes at offset {offset} does not fit a buffer of {buffer_size} bytes"
)]
pub struct LayoutError {
    /// Byte offset the write starts at.
    pub offset: usize,
    /// Bytes written.
    pub len: usize,
    /// Size of the buffer written into.
    pub buffer_size: usize,
}

/// A CPU value that can be written into a uniform buffer at an offset.
pub trait UniformBytes {
    /// The shader type, to find nested layouts.
    fn shader_type() -> Type;
    /// Writes the value's bytes at `offset`; a write past the end of `out` is refused, whole
    /// (nothing of it is written).
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError>;

    /// The value as a complete uniform buffer.
    fn to_uniform_bytes(&self) -> Result<Vec<u8>, LayoutError> {
        let (_, size) = align_size(Self::shader_type());
        let mut out = vec![0; size as usize];
        self.write(&mut out, 0)?;
        Ok(out)
    }
}

fn put(out: &mut [u8], offset: usize, words: &[u32]) -> Result<(), LayoutError> {
    let len = 4 * words.len();
    let error = LayoutError {
        offset,
        len,
        buffer_size: out.len(),
    };
    let slot = offset
        .checked_add(len)
        .and_then(|end| out.get_mut(offset..end))
        .ok_or(error)?;
    for (chunk, w) in slot.chunks_exact_mut(4).zip(words) {
        chunk.copy_from_slice(&w.to_le_bytes());
    }
    Ok(())
}

macro_rules! scalar_bytes {
    ($($t:ty => $ty:expr),*) => {$(
        impl UniformBytes for $t {
            fn shader_type() -> Type {
                $ty
            }
            fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
                put(out, offset, &[self.to_bits()])
            }
        }
    )*};
}

trait ToBits {
    fn to_bits(self) -> u32;
}
impl ToBits for u32 {
    fn to_bits(self) -> u32 {
        self
    }
}
impl ToBits for i32 {
    fn to_bits(self) -> u32 {
        self as u32
    }
}
scalar_bytes!(f32 => Type::F32);
impl UniformBytes for u32 {
    fn shader_type() -> Type {
        Type::U32
    }
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
        put(out, offset, &[ToBits::to_bits(*self)])
    }
}
impl UniformBytes for i32 {
    fn shader_type() -> Type {
        Type::I32
    }
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
        put(out, offset, &[ToBits::to_bits(*self)])
    }
}

macro_rules! vec_bytes {
    ($($t:ty => $n:literal),*) => {$(
        impl UniformBytes for $t {
            fn shader_type() -> Type {
                Type::Vector($n, Scalar::F32)
            }
            fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
                put(out, offset, &self.to_array().map(f32::to_bits))
            }
        }
    )*};
}
vec_bytes!(glam::Vec2 => 2, glam::Vec3 => 3, glam::Vec4 => 4);

impl UniformBytes for glam::Mat3 {
    fn shader_type() -> Type {
        Type::Matrix(3)
    }
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
        // Columns are vec3s, each padded to 16 bytes.
        for (i, col) in [self.x_axis, self.y_axis, self.z_axis].iter().enumerate() {
            put(out, offset + 16 * i, &col.to_array().map(f32::to_bits))?;
        }
        Ok(())
    }
}

impl UniformBytes for glam::Mat4 {
    fn shader_type() -> Type {
        Type::Matrix(4)
    }
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
        put(out, offset, &self.to_cols_array().map(f32::to_bits))
    }
}

impl<T: UniformBytes + crate::ShaderType, const N: usize> UniformBytes for [T; N] {
    fn shader_type() -> Type {
        <<[T; N] as crate::ShaderType>::Dsl as crate::Value>::TYPE
    }
    fn write(&self, out: &mut [u8], offset: usize) -> Result<(), LayoutError> {
        let (_, stride) = array_stride(T::shader_type());
        for (i, v) in self.iter().enumerate() {
            v.write(out, offset + i * stride as usize)?;
        }
        Ok(())
    }
}

/// A value as consecutive 32-bit words in declaration order with no padding: how the parity
/// harness passes arguments through a storage buffer.
pub trait Flatten {
    fn flatten(&self, out: &mut Vec<u32>);
}

impl Flatten for f32 {
    fn flatten(&self, out: &mut Vec<u32>) {
        out.push(self.to_bits());
    }
}
impl Flatten for u32 {
    fn flatten(&self, out: &mut Vec<u32>) {
        out.push(*self);
    }
}
impl Flatten for i32 {
    fn flatten(&self, out: &mut Vec<u32>) {
        out.push(*self as u32);
    }
}
macro_rules! flatten_glam {
    ($($t:ty),*) => {$(
        impl Flatten for $t {
            fn flatten(&self, out: &mut Vec<u32>) {
                out.extend(self.to_cols_array_or_array().iter().map(|v| v.to_bits()));
            }
        }
    )*};
}
trait ComponentArray {
    fn to_cols_array_or_array(&self) -> Vec<f32>;
}
impl ComponentArray for glam::Vec2 {
    fn to_cols_array_or_array(&self) -> Vec<f32> {
        self.to_array().to_vec()
    }
}
impl ComponentArray for glam::Vec3 {
    fn to_cols_array_or_array(&self) -> Vec<f32> {
        self.to_array().to_vec()
    }
}
impl ComponentArray for glam::Vec4 {
    fn to_cols_array_or_array(&self) -> Vec<f32> {
        self.to_array().to_vec()
    }
}
impl ComponentArray for glam::Mat3 {
    fn to_cols_array_or_array(&self) -> Vec<f32> {
        self.to_cols_array().to_vec()
    }
}
impl ComponentArray for glam::Mat4 {
    fn to_cols_array_or_array(&self) -> Vec<f32> {
        self.to_cols_array().to_vec()
    }
}
impl<T: Flatten, const N: usize> Flatten for [T; N] {
    fn flatten(&self, out: &mut Vec<u32>) {
        for v in self {
            v.flatten(out);
        }
    }
}

flatten_glam!(glam::Vec2, glam::Vec3, glam::Vec4, glam::Mat3, glam::Mat4);

/// Members of a uniform value by dotted path, each with its scalar components.
pub type Members = Vec<(String, Vec<f64>)>;

/// The members of a uniform value read back from its buffer bytes, flattened to dotted paths
/// (`group0.min_height`) with their scalar components (matrices column by column): what a host
/// that sets uniforms member by member, or a manifest, needs. Integers and booleans are exact
/// in `f64`.
pub fn read_members(ty: Type, bytes: &[u8]) -> Members {
    member_layout(ty, bytes)
        .into_iter()
        .map(|m| (m.path, m.value))
        .collect()
}

/// One leaf member of a uniform block: where it lives in the buffer and what it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct MemberLayout {
    /// Dotted path with array indices (`groups[1].min_height`).
    pub path: String,
    /// Byte offset from the start of the block.
    pub offset: u32,
    /// Its shader type (a scalar, vector or matrix).
    pub ty: Type,
    /// Its scalar components read from `bytes` (matrices column by column).
    pub value: Vec<f64>,
}

/// Every leaf member of a uniform block of type `ty` with its offset, type and the value it
/// has in `bytes`: a layout an engine can fill member by member, or write as raw bytes.
pub fn member_layout(ty: Type, bytes: &[u8]) -> Vec<MemberLayout> {
    let mut out = Vec::new();
    read_into(ty, bytes, 0, "", &mut out);
    out
}

fn word(bytes: &[u8], at: usize) -> u32 {
    bytes
        .get(at..at + 4)
        .and_then(|b| b.try_into().ok())
        .map_or(0, u32::from_le_bytes)
}

fn scalar(s: Scalar, w: u32) -> f64 {
    match s {
        Scalar::F32 => f64::from(f32::from_bits(w)),
        Scalar::I32 => f64::from(w as i32),
        Scalar::U32 | Scalar::Bool => f64::from(w),
    }
}

fn read_into(ty: Type, bytes: &[u8], offset: u32, path: &str, out: &mut Vec<MemberLayout>) {
    let at = offset as usize;
    match ty {
        Type::Struct(def) => {
            let (_, _, offsets) = struct_layout(def);
            for (f, o) in def.fields.iter().zip(offsets) {
                let p = if path.is_empty() {
                    f.name.to_string()
                } else {
                    format!("{path}.{}", f.name)
                };
                read_into(f.ty, bytes, offset + o, &p, out);
            }
        }
        Type::Scalar(s) => out.push(MemberLayout {
            path: path.to_string(),
            offset,
            ty,
            value: vec![scalar(s, word(bytes, at))],
        }),
        Type::Vector(n, s) => out.push(MemberLayout {
            path: path.to_string(),
            offset,
            ty,
            value: (0..usize::from(n))
                .map(|i| scalar(s, word(bytes, at + 4 * i)))
                .collect(),
        }),
        Type::Matrix(n) => {
            let (col_align, col_size) = align_size(Type::Vector(n, Scalar::F32));
            let stride = round_up(col_align, col_size) as usize;
            let values = (0..usize::from(n))
                .flat_map(|c| (0..usize::from(n)).map(move |r| at + c * stride + 4 * r))
                .map(|a| scalar(Scalar::F32, word(bytes, a)))
                .collect();
            out.push(MemberLayout {
                path: path.to_string(),
                offset,
                ty,
                value: values,
            });
        }
        Type::Array(elem, n) => {
            let (_, stride) = array_stride(*elem);
            for i in 0..n {
                read_into(
                    *elem,
                    bytes,
                    offset + i * stride,
                    &format!("{path}[{i}]"),
                    out,
                );
            }
        }
        Type::RuntimeArray(_) | Type::Texture2d | Type::Texture3d | Type::Sampler => {}
    }
}

#[cfg(test)]
mod tests {
    use super::{LayoutError, UniformBytes};
    use crate::ShaderStruct;

    #[derive(Clone, Copy, ShaderStruct)]
    struct Pair {
        offset: glam::Vec3,
        scale: f32,
        tint: glam::Vec4,
    }

    const PAIR: Pair = Pair {
        offset: glam::Vec3::new(1.0, 2.0, 3.0),
        scale: 4.0,
        tint: glam::Vec4::ONE,
    };

    #[test]
    fn a_write_past_the_end_is_refused() {
        let mut out = [0u8; 8];
        assert_eq!(
            glam::Vec4::ONE.write(&mut out, 0),
            Err(LayoutError {
                offset: 0,
                len: 16,
                buffer_size: 8
            })
        );
        assert_eq!(out, [0; 8], "nothing of a refused write lands");
        assert!(1.0f32.write(&mut out, 4).is_ok());
        assert_eq!(
            1.0f32.write(&mut out, usize::MAX - 1),
            Err(LayoutError {
                offset: usize::MAX - 1,
                len: 4,
                buffer_size: 8
            }),
            "an offset near usize::MAX is refused, not wrapped"
        );
    }

    #[test]
    fn a_struct_refuses_a_too_short_buffer() {
        let full = PAIR.to_uniform_bytes().expect("sized by its own layout");
        assert_eq!(full.len(), 32);
        let mut short = vec![0u8; full.len() - 4];
        // The vec4 at offset 16 is the member that does not fit.
        let e = PAIR
            .write(&mut short, 0)
            .expect_err("28 bytes cannot hold 32");
        assert_eq!(
            e.to_string(),
            "uniform write of 16 bytes at offset 16 does not fit a buffer of 28 bytes"
        );
    }
}
