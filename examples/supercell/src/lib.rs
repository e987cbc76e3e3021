//! A cloud genus of a user's own, written outside Nimbus: a supercell thunderstorm whose shape
//! over height and density profile are `#[shader_fn]`s of this crate.
//!
//! Nimbus' model asks each genus for three functions ([`nimbus_clouds::functions`]): the
//! weather signal, the coverage shape over height, the density profile over height. This crate
//! writes two of them. Each runs on the CPU (the stability catalogue and the parity tests call
//! it) and is recorded into the genus' shaders, which are named after it
//! (`...-supercell_shape-supercell_profile`) and validated for every target like the
//! built-in ones.

use std::path::Path;

use glam::Vec4;
use nimbus_clouds::model::genus_fns::exponential_profile;
use nimbus_clouds::model::layers::LayerGroup;
use nimbus_clouds::{DataError, Genus, HeightFn, height_fn, load_genus, register};
use nimbus_dsl::prelude::*;

/// The silhouette of a supercell over its height fraction `eta`: a flat base (full width within
/// the lowest 2 % of the layer), a tower narrowing slowly upwards, an anvil that spreads to
/// twice the tower's width between 66 % and 84 % of the height and is sheared off flat at
/// 90 % (the tropopause), and above it the overshooting top: the updraught's core alone,
/// narrowing to nothing at the top of the layer. The layer's `shape_altering_bias` scales the
/// anvil's spread (1: 2.5 times the tower's width where the anvil begins).
///
/// The value scales the coverage threshold (`1 − shape·coverage`): where it is large, weaker
/// weather signal still makes cloud, so the anvil covers far more ground than the tower.
#[shader_fn]
pub fn supercell_shape(eta: Vec4, layers: LayerGroup) -> Vec4 {
    let base = (eta / 0.02).saturate();
    let tower =
        (Vec4::splat(0.8) - eta * 0.2) * (Vec4::ONE - smoothstep(Vec4::splat(0.9), Vec4::ONE, eta));
    let anvil = smoothstep(Vec4::splat(0.66), Vec4::splat(0.84), eta)
        * (Vec4::ONE - smoothstep(Vec4::splat(0.86), Vec4::splat(0.9), eta))
        * layers.shape_altering_bias
        * 1.6;
    base * tower.max(anvil)
}

/// Density over height: the layer's own exponential profile (a built-in `#[shader_fn]`,
/// called like any other function) times the water content of the storm: dense rain and cloud
/// water below, thinning to 35 % in the anvil, where the water is ice spread over a far larger
/// volume.
#[shader_fn]
pub fn supercell_profile(eta: Vec4, layers: LayerGroup) -> Vec4 {
    let ice = smoothstep(Vec4::splat(0.55), Vec4::splat(0.85), eta);
    exponential_profile(eta, layers) * (Vec4::ONE - ice * 0.65)
}

/// The shape function, as genus files and keys see it.
pub const SHAPE: HeightFn = height_fn!(
    supercell_shape,
    "flat base, tower, anvil spreading to 2.5x between 66% and 84% of the height, overshooting top"
);

/// The profile function.
pub const PROFILE: HeightFn = height_fn!(
    supercell_profile,
    "the layer's exponential profile times the storm's water: 100% in the tower, 35% in the anvil"
);

/// Lets genus files name this crate's functions (`functions = { shape = "supercell_shape" }`).
pub fn register_functions() -> Result<(), nimbus_clouds::functions::RegisterError> {
    register(SHAPE)?;
    register(PROFILE)
}

/// The genus file beside this crate's manifest.
pub fn genus_file() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("supercell.toml")
}

/// The supercell genus: its functions registered, its file loaded and validated.
pub fn genus() -> Result<Genus, Box<dyn std::error::Error>> {
    register_functions()?;
    let genus: Result<Genus, DataError> = load_genus(&genus_file());
    Ok(genus?)
}
