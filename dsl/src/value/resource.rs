//! Textures, samplers and storage buffers. Their CPU twins live in [`crate::cpu`].

use super::{F32, I32, IVec2, ShaderType, U32, Value, Vec2, Vec3, Vec4};
use crate::ir::{ExprId, ExprKind, SampleKind, Stmt, Type};
use crate::record::{push_expr, push_stmt};

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident, $cpu:ty, $ty:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name(ExprId);

        impl Value for $name {
            const TYPE: Type = $ty;
            fn id(self) -> ExprId {
                self.0
            }
            fn from_id(id: ExprId) -> Self {
                Self(id)
            }
        }

        impl ShaderType for $cpu {
            type Dsl = $name;
        }
    };
}

handle!(
    /// A filterable `texture_2d<f32>`.
    Texture2d, crate::cpu::Texture2d, Type::Texture2d
);
handle!(
    /// A filterable `texture_3d<f32>`.
    Texture3d, crate::cpu::Texture3d, Type::Texture3d
);
handle!(
    /// A filtering sampler.
    Sampler, crate::cpu::Sampler, Type::Sampler
);

fn sample(texture: ExprId, sampler: Sampler, coords: ExprId, kind: SampleKind) -> Vec4 {
    Vec4::from_id(push_expr(
        ExprKind::Sample {
            texture,
            sampler: sampler.id(),
            coords,
            kind,
        },
        Vec4::TYPE,
    ))
}

impl Texture2d {
    /// `textureSampleLevel`: explicit level of detail, valid in every stage.
    pub fn sample_level(
        self,
        sampler: Sampler,
        uv: impl Into<Vec2>,
        level: impl Into<F32>,
    ) -> Vec4 {
        let level = level.into().id();
        sample(self.0, sampler, uv.into().id(), SampleKind::Level(level))
    }

    /// `textureSample`: implicit derivatives, so only valid in fragment shaders.
    pub fn sample(self, sampler: Sampler, uv: impl Into<Vec2>) -> Vec4 {
        sample(self.0, sampler, uv.into().id(), SampleKind::Implicit)
    }

    /// `textureLoad`: the texel at integer coordinates `texel` of mip `level`, with no sampler,
    /// so the texture may be unfilterable (a binding only loaded from is declared so).
    pub fn load(self, texel: impl Into<IVec2>, level: impl Into<I32>) -> Vec4 {
        Vec4::from_id(push_expr(
            ExprKind::Load {
                texture: self.0,
                texel: texel.into().id(),
                level: level.into().id(),
            },
            Vec4::TYPE,
        ))
    }
}

impl Texture3d {
    /// `textureSampleLevel`: explicit level of detail, valid in every stage.
    pub fn sample_level(
        self,
        sampler: Sampler,
        uvw: impl Into<Vec3>,
        level: impl Into<F32>,
    ) -> Vec4 {
        let level = level.into().id();
        sample(self.0, sampler, uvw.into().id(), SampleKind::Level(level))
    }

    /// `textureSample`: implicit derivatives, so only valid in fragment shaders.
    pub fn sample(self, sampler: Sampler, uvw: impl Into<Vec3>) -> Vec4 {
        sample(self.0, sampler, uvw.into().id(), SampleKind::Implicit)
    }
}

/// Scalars that can be elements of a [`StorageArray`].
pub trait StorageElement: Value {}
impl StorageElement for F32 {}
impl StorageElement for U32 {}
impl StorageElement for I32 {}

/// A runtime-sized `array<T>` in a storage buffer, as used by compute kernels (the parity
/// harness reads inputs and writes outputs through these).
#[derive(Clone, Copy, Debug)]
pub struct StorageArray<T: StorageElement> {
    id: ExprId,
    _elem: std::marker::PhantomData<T>,
}

impl<T: StorageElement> StorageArray<T> {
    pub(crate) fn from_id(id: ExprId) -> Self {
        Self {
            id,
            _elem: std::marker::PhantomData,
        }
    }

    /// The expression naming the array.
    pub(crate) fn expr(self) -> ExprId {
        self.id
    }

    /// `array[index]`.
    pub fn get(self, index: impl Into<U32>) -> T {
        T::from_id(push_expr(
            ExprKind::Index(self.id, index.into().id()),
            T::TYPE,
        ))
    }

    /// `array[index] = value;` (the array must be bound read-write; naga rejects it otherwise).
    #[track_caller]
    pub fn set(self, index: impl Into<U32>, value: impl Into<T>) {
        let caller = std::panic::Location::caller();
        let target = push_expr(ExprKind::Index(self.id, index.into().id()), T::TYPE);
        push_stmt(Stmt::Store {
            target,
            value: value.into().id(),
            loc: crate::ir::SourceLoc::new(caller.file(), caller.line(), caller.column()),
        });
    }
}
