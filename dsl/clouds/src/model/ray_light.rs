//! A view ray's light as the march gathers it, and one lit sample added to it. Written once
//! so that the march can call it from where its path wants the light: the volume from the
//! outer loop, which lights the samples its inner loop found (a SIMD group lights its lanes'
//! samples together), the slices path from its single loop, whose light is the texture read
//! that came with the density (nothing to gather: two loops there only cost bookkeeping). The
//! step's integration and the early termination ([`add_step`]) serve the 2D map's march too.

use glam::{Vec3, Vec4};

use crate::key::CloudKey;
use nimbus_dsl::prelude::*;

use super::bindings::CLOUDS;
use super::choices::{DIFFUSION, GROUND_BOUNCE, gate};
use super::march::{
    MarchResult, OctavePhases, one_minus_exp_over, sample_source, sun_optical_depth,
    vertical_optical_depth,
};

/// What a view ray has gathered so far.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct RayLight {
    /// In-scattered radiance.
    pub radiance: Vec3,
    /// Transmittance from the camera to the last sample; exactly 0 once the ray has ended in
    /// cloud (early termination).
    pub transmittance: f32,
    /// Weighted sum of the samples' distances (a march weighs each by the transmittance in
    /// front of it), and the weights' sum: their quotient is the front depth.
    pub depth_sum: f32,
    pub weight_sum: f32,
}

/// `gathered` with the sample of density `rho` at `p` (altitude `h`, distance `t` along the
/// view ray, standing for a step of `step` metres and `footprint` metres across) added: its
/// light to the sun and to the ground and sky (the secondary marches from their `offset`, or
/// the slices' optical depths read into `first`), its source term, integrated over the step,
/// and the early termination when the transmittance falls to the preset's minimum
/// ([`add_step`]).
#[shader_fn]
#[expect(
    clippy::too_many_arguments,
    reason = "a shader function takes what a sample knows as plain arguments"
)]
#[expect(
    clippy::if_same_then_else,
    reason = "the march down runs once for either of two key gates: one `if` per gate is how a \
              shader function branches on the key"
)]
#[expect(
    clippy::collapsible_if,
    reason = "the outer `if` is a generation-time choice (the path), the inner one a gate: \
              `&&` cannot join a Rust `bool` to a gate's switch"
)]
pub fn lit_sample(
    gathered: RayLight,
    rho: f32,
    p: Vec3,
    h: f32,
    first: Vec4,
    t: f32,
    step: f32,
    offset: f32,
    footprint: f32,
    cos_theta: f32,
    phases: OctavePhases,
    view_up: f32,
    #[spec] key: CloudKey,
) -> RayLight {
    let l = CLOUDS.get().light;
    let sigma_t = rho * (l.scattering_coefficient + l.absorption_coefficient);
    let tau_sun = if key.reads_slices() {
        first.y
    } else {
        sun_optical_depth(p, h, offset, footprint, key)
    };
    // The optical depth down to the base: the ground's light comes through it, and the
    // diffusion's slab ends there.
    let mut tau_ground = if key.reads_slices() { first.z } else { 0.0f32 };
    if !key.reads_slices() {
        if gate(key, GROUND_BOUNCE) {
            tau_ground = vertical_optical_depth(p, h, -1.0, offset, footprint, key);
        } else if gate(key, DIFFUSION) {
            tau_ground = vertical_optical_depth(p, h, -1.0, offset, footprint, key);
        }
    }
    let mut tau_up = if key.reads_slices() { first.w } else { 0.0f32 };
    if !key.reads_slices() {
        if gate(key, DIFFUSION) {
            tau_up = vertical_optical_depth(p, h, 1.0, offset, footprint, key);
        }
    }
    let source = sample_source(
        rho, h, tau_sun, tau_up, tau_ground, cos_theta, phases, view_up, key,
    );
    add_step(gathered, source, sigma_t, step, t)
}

/// `gathered` with a step of `step` metres at distance `t`, of extinction `sigma_t` and source
/// term `source`, added: the march's and the 2D map's samples alike.
#[shader_fn]
pub fn add_step(gathered: RayLight, source: Vec3, sigma_t: f32, step: f32, t: f32) -> RayLight {
    // Energy-conserving integration over the step (Hillaire 2016, §5.6.3):
    // S·(1 − e^(−σt·Δ))/σt, written as S·Δ·f(σt·Δ) so thin media stay exact.
    let step_transmittance = (-sigma_t * step).exp();
    let integral = source * (step * one_minus_exp_over(sigma_t * step));
    early_termination(RayLight {
        radiance: gathered.radiance + integral * gathered.transmittance,
        transmittance: gathered.transmittance * step_transmittance,
        depth_sum: gathered.depth_sum + t * gathered.transmittance,
        weight_sum: gathered.weight_sum + gathered.transmittance,
    })
}

/// `gathered` ended in cloud once its transmittance has fallen to the preset's minimum: the
/// march's, the 2D map's and the mesh's rays alike.
#[shader_fn]
pub fn early_termination(gathered: RayLight) -> RayLight {
    let m = CLOUDS.get().march;
    let mut radiance = gathered.radiance;
    let mut transmittance = gathered.transmittance;
    if transmittance <= m.min_transmittance {
        // Early termination treats the rest of the ray as more of the same cloud: its light
        // is extrapolated (the radiance so far is 1 − T of the total) and nothing behind
        // shows through. Cutting the ray at T = 0.1 and compositing the sky behind at 10 %
        // made `low` 64 % too bright inside a cloud (the study).
        radiance *= 1.0 / (1.0 - transmittance).max(1e-6);
        transmittance = 0.0;
    }
    RayLight {
        radiance,
        transmittance,
        depth_sum: gathered.depth_sum,
        weight_sum: gathered.weight_sum,
    }
}

/// The march's result from what the ray gathered and the density evaluations it made: the
/// front depth is the weighted mean distance of its samples (-1: none).
#[shader_fn]
pub fn gathered_result(gathered: RayLight, samples: f32) -> MarchResult {
    MarchResult {
        radiance: gathered.radiance,
        transmittance: gathered.transmittance,
        front_depth: select(
            -1.0,
            gathered.depth_sum / gathered.weight_sum.max(1e-20),
            gathered.weight_sum > 0.0,
        ),
        samples,
    }
}

/// Density evaluations a lit sample of the volume makes in its marches down and up (the
/// ground's steps, for each the key takes), counted by the instrumented variant.
#[shader_fn]
#[expect(
    clippy::if_same_then_else,
    reason = "one `if` per gate is how a shader function branches on the key"
)]
pub fn ground_samples(#[spec] key: CloudKey) -> f32 {
    let m = CLOUDS.get().march;
    let mut count = 0.0f32;
    if gate(key, GROUND_BOUNCE) {
        count += m.ground_steps as f32;
    } else if gate(key, DIFFUSION) {
        count += m.ground_steps as f32;
    }
    if gate(key, DIFFUSION) {
        count += m.ground_steps as f32;
    }
    count
}
