//! The cloud module: one variant per genus, quality preset and set of toggles, each recorded
//! with exactly the code, bindings and textures its features use.

use crate::cloud::{Features, Genus, Quality};
use crate::cpu::{Sampler, Texture2d, Texture3d};
use crate::ir::Module;
use crate::{DslError, ModuleBuilder, loc};

use super::march::{CloudUniforms, MarchKey, PhaseKind, cloud_fragment};
use super::preview::fullscreen_position;

/// A cloud variant: what codegen specialises for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CloudVariant {
    pub genus: String,
    pub quality: Quality,
    pub key: MarchKey,
}

impl CloudVariant {
    /// The variant of `genus` at `quality` with `features` (the preset's unless overridden).
    pub fn new(genus: &Genus, quality: Quality, features: Features) -> Self {
        CloudVariant {
            genus: genus.name.clone(),
            quality,
            key: MarchKey {
                features,
                phase: PhaseKind::of(&genus.phase, &features),
                groups: genus.layer_groups() as u32,
            },
        }
    }

    /// `cumulus.high`, plus `+toggle`/`-toggle` where the features differ from the preset's.
    pub fn name(&self) -> String {
        let mut s = format!("{}.{}", self.genus, self.quality.name());
        let preset = self.quality.features();
        for t in crate::cloud::Toggle::ALL {
            let (want, base) = (t.get(&self.key.features), t.get(&preset));
            if want != base {
                s.push(if want { '+' } else { '-' });
                s.push_str(t.name());
            }
        }
        if self.key.features.octaves != preset.octaves {
            s.push_str(&format!("+octaves{}", self.key.features.octaves));
        }
        s
    }
}

/// Records the cloud module for one variant.
pub fn cloud_module(variant: &CloudVariant) -> Result<Module, DslError> {
    let key = variant.key;
    ModuleBuilder::build(
        "clouds",
        &format!(
            "Volumetric clouds: genus `{}`, quality `{}`, features {:?}.",
            variant.genus,
            variant.quality.name(),
            key.features
        ),
        loc!(),
        |m| {
            let u = m.uniform::<CloudUniforms>(
                "clouds",
                0,
                0,
                "Layers, media, march, light and camera.",
            );
            let weather = m.handle::<Texture2d>(
                "weather_texture",
                0,
                1,
                "Local weather: coverage per channel.",
            );
            let shape = m.handle::<Texture3d>(
                "shape_texture",
                0,
                2,
                "Perlin–Worley shape noise (128³, tileable).",
            );
            let detail = m.handle::<Texture3d>(
                "detail_texture",
                0,
                3,
                "Worley detail noise (32³, tileable).",
            );
            let turbulence = m.handle::<Texture2d>(
                "turbulence_texture",
                0,
                4,
                "Curl noise for turbulent displacement.",
            );
            let shadow = m.handle::<Texture2d>(
                "shadow_map",
                0,
                5,
                "Beer shadow map: front depth, mean extinction, max and tail optical depth.",
            );
            let smp = m.handle::<Sampler>("linear_sampler", 0, 6, "Trilinear, repeat.");
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_main",
                "Clouds, sky and haze for one pixel.",
                loc!(),
                |frag_coord| {
                    cloud_fragment::shader(
                        frag_coord,
                        u.get(),
                        weather.get(),
                        shape.get(),
                        detail.get(),
                        turbulence.get(),
                        shadow.get(),
                        smp.get(),
                        key,
                    )
                },
            );
        },
    )
}
