//! A uniform-block value written word by word into a storage array, in the uniform address
//! space's layout: the shader twin of [`crate::layout::UniformBytes::write`]. A kernel that
//! derives part of a block on the GPU writes the whole block this way into a buffer the API
//! then binds as that uniform block, so the host needs no copy and no knowledge of the layout
//! beyond the block's size.

use super::{StorageArray, U32, Value};
use crate::ir::{ExprId, ExprKind, Literal, Scalar, SourceLoc, Stmt, Type};
use crate::layout::{align_size, array_stride, struct_layout};
use crate::record;

impl StorageArray<U32> {
    /// Writes every member of `value` (a uniform-block struct, or any part of one) at its
    /// uniform-layout offset, the value's first byte at word `word_offset`.
    #[track_caller]
    pub fn write_uniform<V: Value>(self, word_offset: u32, value: V) {
        let caller = std::panic::Location::caller();
        let loc = SourceLoc::new(caller.file(), caller.line(), caller.column());
        store(self.expr(), 4 * word_offset, value.id(), V::TYPE, loc);
    }

    /// Writes `value` where `place` lies in `root`'s uniform layout, `root` starting at word
    /// `word_offset`. `place` is `root` reached through fields (`u.material.albedo`), so
    /// the offset comes from the struct definitions, not from member names.
    #[track_caller]
    pub fn write_uniform_member<R: Value, P: Value>(
        self,
        word_offset: u32,
        root: R,
        place: P,
        value: P,
    ) {
        let caller = std::panic::Location::caller();
        let loc = SourceLoc::new(caller.file(), caller.line(), caller.column());
        match member_offset(root.id(), place.id()) {
            Some(offset) => store(
                self.expr(),
                4 * word_offset + offset,
                value.id(),
                P::TYPE,
                loc,
            ),
            None => record::push_error(format!(
                "{loc}: write_uniform_member: the place is not a field of the root value \
                 (reach it with field accesses from the root)"
            )),
        }
    }
}

/// The byte offset of `place` inside `root`, following `Member` accesses back to `root`.
fn member_offset(root: ExprId, place: ExprId) -> Option<u32> {
    let mut offset = 0;
    let mut at = place;
    while at != root {
        let ExprKind::Member(base, index) = record::expr_kind(at) else {
            return None;
        };
        let Type::Struct(def) = record::expr_type(base) else {
            return None;
        };
        let (_, _, offsets) = struct_layout(def);
        offset += offsets.get(index as usize)?;
        at = base;
    }
    Some(offset)
}

fn literal_u32(v: u32) -> ExprId {
    record::push_expr(ExprKind::Literal(Literal::U32(v)), Type::U32)
}

/// Stores `value` (of type `ty`) at byte `offset` of `array`, one 32-bit word per scalar.
fn store(array: ExprId, offset: u32, value: ExprId, ty: Type, loc: SourceLoc) {
    match ty {
        Type::Scalar(s) => {
            let word = match s {
                Scalar::U32 => value,
                Scalar::F32 | Scalar::I32 => {
                    record::push_expr(ExprKind::Bitcast(Scalar::U32, value), Type::U32)
                }
                Scalar::Bool => {
                    record::push_error(format!(
                        "{loc}: a bool has no uniform layout (uniform blocks hold u32 flags)"
                    ));
                    return;
                }
            };
            let target =
                record::push_expr(ExprKind::Index(array, literal_u32(offset / 4)), Type::U32);
            record::push_stmt(Stmt::Store {
                target,
                value: word,
                loc,
            });
        }
        Type::Vector(n, s) => {
            for i in 0..n {
                let c = record::push_expr(ExprKind::Swizzle(value, vec![i]), Type::Scalar(s));
                store(array, offset + 4 * u32::from(i), c, Type::Scalar(s), loc);
            }
        }
        Type::Matrix(n) => {
            let column = Type::Vector(n, Scalar::F32);
            let (align, size) = align_size(column);
            let stride = size.div_ceil(align) * align;
            for i in 0..u32::from(n) {
                let c = record::push_expr(ExprKind::Index(value, literal_u32(i)), column);
                store(array, offset + stride * i, c, column, loc);
            }
        }
        Type::Struct(def) => {
            let (_, _, offsets) = struct_layout(def);
            for (i, (field, at)) in def.fields.iter().zip(offsets).enumerate() {
                let m = record::push_expr(ExprKind::Member(value, i as u32), field.ty);
                store(array, offset + at, m, field.ty, loc);
            }
        }
        Type::Array(elem, n) => {
            let (_, stride) = array_stride(*elem);
            for i in 0..n {
                let e = record::push_expr(ExprKind::Index(value, literal_u32(i)), *elem);
                store(array, offset + stride * i, e, *elem, loc);
            }
        }
        other => record::push_error(format!("{loc}: {other:?} has no uniform layout to write")),
    }
}
