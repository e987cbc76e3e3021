//! Fixed-size arrays, `array<T, N>`: the twin of a Rust `[T; N]` (two layer groups, the taps of
//! a filter), indexed by a recorded `u32` so a loop can walk them.

use std::marker::PhantomData;

use super::{ShaderType, U32, Value};
use crate::ir::{ExprId, ExprKind, Type};
use crate::record::push_expr;

/// Shader twin of `[T; N]`.
#[derive(Debug)]
pub struct Array<T: Value, const N: usize> {
    id: ExprId,
    _t: PhantomData<T>,
}

impl<T: Value, const N: usize> Clone for Array<T, N> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Value, const N: usize> Copy for Array<T, N> {}

impl<T: Value, const N: usize> Value for Array<T, N> {
    const TYPE: Type = Type::Array(&T::TYPE, N as u32);
    fn id(self) -> ExprId {
        self.id
    }
    fn from_id(id: ExprId) -> Self {
        Array {
            id,
            _t: PhantomData,
        }
    }
}

impl<T: ShaderType, const N: usize> ShaderType for [T; N] {
    type Dsl = Array<T::Dsl, N>;
}

impl<T: Value, const N: usize> Array<T, N> {
    /// `array[index]`. WGSL clamps (or the driver bounds-checks) an index out of range; the CPU
    /// twin panics on one, so parity tests catch it.
    pub fn at(self, index: impl Into<U32>) -> T {
        T::from_id(push_expr(
            ExprKind::Index(self.id, index.into().id()),
            T::TYPE,
        ))
    }
}

/// `a[i]` in a `#[shader_fn]`: the macro writes `nimbus_dsl::ops::index(a, i)`, which records an
/// index into a recorded array and simply indexes a plain Rust array.
pub trait Indexable<I> {
    type Output;
    fn index_at(self, index: I) -> Self::Output;
}

impl<T: Value, const N: usize, I: Into<U32>> Indexable<I> for Array<T, N> {
    type Output = T;
    fn index_at(self, index: I) -> T {
        self.at(index)
    }
}

macro_rules! rust_index {
    ($($i:ty),*) => {$(
        impl<T: Copy, const N: usize> Indexable<$i> for [T; N] {
            type Output = T;
            fn index_at(self, index: $i) -> T {
                self[index as usize]
            }
        }
    )*};
}
rust_index!(usize, u32);
