//! The key's choices as the model reads them: fixed at generation time in a specialised shader,
//! read from a uniform block in the uber-shader.
//!
//! The model asks `if gate(key, SHADOWS)`, `for o in 0..key_count(key, OCTAVES)` and
//! `phase_is(key, DUAL_LOBE)`. Each is a hand-written twin pair (the shape `#[shader_fn]`
//! generates): the CPU twin answers from the key; the shader twin answers with a Rust value,
//! so only the taken arm is recorded, unless the key is the uber key, where it reads
//! [`KEY`](super::bindings::KEY) and the `if` becomes a run-time branch. One model source thus gives both shaders
//! that `bench-frames --uber` compares.

use nimbus_dsl::control::Switch;
use nimbus_dsl::ops;
use nimbus_dsl::prelude::*;
use nimbus_dsl::shader::{Bool, U32};

use super::bindings::KEY;

use crate::Toggle;
use crate::key::{CloudKey, PhaseKind};

/// The uber-shader's generation-time choices, as uniforms.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct KeyUniforms {
    /// Bit `i` set when toggle `Toggle::ALL[i]` is on.
    pub toggles: u32,
    pub octaves: u32,
    /// `PhaseKind` as its index in [`PhaseKind::ALL`].
    pub phase: u32,
    pub groups: u32,
}

impl KeyUniforms {
    /// The uniforms that make the uber-shader compute what `key`'s shader computes.
    pub fn of(key: &CloudKey) -> KeyUniforms {
        KeyUniforms {
            toggles: Toggle::ALL
                .iter()
                .enumerate()
                .filter(|(_, t)| t.get(&key.features))
                .map(|(i, _)| 1u32 << i)
                .sum(),
            octaves: key.features.octaves,
            phase: key.phase.index(),
            groups: key.groups,
        }
    }
}

pub const SHAPE_DETAIL: Toggle = Toggle::ShapeDetail;
pub const TURBULENCE: Toggle = Toggle::Turbulence;
pub const LIGHT_SHAFTS: Toggle = Toggle::LightShafts;
pub const HAZE: Toggle = Toggle::Haze;
pub const SHADOWS: Toggle = Toggle::Shadows;
pub const GROUND_BOUNCE: Toggle = Toggle::GroundBounce;
pub const DIFFUSION: Toggle = Toggle::Diffusion;
pub const POWDER: Toggle = Toggle::Powder;
pub const SUN_SKY_LIGHT: Toggle = Toggle::AccurateSunSkyLight;
pub const FLAT_HIGH_LAYER: Toggle = Toggle::FlatHighLayer;
pub const SCENE_DEPTH: Toggle = Toggle::SceneDepth;
pub const ORTHOGRAPHIC: Toggle = Toggle::Orthographic;
pub const UNTILED_WEATHER: Toggle = Toggle::UntiledWeather;
pub const ACCURATE_AIR_LIGHT: Toggle = Toggle::AccurateAirLight;

pub const HENYEY_GREENSTEIN: PhaseKind = PhaseKind::HenyeyGreenstein;
pub const DUAL_LOBE: PhaseKind = PhaseKind::DualLobe;
pub const APPROXIMATE_MIE: PhaseKind = PhaseKind::ApproximateMie;
pub const ICE_CRYSTAL: PhaseKind = PhaseKind::IceCrystal;

/// A count the key fixes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyCount {
    Octaves,
    Groups,
}
pub const OCTAVES: KeyCount = KeyCount::Octaves;
pub const GROUPS: KeyCount = KeyCount::Groups;

/// Whether `toggle` is on (CPU twin).
pub fn gate(key: CloudKey, toggle: Toggle) -> bool {
    toggle.get(&key.features)
}

/// The number the key gives for `what` (CPU twin).
pub fn key_count(key: CloudKey, what: KeyCount) -> u32 {
    match what {
        KeyCount::Octaves => key.features.octaves,
        KeyCount::Groups => key.groups,
    }
}

/// Whether the key's phase function is `kind` (CPU twin).
pub fn phase_is(key: CloudKey, kind: PhaseKind) -> bool {
    key.phase == kind
}

fn bit_set(word: U32, bit: u32) -> Bool {
    ops::ne(word & (1u32 << bit), 0u32)
}

#[doc(hidden)]
pub use gate::shader as __shader_twin_gate;

/// Shader twin of [`gate()`](fn@gate).
pub mod gate {
    use super::*;

    pub fn shader(key: CloudKey, toggle: Toggle) -> Switch {
        // The engine's depth and its camera's projection are the host's, not run-time choices:
        // the uber-shader has neither.
        if !key.uber || matches!(toggle, Toggle::SceneDepth | Toggle::Orthographic) {
            return Switch::Fixed(super::gate(key, toggle));
        }
        let bit = Toggle::ALL.iter().position(|t| *t == toggle).unwrap_or(0) as u32;
        Switch::Dynamic(bit_set(KEY.read().toggles, bit))
    }
}

#[doc(hidden)]
pub use key_count::shader as __shader_twin_key_count;

/// Shader twin of [`key_count()`](fn@key_count).
pub mod key_count {
    use super::*;

    pub fn shader(key: CloudKey, what: KeyCount) -> U32 {
        if !key.uber {
            return U32::from(super::key_count(key, what));
        }
        let k = KEY.read();
        match what {
            KeyCount::Octaves => k.octaves,
            KeyCount::Groups => k.groups,
        }
    }
}

#[doc(hidden)]
pub use phase_is::shader as __shader_twin_phase_is;

/// Shader twin of [`phase_is()`](fn@phase_is).
pub mod phase_is {
    use super::*;

    pub fn shader(key: CloudKey, kind: PhaseKind) -> Switch {
        if !key.uber {
            return Switch::Fixed(super::phase_is(key, kind));
        }
        Switch::Dynamic(ops::eq(KEY.read().phase, kind.index()))
    }
}
