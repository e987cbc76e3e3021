//! What a host puts in each binding slot of the cloud passes, named once: the runtime binds by
//! it, an engine package describes every slot with it (`nimbus-package.json`: its id, its kind
//! and what it holds) and the package's JavaScript hosts bind by the id, from one table of the
//! resources they own. A pass's slots map to these in [`super::bindings`].

use schemars::JsonSchema;
use serde::Serialize;

/// One resource a pass binds. Serialised as its stable id (`"shadow_atlas"`), the same in every
/// package and every host.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Resource {
    /// The pair's cloud block (`uniforms/<pair>.json`), completed by the `sun_light` kernel
    /// where a package has one.
    Pair,
    /// The cloud block as the host fills it before the `sun_light` kernel completes it.
    PairInputs,
    /// The weather texture (coverage per channel).
    Weather,
    /// The 3D shape noise.
    Shape,
    /// The 3D detail noise.
    Detail,
    /// The 2D curl noise.
    Turbulence,
    /// The shadow pass's target.
    ShadowAtlas,
    /// The air table pass's target.
    AirTable,
    /// The bake pass's target (the baked paths).
    CloudBake,
    /// Linear filtering, repeating.
    LinearRepeat,
    /// The uber-shader's key uniforms (never in a package: packages hold specialised keys).
    Key,
    /// The engine's depth texture, given with each frame.
    SceneDepth,
    /// The engine camera and its depth encoding (`uniforms/scene.json`).
    Scene,
    /// The resolve pass's block (`uniforms/resolve.json`).
    Resolve,
    /// The cloud pass's target.
    CloudsHdr,
    /// The history target written last frame.
    HistoryRead,
    /// Nearest filtering, clamped.
    NearestClamp,
    /// Linear filtering, clamped.
    LinearClamp,
    /// The display pass's block (`uniforms/display.json`).
    Display,
    /// What the display pass shows: the history target resolve wrote, or the cloud target.
    Shown,
}

/// How a host provides a [`Resource`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, JsonSchema)]
pub enum ResourceKind {
    /// A uniform buffer whose bytes a uniform file describes.
    #[serde(rename = "uniform block")]
    UniformBlock,
    /// A texture file of the package.
    #[serde(rename = "texture")]
    Texture,
    /// A render target the host creates (`targets` in the package description).
    #[serde(rename = "target")]
    Target,
    /// A sampler whose state the layout or manifest gives.
    #[serde(rename = "sampler")]
    Sampler,
    /// The engine's own depth buffer.
    #[serde(rename = "engine depth")]
    EngineDepth,
}

impl Resource {
    pub const ALL: [Resource; 20] = [
        Resource::Pair,
        Resource::PairInputs,
        Resource::Weather,
        Resource::Shape,
        Resource::Detail,
        Resource::Turbulence,
        Resource::ShadowAtlas,
        Resource::AirTable,
        Resource::CloudBake,
        Resource::LinearRepeat,
        Resource::Key,
        Resource::SceneDepth,
        Resource::Scene,
        Resource::Resolve,
        Resource::CloudsHdr,
        Resource::HistoryRead,
        Resource::NearestClamp,
        Resource::LinearClamp,
        Resource::Display,
        Resource::Shown,
    ];

    /// Its stable id, as the package description spells it (serde's name for the variant).
    pub fn id(self) -> &'static str {
        match self {
            Resource::Pair => "pair",
            Resource::PairInputs => "pair_inputs",
            Resource::Weather => "weather",
            Resource::Shape => "shape",
            Resource::Detail => "detail",
            Resource::Turbulence => "turbulence",
            Resource::ShadowAtlas => "shadow_atlas",
            Resource::AirTable => "air_table",
            Resource::CloudBake => "cloud_bake",
            Resource::LinearRepeat => "linear_repeat",
            Resource::Key => "key",
            Resource::SceneDepth => "scene_depth",
            Resource::Scene => "scene",
            Resource::Resolve => "resolve",
            Resource::CloudsHdr => "clouds_hdr",
            Resource::HistoryRead => "history_read",
            Resource::NearestClamp => "nearest_clamp",
            Resource::LinearClamp => "linear_clamp",
            Resource::Display => "display",
            Resource::Shown => "shown",
        }
    }

    /// How a host provides it.
    pub fn kind(self) -> ResourceKind {
        match self {
            Resource::Pair | Resource::Key | Resource::Scene | Resource::Resolve => {
                ResourceKind::UniformBlock
            }
            Resource::Display | Resource::PairInputs => ResourceKind::UniformBlock,
            Resource::Weather | Resource::Shape | Resource::Detail | Resource::Turbulence => {
                ResourceKind::Texture
            }
            Resource::ShadowAtlas
            | Resource::AirTable
            | Resource::CloudBake
            | Resource::CloudsHdr
            | Resource::HistoryRead
            | Resource::Shown => ResourceKind::Target,
            Resource::LinearRepeat | Resource::NearestClamp | Resource::LinearClamp => {
                ResourceKind::Sampler
            }
            Resource::SceneDepth => ResourceKind::EngineDepth,
        }
    }

    /// What it holds, in words, for the package description.
    pub fn holds(self) -> &'static str {
        match self {
            Resource::Pair => {
                "uniforms/<pair>.json (the sun_light kernel writes it as a storage buffer where \
                 a package has that pass: its buffer then needs storage and uniform usage)"
            }
            Resource::PairInputs => {
                "uniforms/<pair>.json as the host fills it, light.sun_direction set"
            }
            Resource::Weather => "textures: weather",
            Resource::Shape => "textures: shape",
            Resource::Detail => "textures: detail",
            Resource::Turbulence => "textures: turbulence",
            Resource::ShadowAtlas => "the shadow pass's target",
            Resource::AirTable => "the air pass's target",
            Resource::CloudBake => "the bake pass's target",
            Resource::LinearRepeat => "linear, repeat",
            Resource::Key => "the uber-shader's key uniforms",
            Resource::SceneDepth => {
                "the engine's own depth buffer (its depth texture, read as float, one texel per \
                 output pixel), given with each frame"
            }
            Resource::Scene => {
                "uniforms/scene.json: the engine camera's view-projection, forward direction and \
                 depth encoding, set with the camera"
            }
            Resource::Resolve => "uniforms/resolve.json",
            Resource::CloudsHdr => "the cloud pass's target",
            Resource::HistoryRead => "the history target written last frame",
            Resource::NearestClamp => "nearest, clamp",
            Resource::LinearClamp => "linear, clamp",
            Resource::Display => "uniforms/display.json",
            Resource::Shown => {
                "the history target resolve wrote, or clouds_hdr when there is no resolve"
            }
        }
    }
}
