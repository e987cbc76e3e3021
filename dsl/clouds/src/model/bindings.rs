//! The resources of the cloud passes, each declared once as a [`Binding`] that `#[shader_fn]`s
//! read by name (`CLOUDS.get().march`, `WEATHER.get().sample_level(..)`): no function passes
//! the uniform block or a texture around. A module declares the bindings its code reads, so a
//! variant without shadows has no shadow map. The clouds and shadow passes share the numbering;
//! the runtime binds by [`CloudBinding`], found by slot in codegen's binding description, and
//! every slot names the [`Resource`] a host puts there.

use std::sync::Arc;

use nimbus_dsl::cpu::{Sampler, Texture2d, Texture3d};
use nimbus_dsl::ir::SamplerDesc;
use nimbus_dsl::{Binding, BoundGuard, CpuBindings};

use super::choices::KeyUniforms;
use super::display::DisplayParams;
use super::march::CloudUniforms;
use super::resolve::ResolveParams;
use super::resource::Resource;
use super::scene_depth::SceneDepthParams;

/// Layers, media, march, shadow map, light, sky and camera.
pub static CLOUDS: Binding<CloudUniforms> = Binding::uniform(
    "clouds",
    0,
    0,
    "Layers, media, march, shadow map, light, sky and camera.",
);
/// The cloud block as the host binds it, read under this name by orthographic keys only: each
/// of their pixels shades its ray with [`CLOUDS`] fed a copy of it whose camera stands at the
/// ray's own origin (`model::orthographic`). The same slot as [`CLOUDS`].
pub static CLOUDS_INPUT: Binding<CloudUniforms> = Binding::uniform(
    "clouds_input",
    0,
    0,
    "Layers, media, march, shadow map, light, sky and camera, as bound.",
);
/// Local weather: coverage per channel.
pub static WEATHER: Binding<Texture2d> = Binding::texture(
    "weather_texture",
    0,
    1,
    "Local weather: coverage per channel.",
);
/// Perlin–Worley shape noise (128³, tileable).
pub static SHAPE: Binding<Texture3d> = Binding::texture(
    "shape_texture",
    0,
    2,
    "Perlin–Worley shape noise (128³, tileable).",
);
/// Worley detail noise (32³, tileable).
pub static DETAIL: Binding<Texture3d> = Binding::texture(
    "detail_texture",
    0,
    3,
    "Worley detail noise (32³, tileable).",
);
/// Curl noise for turbulent displacement.
pub static TURBULENCE: Binding<Texture2d> = Binding::texture(
    "turbulence_texture",
    0,
    4,
    "Curl noise for turbulent displacement.",
);
/// Beer shadow map atlas.
pub static SHADOW_MAP: Binding<Texture2d> = Binding::texture(
    "shadow_map",
    0,
    5,
    "Beer shadow map atlas: front depth, mean extinction, max and tail optical depth.",
);
/// Trilinear, repeat.
pub static LINEAR_REPEAT: Binding<Sampler> = Binding::sampler(
    "linear_sampler",
    0,
    6,
    SamplerDesc::LINEAR_REPEAT,
    "Trilinear, repeat.",
);

/// The uber-shader's key uniforms; only the uber-shader declares it.
pub static KEY: Binding<KeyUniforms> = Binding::uniform(
    "key",
    0,
    7,
    "The uber-shader's generation-time choices, read at run time.",
);

/// The engine's depth buffer (`scene-depth` keys only).
pub static SCENE_DEPTH: Binding<Texture2d> = Binding::texture(
    "scene_depth_texture",
    0,
    8,
    "The engine's depth buffer: where its opaque scene stops the march.",
);
/// How the engine's depth buffer encodes distance (`scene-depth` keys only).
pub static SCENE: Binding<SceneDepthParams> = Binding::uniform(
    "scene",
    0,
    9,
    "The engine camera and its depth buffer's encoding.",
);

/// The air table (`model::air_table`): the air's light per direction and distance, drawn by
/// its own pass (keys without `accurate-air-light`).
pub static AIR_TABLE: Binding<Texture2d> = Binding::texture(
    "air_table",
    0,
    10,
    "The air's phase-free light and transmittance per direction and distance.",
);

/// The bake of a baked path (`model::bake`), drawn by its own pass: the slice stack
/// (`model::slices`), the octahedral impostor (`model::impostor`) or the 2D map
/// (`model::blob2d`).
pub static BAKE: Binding<Texture2d> = Binding::texture(
    "cloud_bake",
    0,
    11,
    "The path's bake: the slice stack, the impostor or the 2D map of the clouds around the \
     camera.",
);

/// Offsets, weights, reprojection.
pub static RESOLVE: Binding<ResolveParams> =
    Binding::uniform("resolve", 0, 0, "Offsets, weights, reprojection.");
/// This frame's clouds.
pub static CURRENT: Binding<Texture2d> =
    Binding::texture("current_texture", 0, 1, "This frame's clouds.");
/// Last resolved frame.
pub static HISTORY: Binding<Texture2d> =
    Binding::texture("history_texture", 0, 2, "Last resolved frame.");
/// Nearest, clamp.
pub static NEAREST_CLAMP: Binding<Sampler> = Binding::sampler(
    "nearest_sampler",
    0,
    3,
    SamplerDesc::NEAREST_CLAMP,
    "Nearest, clamp.",
);
/// Bilinear, clamp.
pub static LINEAR_CLAMP: Binding<Sampler> = Binding::sampler(
    "linear_sampler",
    0,
    4,
    SamplerDesc::LINEAR_CLAMP,
    "Bilinear, clamp.",
);

/// Resolution, exposure, alpha and row order of the display pass.
pub static DISPLAY: Binding<DisplayParams> = Binding::uniform(
    "display",
    0,
    0,
    "Resolution, exposure, alpha and row order.",
);
/// The HDR image to display (the cloud or resolve pass's target).
pub static DISPLAY_SOURCE: Binding<Texture2d> = Binding::texture(
    "source_texture",
    0,
    1,
    "The HDR image to display (the cloud or resolve pass's target).",
);
/// Nearest, clamp: one source texel per pixel.
pub static DISPLAY_SAMPLER: Binding<Sampler> = Binding::sampler(
    "source_sampler",
    0,
    2,
    SamplerDesc::NEAREST_CLAMP,
    "Nearest, clamp: one source texel per pixel.",
);

/// Where the `sun_light` kernel writes the completed cloud block: a storage buffer that the
/// host then binds as [`CLOUDS`] in the shadow and cloud passes.
pub const SUN_LIGHT_BLOCK: (u32, u32) = (0, 1);

/// A pass's slots, each declared once with the binding it is and the [`Resource`] a host puts
/// there: `slot`, `at` and `resource` all come from this one list.
macro_rules! pass_bindings {
    (
        $(#[$doc:meta])*
        pub enum $name:ident {
            $($(#[$vdoc:meta])* $variant:ident = $slot:expr => $resource:ident,)+
        }
    ) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum $name {
            $($(#[$vdoc])* $variant,)+
        }

        impl $name {
            pub const GROUP: u32 = 0;
            pub const ALL: [$name; [$(stringify!($variant)),+].len()] = [$($name::$variant),+];

            /// `(group, binding)`, from the binding's one declaration.
            pub fn slot(self) -> (u32, u32) {
                match self {
                    $($name::$variant => $slot,)+
                }
            }

            /// The binding index in [`Self::GROUP`].
            pub fn binding(self) -> u32 {
                self.slot().1
            }

            /// The binding at `(group, binding)`.
            pub fn at(group: u32, binding: u32) -> Option<$name> {
                Self::ALL.into_iter().find(|b| b.slot() == (group, binding))
            }

            /// What a host binds there.
            pub fn resource(self) -> Resource {
                match self {
                    $($name::$variant => Resource::$resource,)+
                }
            }
        }
    };
}

pass_bindings! {
    /// What the runtime binds at each slot of the cloud passes (clouds and shadow).
    pub enum CloudBinding {
        Uniforms = CLOUDS.slot() => Pair,
        Weather = WEATHER.slot() => Weather,
        Shape = SHAPE.slot() => Shape,
        Detail = DETAIL.slot() => Detail,
        Turbulence = TURBULENCE.slot() => Turbulence,
        ShadowMap = SHADOW_MAP.slot() => ShadowAtlas,
        Sampler = LINEAR_REPEAT.slot() => LinearRepeat,
        /// The uber-shader's key uniforms ([`KEY`]).
        Key = KEY.slot() => Key,
        /// The engine's depth buffer ([`SCENE_DEPTH`]).
        SceneDepth = SCENE_DEPTH.slot() => SceneDepth,
        /// Its encoding and camera ([`SCENE`]).
        Scene = SCENE.slot() => Scene,
        /// The air table pass's target ([`AIR_TABLE`]).
        AirTable = AIR_TABLE.slot() => AirTable,
        /// The bake pass's target ([`BAKE`]).
        Bake = BAKE.slot() => CloudBake,
    }
}

pass_bindings! {
    /// What the runtime binds at each slot of the temporal resolve pass.
    pub enum ResolveBinding {
        Params = RESOLVE.slot() => Resolve,
        Current = CURRENT.slot() => CloudsHdr,
        History = HISTORY.slot() => HistoryRead,
        Nearest = NEAREST_CLAMP.slot() => NearestClamp,
        Linear = LINEAR_CLAMP.slot() => LinearClamp,
    }
}

pass_bindings! {
    /// What an engine binds at each slot of the display pass.
    pub enum DisplayBinding {
        Params = DISPLAY.slot() => Display,
        Source = DISPLAY_SOURCE.slot() => Shown,
        Sampler = DISPLAY_SAMPLER.slot() => NearestClamp,
    }
}

pass_bindings! {
    /// What an engine binds at each slot of the `sun_light` kernel.
    pub enum SunLightBinding {
        /// The cloud block as the host filled it (with `light.sun_direction` set).
        Inputs = CLOUDS.slot() => PairInputs,
        /// The same block with what the sun decides filled in.
        Block = SUN_LIGHT_BLOCK => Pair,
    }
}

/// The textures of the cloud passes on the CPU, shared (not copied) with every binding.
#[derive(Clone, Debug)]
pub struct CloudTextures {
    pub weather: Arc<Texture2d>,
    pub shape: Arc<Texture3d>,
    pub detail: Arc<Texture3d>,
    pub turbulence: Arc<Texture2d>,
    /// Beer shadow map texels: front depth (m), mean extinction, max optical depth, tail.
    pub shadow: Arc<Texture2d>,
}

impl CloudTextures {
    /// A shadow map that shadows nothing (one texel, no optical depth), for callers that do not
    /// march shadows.
    pub fn no_shadow() -> Arc<Texture2d> {
        Arc::new(Texture2d {
            size: [1, 1],
            texels: vec![glam::Vec4::ZERO],
        })
    }

    /// Binds `uniforms`, these textures, the air table drawn for `uniforms` and the repeating
    /// sampler for the CPU twins of the cloud model on this thread, as the runtime's bind group
    /// does for the GPU.
    pub fn bind(&self, uniforms: CloudUniforms) -> BoundGuard {
        CpuBindings::new()
            .set(&CLOUDS, uniforms)
            .set(&WEATHER, self.weather.clone())
            .set(&SHAPE, self.shape.clone())
            .set(&DETAIL, self.detail.clone())
            .set(&TURBULENCE, self.turbulence.clone())
            .set(&SHADOW_MAP, self.shadow.clone())
            .set(&AIR_TABLE, super::air_table::air_table_texture(&uniforms))
            .set(&LINEAR_REPEAT, Sampler::default())
            .bind()
    }
}
