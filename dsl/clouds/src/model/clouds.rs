//! The cloud module: one variant per genus, quality preset and set of toggles, each recorded
//! with exactly the code, bindings and textures its features use.

use crate::{Features, Genus, Path, Quality};
use nimbus_dsl::ir::Module;
use nimbus_dsl::{DslError, ModuleBuilder, loc};

pub use super::bindings::{CloudBinding, ResolveBinding};

use super::air_table::air_table_fragment;
use super::blob2d::blob2d_fragment;
use super::display::display_fragment;
use super::impostor::impostor_fragment;
use super::march::{CloudUniforms, cloud_fragment};
use super::mesh::mesh_fragment;
use super::preview::fullscreen_position;
use super::resolve::resolve_fragment;
use super::shadow::shadow_fragment;
use super::slices::slices_fragment;
use crate::key::{CloudKey, ShadowKey};

/// A genus at a quality preset with a set of features: it resolves to a shader key (the
/// code) and uniform values ([`CloudUniforms::for_genus`]).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CloudVariant {
    pub genus: String,
    pub quality: Quality,
    pub key: CloudKey,
}

impl CloudVariant {
    /// The variant of `genus` at `quality` with `features` (the preset's unless overridden).
    pub fn new(genus: &Genus, quality: Quality, features: Features) -> Self {
        CloudVariant {
            genus: genus.name.clone(),
            quality,
            key: CloudKey::new(features, &genus.phase, genus.layer_groups() as u32)
                .with_functions(genus.functions.for_layers(&genus.layers)),
        }
    }

    /// `cumulus.high`, plus `+toggle`/`-toggle` where the key's features differ from the
    /// preset's (as far as the key can tell: canonical keys drop toggles with no effect).
    pub fn name(&self) -> String {
        let mut s = format!("{}.{}", self.genus, self.quality.name());
        let preset = self.quality.features();
        for &t in crate::Toggle::ALL {
            let (want, base) = (t.get(&self.key.features), t.get(&preset));
            if want != base {
                s.push(if want { '+' } else { '-' });
                s.push_str(t.name());
            }
        }
        // With the diffusion the octaves beyond the first are gone, whatever the count.
        if !self.key.features.diffusion && self.key.features.octaves != preset.octaves {
            s.push_str(&format!("+octaves{}", self.key.features.octaves));
        }
        if let Some(tag) = self.key.output.tag() {
            s.push('+');
            s.push_str(tag);
        }
        s
    }
}

/// Records the cloud module of `key`.
pub fn cloud_module(key: &CloudKey) -> Result<Module, DslError> {
    let key = *key;
    ModuleBuilder::build(
        "clouds",
        &format!(
            "Volumetric clouds, key `{}`. Genus and quality preset are uniform values.",
            key.name()
        ),
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_main",
                "Clouds, sky and haze for one pixel.",
                loc!(),
                |frag_coord| cloud_fragment::shader(frag_coord, key),
            );
        },
    )
}

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::density::MediaParams;
use super::layers::LayerGroup;
use super::march::{CompositeParams, HazeParams, LightParams, MarchParams};
use super::shadow::{CascadeLookup, ShadowParams};
use super::shell::EARTH_RADIUS;
use super::sky::AtmosphereParams;
use crate::MarchSettings;

impl CloudUniforms {
    /// Uniforms for `genus` at `quality`, lit by a sun in `sun_direction` (local frame, y up),
    /// seen from `camera_altitude`; the remaining parameters take the reference library's
    /// defaults.
    pub fn for_genus(
        genus: &Genus,
        quality: Quality,
        sun_direction: Vec3,
        camera_altitude: f32,
    ) -> Self {
        let st = quality.settings();
        let groups = LayerGroup::from_genus(genus);
        let enabled = genus.layers.iter().filter(|l| l.is_enabled());
        let (mut min_h, mut max_h, mut shadow_top) = (f32::MAX, 0.0f32, 0.0f32);
        for l in enabled {
            min_h = min_h.min(l.altitude);
            max_h = max_h.max(l.altitude + l.height);
            if l.shadow {
                shadow_top = shadow_top.max(l.altitude + l.height);
            }
        }
        let (g1, g2, lobe_weight, droplet) = match genus.phase {
            crate::PhaseSpec::HenyeyGreenstein { g } => (g, 0.0, 0.0, 10.0),
            crate::PhaseSpec::DualLobe { g1, g2, weight } => (g1, g2, weight, 10.0),
            crate::PhaseSpec::ApproximateMie {
                droplet_diameter_um,
            } => (0.7, -0.2, 0.5, droplet_diameter_um),
            crate::PhaseSpec::Isotropic => (0.0, 0.0, 0.0, 10.0),
            // The halo is the second lobe.
            crate::PhaseSpec::IceCrystal { g, halo } => (g, 0.0, halo, 10.0),
        };
        let sky = AtmosphereParams::default();
        let sun_direction = sun_direction.normalize_or(Vec3::Y);
        let shadow = ShadowParams::for_quality(&st);
        let block = CloudUniforms {
            groups,
            media: MediaParams {
                coverage: genus.coverage,
                ..MediaParams::default()
            },
            march: MarchParams {
                max_iterations: st.max_iteration_count,
                sun_steps: st.max_iteration_count_to_sun,
                ground_steps: st.max_iteration_count_to_ground,
                min_step: st.min_step_size,
                max_step: st.max_step_size,
                max_ray_distance: st.max_ray_distance,
                perspective_step_scale: st.perspective_step_scale,
                min_density: st.min_density,
                min_extinction: st.min_extinction,
                min_transmittance: st.min_transmittance,
                min_secondary_step: st.min_secondary_step_size,
                secondary_step_scale: st.secondary_step_scale,
                secondary_full_path: u32::from(st.secondary_full_path),
                min_height: if min_h == f32::MAX { 0.0 } else { min_h },
                max_height: max_h,
                shadow_top_height: shadow_top,
                radius: EARTH_RADIUS,
            },
            light: LightParams {
                sun_direction,
                // Filled below by `sun_light`, as a host fills them when the sun moves.
                sun_irradiance: Vec3::ZERO,
                sky_irradiance: Vec3::ZERO,
                scattering_coefficient: genus.medium.scattering_coefficient,
                absorption_coefficient: genus.medium.absorption_coefficient,
                sky_light_scale: 1.0,
                ground_bounce_scale: 1.0,
                // The rendered ground's albedo, as one number for the bounce.
                ground_albedo: sky.ground_albedo.dot(Vec3::ONE) / 3.0,
                powder_scale: 0.8,
                powder_exponent: 150.0,
                g1,
                g2,
                lobe_weight,
                droplet_diameter: droplet,
            },
            haze: HazeParams {
                density: 3e-5,
                exponent: 1e-3,
                scattering_coefficient: 0.9,
                absorption_coefficient: 0.5,
            },
            composite: CompositeParams::ALL,
            camera_altitude,
            camera_offset: Vec3::ZERO,
            inverse_view_projection: Mat4::IDENTITY,
            shadow,
            sky,
            resolution: Vec2::new(640.0, 360.0),
            pixel_offset: Vec2::ZERO,
            pixel_scale: 1.0,
            subpixel: Vec2::splat(0.5),
            frame: 0,
            jitter: 0.0,
        };
        // What the sun's position decides (irradiances, cascade transforms) comes from the one
        // `#[shader_fn]` engine hosts run too: its CPU twin here.
        block.with_sun(sun_direction)
    }
}

impl CloudUniforms {
    /// These uniforms lit by a sun of irradiance 1 alone: no sky light, ground bounce, or
    /// anything the composite adds around the clouds (verification mode's uniforms, with
    /// [`crate::Features::sun_scattering_only`] its shader).
    pub fn lit_by_sun_alone(mut self) -> Self {
        self.light.sun_irradiance = Vec3::ONE;
        self.light.sky_irradiance = Vec3::ZERO;
        self.light.sky_light_scale = 0.0;
        self.light.ground_bounce_scale = 0.0;
        self.composite = CompositeParams::NONE;
        self
    }
}

impl ShadowParams {
    /// The quality preset's shadow settings. The cascade transforms depend on the sun and
    /// the camera: [`super::sun::sun_light`] fills them (identity until then).
    pub fn for_quality(st: &MarchSettings) -> Self {
        ShadowParams {
            lookup: CascadeLookup {
                u: Mat4::IDENTITY,
                v: Mat4::IDENTITY,
            },
            inverse_matrix: Mat4::IDENTITY,
            cascade_scales: Vec4::new(1.0, 4.0, 16.0, 64.0),
            cascade_count: st.shadow_cascade_count.clamp(1, 4),
            map_size: st.shadow_map_size as f32,
            max_iterations: st.shadow_max_iteration_count,
            min_step: st.shadow_min_step_size,
            max_step: st.shadow_max_step_size,
            min_extinction: st.shadow_min_extinction,
            min_transmittance: st.shadow_min_transmittance,
            tail_scale: 2.0,
        }
    }
}

/// Records the beer-shadow-map module of `key`: the atlas fragment with the density stages
/// of the key, and nothing of the lighting.
pub fn shadow_module(key: &ShadowKey) -> Result<Module, DslError> {
    let name = key.name();
    let key = key.march_key();
    ModuleBuilder::build(
        "shadow",
        &format!("Beer shadow map atlas, key `{name}`."),
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_shadow",
                "One texel of the shadow atlas.",
                loc!(),
                |frag_coord| shadow_fragment::shader(frag_coord, key),
            );
        },
    )
}

/// Records the air table module (the same for every key that reads the table): one texel of
/// the table per fragment, from the cloud block's sun, camera altitude and atmosphere.
pub fn air_table_module() -> Result<Module, DslError> {
    ModuleBuilder::build(
        "air",
        "The air table: the air's phase-free light and transmittance per direction and distance.",
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_air",
                "One texel of the air table.",
                loc!(),
                air_table_fragment::shader,
            );
        },
    )
}

/// Records the bake module of `key` (a key of a baked path): one texel of the path's bake per
/// fragment (the slice stack, the 2D map or the impostor), from the cloud block and the noise
/// textures, with the density the key's erosion stages and genus functions make.
pub fn bake_module(key: &CloudKey) -> Result<Module, DslError> {
    let key = *key;
    let path = key.features.path;
    let (module, entry, noun, what, texel) = match path {
        Path::Blob2d => (
            "blob2d",
            "fs_blob2d",
            "The 2D map",
            "the clouds' columns around the camera (optical depths, powder, mean altitude, \
             optical depths to the sun)",
            "One texel of the 2D map.",
        ),
        Path::Impostor => (
            "impostor",
            "fs_impostor",
            "The impostor",
            "the volume's march from the camera in every direction (light, transmittance, front \
             depth)",
            "One texel of the impostor.",
        ),
        Path::Mesh => (
            "mesh",
            "fs_mesh",
            "The cluster table",
            "soft puffs fitted to the clouds around the camera (mass, mean, spread, optical \
             depths to the sun)",
            "One texel of the cluster table.",
        ),
        Path::Slices | Path::Volume => (
            "slices",
            "fs_slices",
            "The slice stack",
            "density and optical depths to the sun, down and up, per altitude around the camera",
            "One texel of the slice stack.",
        ),
    };
    ModuleBuilder::build(
        module,
        &format!("{noun} of key `{}`: {what}.", key.name()),
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(entry, texel, loc!(), |frag_coord| match path {
                Path::Blob2d => blob2d_fragment::shader(frag_coord, key),
                Path::Impostor => impostor_fragment::shader(frag_coord, key),
                Path::Mesh => mesh_fragment::shader(frag_coord, key),
                Path::Slices | Path::Volume => slices_fragment::shader(frag_coord, key),
            });
        },
    )
}

/// Records the temporal resolve module (the same for every variant).
pub fn resolve_module() -> Result<Module, DslError> {
    ModuleBuilder::build(
        "resolve",
        "Temporal resolve: upscaling and accumulation with reprojection and history clipping.",
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment("fs_resolve", "One resolved pixel.", loc!(), |frag_coord| {
                resolve_fragment::shader(frag_coord)
            });
        },
    )
}

/// Records the display-transform module (the same for every variant): the HDR image to display
/// sRGB through the model's tone curve.
pub fn display_module() -> Result<Module, DslError> {
    ModuleBuilder::build(
        "display",
        "Display transform: exposure, ACES filmic curve, sRGB encoding.",
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment("fs_display", "One displayed pixel.", loc!(), |frag_coord| {
                display_fragment::shader(frag_coord)
            });
        },
    )
}
