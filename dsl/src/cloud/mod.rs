//! Cloud data: layers, genera, scene presets, quality presets and feature toggles. Plain data
//! loaded with serde; the model in [`crate::model`] turns it into shader variants.

pub mod analysis;
mod error;
mod features;
mod genus;
mod layer;
mod load;
mod quality;
mod scene;

pub use analysis::{Analysis, analyse};
pub use error::DataError;
pub use features::{Features, Toggle};
pub use genus::{Genus, MAX_LAYERS, Medium, PhaseSpec};
pub use layer::{Channel, CloudLayer, DensityProfileParams, MAX_PROFILE_EXPONENT};
pub use load::{CloudLibrary, load_genus, load_scene, parse_genus, parse_scene};
pub use quality::{MarchSettings, Quality};
pub use scene::{FeatureOverrides, ScenePreset};
