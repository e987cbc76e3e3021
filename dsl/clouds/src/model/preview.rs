//! A false-colour preview of the density profile and the phase function: the first module that
//! proves the chain from `#[shader_fn]` to validated shaders for every target.
//!
//! The screen's x axis sweeps the scattering angle (0 at the left, π at the right) and its y axis
//! the height fraction η (0 at the bottom). Red shows the density profile at η, green the phase
//! function at that angle on a log scale, blue their product.

use glam::Vec4;

use nimbus_dsl::ir::Module;
use nimbus_dsl::prelude::*;
use nimbus_dsl::{DslError, ModuleBuilder, SpecValue, loc};

use super::phase::{dual_lobe_hg, henyey_greenstein};
use super::profile::density_profile;

/// Which phase function the preview shows; a generation-time choice, so each variant contains
/// only the function it uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhaseModel {
    HenyeyGreenstein,
    DualLobe,
}

impl PhaseModel {
    pub const ALL: [PhaseModel; 2] = [PhaseModel::HenyeyGreenstein, PhaseModel::DualLobe];
}

impl SpecValue for PhaseModel {
    fn suffix(&self) -> String {
        match self {
            PhaseModel::HenyeyGreenstein => "hg".into(),
            PhaseModel::DualLobe => "dual_lobe".into(),
        }
    }

    fn label(&self) -> String {
        self.suffix()
    }
}

/// Uniform inputs of the preview.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct PreviewParams {
    /// Render target size in pixels.
    pub resolution: Vec2,
    /// Forward anisotropy (the only one used by the single-lobe variant).
    pub g1: f32,
    /// Backward anisotropy of the second lobe.
    pub g2: f32,
    /// Weight of the second lobe.
    pub lobe_mix: f32,
    /// Profile coefficients a, b, c, d of `a·e^(b·η) + c·η + d`.
    pub profile: Vec4,
}

impl Default for PreviewParams {
    fn default() -> Self {
        Self {
            resolution: Vec2::new(640.0, 360.0),
            g1: 0.7,
            g2: -0.2,
            lobe_mix: 0.5,
            profile: Vec4::new(0.0, 0.0, 0.75, 0.25),
        }
    }
}

/// Clip-space position of a full-screen triangle's vertex (indices 0, 1, 2).
#[shader_fn]
pub fn fullscreen_position(vertex_index: u32) -> Vec4 {
    let x = ((vertex_index << 1u32) & 2u32) as f32 * 2.0 - 1.0;
    let y = (vertex_index & 2u32) as f32 * 2.0 - 1.0;
    vec4(x, y, 0.0, 1.0)
}

/// Phase function value for the chosen model.
#[shader_fn]
pub fn preview_phase(cos_theta: f32, params: PreviewParams, #[spec] model: PhaseModel) -> f32 {
    match model {
        PhaseModel::HenyeyGreenstein => henyey_greenstein(cos_theta, params.g1),
        PhaseModel::DualLobe => dual_lobe_hg(cos_theta, params.g1, params.g2, params.lobe_mix),
    }
}

/// False colour at normalised screen position `uv` (origin bottom-left).
#[shader_fn]
pub fn preview_color(uv: Vec2, params: PreviewParams, #[spec] model: PhaseModel) -> Vec4 {
    let cos_theta = (uv.x * core::f32::consts::PI).cos();
    let p = params.profile;
    let density = density_profile(uv.y, p.x, p.y, p.z, p.w).max(0.0);
    let phase = preview_phase(cos_theta, params, model);
    // log10 scale from 0.01 to 100 sr⁻¹ maps to [0, 1].
    let phase_level = ((phase.max(1e-6).log2() * 0.150_514_99 + 2.0) * 0.25).saturate();
    vec4(
        density.saturate(),
        phase_level,
        (density * phase_level).saturate(),
        1.0,
    )
}

/// Colour of the pixel at `frag_coord` (framebuffer coordinates, y down), scaled by `exposure`.
#[shader_fn]
pub fn preview_fragment(
    frag_coord: Vec4,
    params: PreviewParams,
    exposure: f32,
    #[spec] model: PhaseModel,
) -> Vec4 {
    let uv = frag_coord.xy() / params.resolution;
    // Framebuffer y grows downwards; the preview's η grows upwards.
    let color = preview_color(vec2(uv.x, 1.0 - uv.y), params, model);
    color * vec4(exposure, exposure, exposure, 1.0)
}

/// Records the preview module for one phase model.
pub fn preview_module(model: PhaseModel) -> Result<Module, DslError> {
    ModuleBuilder::build(
        "preview",
        "False-colour preview of the density profile (red) and phase function (green).",
        loc!(),
        |m| {
            let params = m.uniform::<PreviewParams>("params", 0, 0, "Preview inputs.");
            let exposure = m.override_f32(
                "EXPOSURE",
                1.0,
                "Brightness multiplier; a pipeline constant for wgpu, baked for other targets.",
            );
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_main",
                "Preview colour per pixel.",
                loc!(),
                |frag_coord| {
                    preview_fragment::shader(frag_coord, params.get(), exposure.get(), model)
                },
            );
        },
    )
}
