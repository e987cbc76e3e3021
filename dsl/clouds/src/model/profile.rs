//! Vertical density profile of a cloud layer.
//!
//! Over the height fraction η ∈ [0, 1] inside a layer the density is scaled by
//! `a·e^(b·η) + c·η + d` (the exponential-plus-linear profile of @takram/three-clouds; default
//! a = 0, b = 0, c = 0.75, d = 0.25: denser towards the top, as in cumulus).

use nimbus_dsl::prelude::*;

/// Density profile `a·e^(b·η) + c·η + d` at height fraction `eta`.
///
/// The exponential term is skipped when `a` is 0, so a huge `b` cannot turn `0·∞` into NaN.
#[shader_fn]
pub fn density_profile(eta: f32, a: f32, b: f32, c: f32, d: f32) -> f32 {
    let exp_term = select(0.0, a * (b * eta).exp(), a != 0.0);
    exp_term + c * eta + d
}
