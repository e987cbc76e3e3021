//! A scene's cloud formation: the probabilities and pace of the formation automaton
//! ([`crate::model::formation`]) that makes clouds appear, grow and dissolve over the timeline.

use serde::{Deserialize, Serialize};

use crate::model::formation::{FormationParams, threshold};

/// The `[formation]` table of a scene. Each probability is per step of the automaton.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Formation {
    /// Chance per step that vapour returns to a cell where the weather map is moist.
    #[serde(default = "default_humidity")]
    pub humidity: f32,
    /// Chance per step that a humid cell starts condensing by itself (new clouds).
    #[serde(default = "default_activation")]
    pub activation: f32,
    /// Chance per step that a cloudy cell dissipates.
    #[serde(default = "default_extinction")]
    pub extinction: f32,
    /// Seconds per step: with the probabilities, how fast clouds grow and dissolve.
    #[serde(default = "default_step_seconds")]
    pub step_seconds: f32,
    /// Cells per side of the grid over one weather tile (100 km): a multiple of 8.
    #[serde(default = "default_cells")]
    pub cells: u32,
    /// Seed of the automaton's random draws.
    #[serde(default = "default_seed")]
    pub seed: u32,
}

// Vapour returns slowly and condensation rarely starts by itself, so a moist area fills with
// vapour, clouds over when a front sweeps through it, and clears again as its cloud dissipates
// (about 50 steps); faster supply keeps the same areas clouded all the time.
fn default_humidity() -> f32 {
    0.03
}
fn default_activation() -> f32 {
    0.0002
}
fn default_extinction() -> f32 {
    0.02
}
fn default_step_seconds() -> f32 {
    20.0
}
fn default_cells() -> u32 {
    128
}
fn default_seed() -> u32 {
    1
}

impl Default for Formation {
    fn default() -> Self {
        Formation {
            humidity: default_humidity(),
            activation: default_activation(),
            extinction: default_extinction(),
            step_seconds: default_step_seconds(),
            cells: default_cells(),
            seed: default_seed(),
        }
    }
}

/// How far a cell's density follows its neighbourhood's cloud per step: about ten steps to
/// settle, so a cell's flicker does not show.
pub const RELAX: f32 = 0.1;

/// Densities the weather is gated between (none below, all above).
pub const GATE: (f32, f32) = (0.15, 0.6);

impl Formation {
    /// The automaton's parameters (step 0, blend 0).
    pub fn params(&self) -> FormationParams {
        FormationParams {
            step: 0,
            seed: self.seed,
            activation: threshold(self.activation),
            extinction: threshold(self.extinction),
            relax: RELAX,
            gate_low: GATE.0,
            gate_high: GATE.1,
            blend: 0.0,
        }
    }

    /// The step the automaton is at `seconds` into the timeline, and how far towards the next.
    pub fn step_at(&self, seconds: f64) -> (u32, f32) {
        let steps = (seconds.max(0.0) / f64::from(self.step_seconds)).max(0.0);
        (steps.floor() as u32, steps.fract() as f32)
    }
}
