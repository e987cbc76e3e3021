//! Quality presets with the semantics and numbers of @takram/three-clouds (`qualityPresets.ts`):
//! low drops shape detail, light shafts and turbulence and marches far more coarsely; medium
//! drops light shafts and turbulence; high is the baseline; ultra refines the shadow map and
//! the minimum step. `reference` is not a real-time preset: it is the converged render the
//! others are measured against (`nimbus tradeoff`).

use serde::{Deserialize, Serialize};

use super::features::Features;

#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
#[serde(rename_all = "lowercase")]
pub enum Quality {
    Low,
    Medium,
    #[default]
    High,
    Ultra,
    /// Converged, for measuring the others: short steps that never grow past 100 m, no early
    /// termination or density cut-offs, long secondary marches, every effect on. Seconds per
    /// frame; not for real time.
    Reference,
}

/// Numbers of the primary, secondary, light-shaft and shadow marches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSettings {
    pub max_iteration_count: u32,
    pub min_step_size: f32,
    pub max_step_size: f32,
    pub max_ray_distance: f32,
    pub perspective_step_scale: f32,
    pub min_density: f32,
    pub min_extinction: f32,
    pub min_transmittance: f32,
    pub max_iteration_count_to_sun: u32,
    pub max_iteration_count_to_ground: u32,
    pub min_secondary_step_size: f32,
    pub secondary_step_scale: f32,
    /// Secondary marches span the whole path out of the cloud slab with stratified samples
    /// (unbiased, no shadow map in the march) instead of a short reach handed to the shadow map.
    pub secondary_full_path: bool,
    pub max_shadow_length_iteration_count: u32,
    pub min_shadow_length_step_size: f32,
    pub max_shadow_length_ray_distance: f32,
    pub shadow_cascade_count: u32,
    pub shadow_map_size: u32,
    pub shadow_max_iteration_count: u32,
    pub shadow_min_step_size: f32,
    pub shadow_max_step_size: f32,
    pub shadow_min_density: f32,
    pub shadow_min_extinction: f32,
    pub shadow_min_transmittance: f32,
}

impl Quality {
    /// The real-time presets (the reference is left out of catalogues and benchmarks).
    pub const ALL: [Quality; 4] = [Quality::Low, Quality::Medium, Quality::High, Quality::Ultra];

    pub fn name(self) -> &'static str {
        match self {
            Quality::Low => "low",
            Quality::Medium => "medium",
            Quality::High => "high",
            Quality::Ultra => "ultra",
            Quality::Reference => "reference",
        }
    }

    /// Every preset, the reference included.
    pub const WITH_REFERENCE: [Quality; 5] = [
        Quality::Low,
        Quality::Medium,
        Quality::High,
        Quality::Ultra,
        Quality::Reference,
    ];

    pub fn parse(s: &str) -> Option<Quality> {
        Quality::ALL
            .into_iter()
            .chain([Quality::Reference])
            .find(|q| q.name() == s.trim().to_ascii_lowercase())
    }

    /// The effects this preset turns on (the `presets` column of the effect table).
    pub fn features(self) -> Features {
        super::features::preset_features(self)
    }

    /// March settings (high = the reference library's defaults but for one ground step and a
    /// ray's end at a transmittance of 0.1).
    pub fn settings(self) -> MarchSettings {
        let high = MarchSettings {
            max_iteration_count: 500,
            min_step_size: 50.0,
            max_step_size: 1000.0,
            max_ray_distance: 2e5,
            perspective_step_scale: 1.01,
            min_density: 1e-5,
            min_extinction: 1e-5,
            // Every real-time preset ends a ray at a transmittance of 0.1 and takes the rest as
            // more of the same cloud (`march_clouds`' early termination), as the reference
            // library's `low` does. The accuracy study measured it no further from the
            // reference than marching on to its 0.01 (FLIP medium 0.0779 → 0.0774, high
            // 0.0526 → 0.0524, ultra 0.0459 → 0.0459): the last tenth of a ray's light, taken
            // with steps grown to hundreds of metres deep in a cloud, was no better than the
            // extrapolation, and cost medium a fifth of its frame (samples per pixel 12 → 10).
            min_transmittance: 1e-1,
            max_iteration_count_to_sun: 2,
            max_iteration_count_to_ground: 3,
            min_secondary_step_size: 100.0,
            secondary_step_scale: 2.0,
            secondary_full_path: false,
            max_shadow_length_iteration_count: 500,
            min_shadow_length_step_size: 50.0,
            max_shadow_length_ray_distance: 2e5,
            shadow_cascade_count: 3,
            shadow_map_size: 512,
            shadow_max_iteration_count: 50,
            shadow_min_step_size: 100.0,
            shadow_max_step_size: 1000.0,
            shadow_min_density: 1e-5,
            shadow_min_extinction: 1e-5,
            shadow_min_transmittance: 1e-4,
        };
        match self {
            Quality::Low => MarchSettings {
                max_iteration_count: 200,
                min_step_size: 100.0,
                max_ray_distance: 1e5,
                min_density: 1e-4,
                min_extinction: 1e-4,
                max_iteration_count_to_ground: 0,
                // The shadow map alone towards the sun below the top of the shadow-casting
                // layers (one step above it and beyond the map's edge, `sun_optical_depth`):
                // the reference library's one step there took 11 % of this preset's frame in
                // the browser benchmark (364 → 324 ms, median of 6 alternating runs), and the
                // accuracy study measured the map alone closer to the reference (FLIP 0.3024 →
                // 0.2893, luminance 0.83 → 0.87).
                max_iteration_count_to_sun: 0,
                shadow_cascade_count: 2,
                shadow_map_size: 256,
                shadow_max_iteration_count: 25,
                shadow_min_density: 1e-4,
                shadow_min_extinction: 1e-4,
                ..high
            },
            // The way to the sun left to the shadow map below the top of the shadow-casting
            // layers, as `low`, and steps from 100 m, as `low`: once the haze lay in the
            // clouds' shadows (`near_air_sunlit`) the accuracy study measured this no further
            // from the reference than `high` and closer than `medium` had been (FLIP 0.0616,
            // against 0.0779 with two sun steps and 50 m steps and the haze lit everywhere),
            // at three quarters of the browser's frame. Before that change the two sun steps
            // had held `medium`'s picture together (0.0779 → 0.0843 without them).
            Quality::Medium => MarchSettings {
                min_step_size: 100.0,
                max_iteration_count_to_sun: 0,
                min_density: 1e-4,
                min_extinction: 1e-4,
                max_iteration_count_to_ground: 1,
                shadow_map_size: 256,
                shadow_min_density: 1e-4,
                shadow_min_extinction: 1e-4,
                ..high
            },
            // One ground step, as medium: high's three cost 6 % of its frame and measured no
            // closer to the reference than none (the accuracy study put high off its front).
            Quality::High => MarchSettings {
                max_iteration_count_to_ground: 1,
                ..high
            },
            Quality::Ultra => MarchSettings {
                min_step_size: 10.0,
                shadow_map_size: 1024,
                ..high
            },
            Quality::Reference => MarchSettings {
                max_iteration_count: 6000,
                // Steps of 0.2 % of the distance down to 5 m: each sample's light stands for
                // its whole step, and within a step of a dense deck's top (σt·20 m ≈ 1) the
                // light falls faster than the view's transmittance, so 20 m steps read the deck
                // 1.3 % dark against Mitsuba (5 m: 0.2 %).
                min_step_size: 5.0,
                max_step_size: 100.0,
                perspective_step_scale: 1.002,
                min_density: 0.0,
                min_extinction: 0.0,
                min_transmittance: 0.0,
                // 24 sun and 12 ground intervals growing ×1.2 over the whole path out of the
                // slab, one stratified sample in each: unbiased against a 1 m integral.
                max_iteration_count_to_sun: 24,
                max_iteration_count_to_ground: 12,
                min_secondary_step_size: 100.0,
                secondary_step_scale: 1.2,
                secondary_full_path: true,
                max_shadow_length_iteration_count: 4000,
                min_shadow_length_step_size: 20.0,
                shadow_cascade_count: 4,
                shadow_map_size: 1024,
                shadow_max_iteration_count: 400,
                shadow_min_step_size: 20.0,
                shadow_max_step_size: 100.0,
                shadow_min_density: 0.0,
                shadow_min_extinction: 0.0,
                shadow_min_transmittance: 0.0,
                ..high
            },
        }
    }
}

#[cfg(feature = "clap")]
impl clap::ValueEnum for Quality {
    fn value_variants<'a>() -> &'a [Self] {
        &Quality::WITH_REFERENCE
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()))
    }
}
