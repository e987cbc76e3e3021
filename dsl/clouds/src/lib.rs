//! nimbus-clouds: volumetric clouds written in the Nimbus DSL.
//!
//! This crate sits on `nimbus-dsl` as any user's crate would: the model is `#[shader_fn]`s
//! ([`model`]), genera, layers, scenes and quality presets are plain serde data, the effect
//! table ([`Toggle`]) declares each toggle once, [`analysis`] derives the effects a scene can
//! show, and [`catalog`] turns genus × quality pairs into the distinct shader keys they need.

pub mod analysis;
pub mod budget;
pub mod catalog;
pub mod clock;
pub mod engine_depth;
mod error;
mod features;
pub mod formation;
pub mod frame;
pub mod frame_sequence;
pub mod functions;
mod genus;
pub mod key;
mod layer;
pub mod limits;
mod load;
pub mod model;
mod path;
mod quality;
mod scene;
pub mod timeline;
pub mod view_defaults;
pub mod wind;

pub use analysis::{Analysis, analyse};
pub use error::DataError;
pub use features::{FeatureOverrides, Features, Toggle};
pub use functions::{GenusFunctions, HeightFn, WeatherFn, register};
pub use genus::{Genus, MAX_LAYERS, Medium, PhaseSpec};
pub use key::{CloudKey, PhaseKind, PixelOutput, ShadowKey};
pub use layer::{Channel, CloudLayer, DensityProfileParams, MAX_PROFILE_EXPONENT};
pub use limits::{Limit, Origin};
pub use load::{CloudLibrary, load_genus, load_scene, parse_genus, parse_scene};
pub use path::Path;
pub use quality::{MarchSettings, Quality};
pub use scene::ScenePreset;
