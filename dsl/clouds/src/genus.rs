//! A cloud genus: the layers, coverage, medium and phase function that make, say, cumulus look
//! like cumulus. Genera are data (TOML files); adding one needs no Rust.

use serde::{Deserialize, Serialize};

use super::layer::CloudLayer;
use crate::functions::GenusFunctions;

/// Most layers a genus may have: two groups of four vec4 lanes.
pub const MAX_LAYERS: usize = 8;

/// Scattering medium of the cloud droplets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Medium {
    /// σ_s per unit density (1/m at density 1).
    pub scattering_coefficient: f32,
    /// σ_a per unit density (1/m at density 1).
    pub absorption_coefficient: f32,
}

impl Default for Medium {
    fn default() -> Self {
        Self {
            scattering_coefficient: 1.0,
            absorption_coefficient: 0.0,
        }
    }
}

/// Which phase function the genus scatters with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PhaseSpec {
    /// One Henyey–Greenstein lobe.
    HenyeyGreenstein { g: f32 },
    /// Forward and backward Henyey–Greenstein lobes.
    DualLobe { g1: f32, g2: f32, weight: f32 },
    /// Jendersie & d'Eon 2023 HG + Draine fit for water droplets of this diameter (µm, 5..50).
    ApproximateMie { droplet_diameter_um: f32 },
    /// 1 / 4π.
    Isotropic,
    /// Hexagonal ice crystals: a Henyey–Greenstein lobe of asymmetry `g` and the fraction
    /// `halo` of the scattered light in the 22° halo.
    IceCrystal { g: f32, halo: f32 },
}

impl Default for PhaseSpec {
    fn default() -> Self {
        PhaseSpec::DualLobe {
            g1: 0.7,
            g2: -0.2,
            weight: 0.5,
        }
    }
}

impl PhaseSpec {
    /// Short name used in variant keys.
    pub fn kind(&self) -> &'static str {
        match self {
            PhaseSpec::HenyeyGreenstein { .. } => "hg",
            PhaseSpec::DualLobe { .. } => "dual-lobe",
            PhaseSpec::ApproximateMie { .. } => "mie",
            PhaseSpec::Isotropic => "isotropic",
            PhaseSpec::IceCrystal { .. } => "ice-crystal",
        }
    }
}

/// A genus file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Genus {
    /// Identifier; must equal the file's stem.
    pub name: String,
    pub description: String,
    /// Fraction of the sky covered, 0..1.
    #[serde(default = "default_coverage")]
    pub coverage: f32,
    #[serde(default)]
    pub medium: Medium,
    #[serde(default)]
    pub phase: PhaseSpec,
    /// The weather, shape and profile functions of the density (`functions = { shape =
    /// "anvil_shape" }`); the built-ins of the reference library's model where unset.
    #[serde(default, skip_serializing_if = "GenusFunctions::is_default")]
    pub functions: GenusFunctions,
    pub layers: Vec<CloudLayer>,
}

fn default_coverage() -> f32 {
    0.3
}

impl Genus {
    /// Checks everything a file can get wrong; returns (field path, reason).
    pub fn validate(&self) -> Result<(), (String, String)> {
        let err = |f: &str, r: String| Err((f.to_string(), r));
        if self.layers.is_empty() {
            return err("layers", "a genus needs at least one layer".into());
        }
        if self.layers.len() > MAX_LAYERS {
            return err(
                "layers",
                format!(
                    "{} layers given; at most {MAX_LAYERS} are supported",
                    self.layers.len()
                ),
            );
        }
        for (i, l) in self.layers.iter().enumerate() {
            l.validate()
                .map_err(|(f, r)| (format!("layers[{i}].{f}"), r))?;
        }
        if !self.layers.iter().any(CloudLayer::is_enabled) {
            return err(
                "layers",
                "every layer has height 0 or density_scale 0; nothing would render".into(),
            );
        }
        if !(self.coverage.is_finite() && (0.0..=1.0).contains(&self.coverage)) {
            return err(
                "coverage",
                format!("must be in [0, 1], got {}", self.coverage),
            );
        }
        for (f, v) in [
            (
                "medium.scattering_coefficient",
                self.medium.scattering_coefficient,
            ),
            (
                "medium.absorption_coefficient",
                self.medium.absorption_coefficient,
            ),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return err(f, format!("must be a finite number ≥ 0, got {v}"));
            }
        }
        let g_ok = |g: f32| g.is_finite() && g.abs() <= 0.999;
        match self.phase {
            PhaseSpec::HenyeyGreenstein { g } if !g_ok(g) => {
                return err("phase.g", format!("must be in [-0.999, 0.999], got {g}"));
            }
            PhaseSpec::DualLobe { g1, g2, weight } => {
                if !g_ok(g1) {
                    return err("phase.g1", format!("must be in [-0.999, 0.999], got {g1}"));
                }
                if !g_ok(g2) {
                    return err("phase.g2", format!("must be in [-0.999, 0.999], got {g2}"));
                }
                if !(weight.is_finite() && (0.0..=1.0).contains(&weight)) {
                    return err("phase.weight", format!("must be in [0, 1], got {weight}"));
                }
            }
            PhaseSpec::IceCrystal { g, halo } => {
                if !g_ok(g) {
                    return err("phase.g", format!("must be in [-0.999, 0.999], got {g}"));
                }
                if !(halo.is_finite() && (0.0..=1.0).contains(&halo)) {
                    return err("phase.halo", format!("must be in [0, 1], got {halo}"));
                }
            }
            PhaseSpec::ApproximateMie {
                droplet_diameter_um: d,
            } if !(d.is_finite() && (5.0..=50.0).contains(&d)) => {
                return err(
                    "phase.droplet_diameter_um",
                    format!("the fit is valid for 5..50 µm, got {d}"),
                );
            }
            _ => {}
        }
        Ok(())
    }

    /// Bottom of the lowest and top of the highest layer that renders anything (m), if any.
    pub fn altitude_range(&self) -> Option<(f32, f32)> {
        let enabled = self.layers.iter().filter(|l| l.is_enabled());
        enabled.fold(None, |range, l| {
            let (lo, hi) = range.unwrap_or((f32::MAX, f32::MIN));
            Some((lo.min(l.altitude), hi.max(l.altitude + l.height)))
        })
    }

    /// Number of vec4 lane groups the layers need (4 layers per group).
    pub fn layer_groups(&self) -> usize {
        self.layers.len().div_ceil(4).max(1)
    }
}
