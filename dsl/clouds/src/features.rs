//! The effect table: every toggle declared once, in one row of [`effects!`]. A row gives the
//! toggle's field, its name on the command line and in scene files, its short tag in shader key
//! names, the quality presets that include it, the scene rule that can drop it, and its doc.
//! `Features`, `Toggle` (with its clap `ValueEnum`), the scene's `FeatureOverrides`, each
//! preset's features and the analysis' rule lookup are all derived from that table.
//!
//! Each toggle is a generation-time choice: a toggle that is off leaves no code, binding or
//! texture in the shader.

use serde::{Deserialize, Serialize};

use crate::analysis::{self, SceneContent, Verdict};
use crate::path::Path;
use crate::quality::Quality;

/// A scene rule: can the scene show this effect, and why.
pub type Rule = fn(&SceneContent) -> Verdict;

macro_rules! effects {
    ($(
        $(#[doc = $doc:literal])+
        $variant:ident, $field:ident, $name:literal, tag $tag:literal,
        presets [$($q:ident),*], rule $rule:expr;
    )+) => {
        /// Which effects a shader simulates.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        #[serde(deny_unknown_fields, default)]
        pub struct Features {
            $($(#[doc = $doc])+ pub $field: bool,)+
            /// Multiple-scattering octaves (1..=12).
            pub octaves: u32,
            /// How the cloud pass draws the genus (the volume unless a scene picks another).
            pub path: Path,
        }

        impl Default for Features {
            /// The `high` preset's features.
            fn default() -> Self {
                Quality::High.features()
            }
        }

        /// A named on/off effect, as spelled on the command line and in scene files.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Toggle {
            $($(#[doc = $doc])+ $variant,)+
        }

        impl Toggle {
            /// Every toggle, in table order (the order of key names and `explain`).
            pub const ALL: &[Toggle] = &[$(Toggle::$variant),+];

            /// The command-line and scene-file name (`shape-detail`).
            pub fn name(self) -> &'static str {
                match self { $(Toggle::$variant => $name,)+ }
            }

            /// The short tag in shader key names (`detail`).
            pub fn tag(self) -> &'static str {
                match self { $(Toggle::$variant => $tag,)+ }
            }

            /// The first line of the toggle's doc.
            pub fn doc(self) -> &'static str {
                match self { $(Toggle::$variant => first_line(&[$($doc),+]),)+ }
            }

            /// Whether the quality preset `q` includes the effect.
            pub fn in_preset(self, q: Quality) -> bool {
                match self { $(Toggle::$variant => [$(Quality::$q),*].contains(&q),)+ }
            }

            /// The scene rule that may leave the effect out, or `None` when only the quality
            /// preset decides.
            pub fn rule(self) -> Option<Rule> {
                match self { $(Toggle::$variant => $rule,)+ }
            }

            pub fn get(self, f: &Features) -> bool {
                match self { $(Toggle::$variant => f.$field,)+ }
            }

            pub fn set(self, f: &mut Features, on: bool) {
                match self { $(Toggle::$variant => f.$field = on,)+ }
            }

            fn forced(self, o: &FeatureOverrides) -> Option<bool> {
                match self { $(Toggle::$variant => o.$field,)+ }
            }
        }

        /// A scene's `[features]` table: effects forced on or off over the preset and the rules.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct FeatureOverrides {
            $(pub $field: Option<bool>,)+
            pub octaves: Option<u32>,
            pub path: Option<Path>,
        }

        /// The features of a quality preset, from the table's `presets` column.
        pub(crate) fn preset_features(q: Quality) -> Features {
            Features {
                $($field: Toggle::$variant.in_preset(q),)+
                octaves: if q == Quality::Reference { 12 } else { 8 },
                path: Path::Volume,
            }
        }
    };
}

effects! {
    /// Detail erosion by the 32³ Worley texture.
    ShapeDetail, shape_detail, "shape-detail", tag "detail",
        presets [Medium, High, Ultra, Reference], rule Some(analysis::shape_detail);
    /// Domain distortion of the shape by the curl-noise texture near cloud bases.
    Turbulence, turbulence, "turbulence", tag "turb",
        presets [High, Ultra, Reference], rule Some(analysis::turbulence);
    /// Crepuscular rays: the shadow-length march through the beer shadow map (in the haze).
    LightShafts, light_shafts, "light-shafts", tag "shafts",
        presets [High, Ultra, Reference], rule Some(analysis::light_shafts);
    /// Analytic exponential haze.
    Haze, haze, "haze", tag "haze",
        presets [Low, Medium, High, Ultra, Reference], rule Some(analysis::haze);
    /// Beer shadow map: optical depth towards the sun beyond the secondary march.
    Shadows, shadows, "shadows", tag "shadows",
        presets [Low, Medium, High, Ultra, Reference], rule Some(analysis::shadows);
    /// Light bounced from the ground below the clouds. Not in `low`: with no ground steps to
    /// attenuate it, the bounce lit cloud bases as if nothing stood between them and the ground
    /// (`low` read 20 % too bright below a deck in the accuracy study).
    GroundBounce, ground_bounce, "ground-bounce", tag "bounce",
        presets [Medium, High, Ultra, Reference], rule Some(analysis::ground_bounce);
    /// Multiple scattering by diffusion through the layer, in place of the octaves: the
    /// Eddington two-stream solution around each sample, from its optical depths to the sun and
    /// down to the base. The octaves lose the light thick cloud scatters many times (a deck 3 to
    /// 15 times too dark against a path tracer) and overshoot thin cloud; this holds in both. It
    /// marches down to the base (the ground steps) where the ground bounce does not already, so
    /// it is not in `low`, which has no ground steps.
    Diffusion, diffusion, "diffusion", tag "diffuse",
        presets [Medium, High, Ultra, Reference], rule None;
    /// The "powder" darkening of thin cloud edges facing the sun.
    Powder, powder, "powder", tag "powder",
        presets [Low, Medium, High, Ultra, Reference], rule None;
    /// Sun and sky irradiance evaluated per sample rather than interpolated between the shells.
    /// Not in `high`: on top of its short sun march it darkened the clouds further from the
    /// converged reference (the accuracy study: FLIP 0.068 with it, 0.058 without, same time).
    AccurateSunSkyLight, accurate_sun_sky_light, "accurate-sun-sky-light", tag "sunsky",
        presets [Ultra, Reference], rule None;
    /// Approximate Mie (Jendersie & d'Eon 2023) instead of the genus' phase function.
    AccuratePhaseFunction, accurate_phase_function, "accurate-phase-function", tag "mie",
        presets [], rule None;
    /// Thin high layers drawn as a textured 2D layer (a few density reads per pixel, no march).
    /// An approximation, not an effect: in no preset, but the scene analysis chooses it in the
    /// real-time presets ([`Toggle::chosen_in`]) where a thin high layer seen from far below is
    /// all the sky holds (`analysis::flat_high_layer`).
    FlatHighLayer, flat_high_layer, "flat-high-layer", tag "flat",
        presets [], rule Some(analysis::flat_high_layer);
    /// The engine's opaque scene, read from its depth buffer, stops the march; the output is
    /// premultiplied over the engine's picture. An engine integration, not an effect: in no
    /// preset, chosen by the host that has a scene (`--enable scene-depth`).
    SceneDepth, scene_depth, "scene-depth", tag "depth",
        presets [], rule None;
    /// The weather without its tile's repetition: the 100 km weather tile read at an offset of
    /// its own around each vertex of a lattice (hex tiling), blended between them. A view from
    /// high above crosses tens of tiles, and the same cloud fields came back in rows and
    /// columns. Not in a preset (its arithmetic costs about a fifth of a frame on a CPU
    /// rasteriser); the scene analysis chooses it in every preset where the camera is high
    /// above the clouds (`analysis::untiled_weather`).
    UntiledWeather, untiled_weather, "untiled-weather", tag "untile",
        presets [], rule Some(analysis::untiled_weather);
    /// An orthographic camera: parallel rays, each from its own point of the image plane. A
    /// camera's, not an effect: in no preset, chosen by the host (`--enable orthographic`).
    Orthographic, orthographic, "orthographic", tag "ortho",
        presets [], rule None;
    /// The air's light (the sky behind the clouds and the air in front of them) integrated along
    /// each pixel's ray, twelve samples for each, instead of read from the air table
    /// (`model::air_table`), which a pass of its own fills when the sun or the camera's altitude
    /// changes. In `reference` only: the integrals cost a third of `low`'s frame in the browser
    /// benchmark. An orthographic camera always integrates (each of its rays starts at its own
    /// altitude, which one table cannot hold).
    AccurateAirLight, accurate_air_light, "accurate-air-light", tag "air",
        presets [Reference], rule None;
}

fn first_line(doc: &[&'static str]) -> &'static str {
    doc.first().map_or("", |l| l.trim())
}

impl Toggle {
    /// Whether the scene analysis may switch this toggle on at quality `q` when its rule allows
    /// it (the flat high layer in the real-time presets, as `ultra` and `reference` always
    /// march the volume; the untiled weather in all).
    pub fn chosen_in(self, q: Quality) -> bool {
        match self {
            Toggle::FlatHighLayer => matches!(q, Quality::Low | Quality::Medium | Quality::High),
            // A picture's, not an approximation: the same in every preset, so that presets
            // compared on one view see the same weather.
            Toggle::UntiledWeather => true,
            _ => false,
        }
    }

    /// A toggle by name (`shape-detail`, also `shape_detail`, any case).
    pub fn parse(s: &str) -> Option<Toggle> {
        let s = s.trim().to_ascii_lowercase().replace('_', "-");
        Toggle::ALL.iter().copied().find(|t| t.name() == s)
    }
}

#[cfg(feature = "clap")]
impl clap::ValueEnum for Toggle {
    fn value_variants<'a>() -> &'a [Self] {
        Toggle::ALL
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()).help(self.doc()))
    }
}

impl Features {
    /// These features less every effect beyond the sun's scattering by the clouds (powder,
    /// ground bounce, haze, light shafts, per-sample sun/sky light): verification mode's
    /// shader, the model an independent path tracer reproduces. Octaves are left as they are.
    pub fn sun_scattering_only(mut self) -> Features {
        self.powder = false;
        self.ground_bounce = false;
        self.haze = false;
        self.light_shafts = false;
        self.accurate_sun_sky_light = false;
        self
    }
}

impl FeatureOverrides {
    /// The forced state of `t`, if the scene forces it.
    pub fn get(&self, t: Toggle) -> Option<bool> {
        t.forced(self)
    }

    /// `f` with the forced toggles and octaves applied.
    pub fn apply(&self, mut f: Features) -> Features {
        for &t in Toggle::ALL {
            if let Some(on) = t.forced(self) {
                t.set(&mut f, on);
            }
        }
        if let Some(o) = self.octaves {
            f.octaves = o;
        }
        if let Some(p) = self.path {
            f.path = p;
        }
        f
    }
}
