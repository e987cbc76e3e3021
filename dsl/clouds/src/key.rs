//! Shader keys: everything a cloud shader fixes at generation time, and nothing else. A key is
//! a shader's identity: two genus × preset pairs with the same key run the very same code and
//! differ only in uniform values, so emit, check, the snapshots, the manifest and the runtime's
//! pipeline cache all count, name and cache shaders by key.
//!
//! Keys are canonical: settings that cannot change the code given the others are cleared when
//! the key is made (light shafts live in the haze, so they are off without it; the accurate
//! phase function is the `mie` phase kind), so distinct keys are distinct shaders.

use nimbus_dsl::SpecValue;

use crate::features::{Features, Toggle};
use crate::functions::GenusFunctions;
use crate::genus::PhaseSpec;
use crate::path::Path;

/// Phase function of a shader (the genus decides it, `accurate-phase-function` forces Mie).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PhaseKind {
    HenyeyGreenstein,
    DualLobe,
    ApproximateMie,
    Isotropic,
    IceCrystal,
}

impl PhaseKind {
    pub fn of(spec: &PhaseSpec, features: &Features) -> PhaseKind {
        // The accurate phase function is that of water droplets; ice keeps its own.
        if let PhaseSpec::IceCrystal { .. } = spec {
            return PhaseKind::IceCrystal;
        }
        if features.accurate_phase_function {
            return PhaseKind::ApproximateMie;
        }
        match spec {
            PhaseSpec::HenyeyGreenstein { .. } => PhaseKind::HenyeyGreenstein,
            PhaseSpec::DualLobe { .. } => PhaseKind::DualLobe,
            PhaseSpec::ApproximateMie { .. } => PhaseKind::ApproximateMie,
            PhaseSpec::Isotropic => PhaseKind::Isotropic,
            PhaseSpec::IceCrystal { .. } => PhaseKind::IceCrystal,
        }
    }

    /// The tag in key names.
    /// Position in [`PhaseKind::ALL`] (the uber-shader's uniform value).
    pub fn index(self) -> u32 {
        self as u32
    }

    pub const ALL: [PhaseKind; 5] = [
        PhaseKind::HenyeyGreenstein,
        PhaseKind::DualLobe,
        PhaseKind::ApproximateMie,
        PhaseKind::Isotropic,
        PhaseKind::IceCrystal,
    ];

    pub fn tag(self) -> &'static str {
        match self {
            PhaseKind::HenyeyGreenstein => "hg",
            PhaseKind::DualLobe => "dual",
            PhaseKind::ApproximateMie => "mie",
            PhaseKind::Isotropic => "iso",
            PhaseKind::IceCrystal => "ice",
        }
    }
}

impl SpecValue for PhaseKind {
    fn suffix(&self) -> String {
        match self {
            PhaseKind::HenyeyGreenstein => "hg".into(),
            PhaseKind::DualLobe => "dual_lobe".into(),
            PhaseKind::ApproximateMie => "mie".into(),
            PhaseKind::Isotropic => "isotropic".into(),
            PhaseKind::IceCrystal => "ice_crystal".into(),
        }
    }

    fn label(&self) -> String {
        self.tag().into()
    }
}

/// What a pixel of the cloud pass holds. Each is its own shader (the unused results are not
/// computed); the layers of a linear image come from one frame rendered once per layer with
/// the same jitter, so they line up pixel for pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum PixelOutput {
    /// The composited image (clouds over sky or ground, air and haze); alpha is the clouds'
    /// opacity.
    #[default]
    Composite,
    /// The composited image with alpha holding the density samples the march took (for
    /// `nimbus tradeoff`).
    Samples,
    /// The clouds alone: the radiance they scatter towards the camera, before the air in front
    /// of them; alpha is their transmittance.
    Clouds,
    /// The clouds' front depth (transmittance-weighted mean distance of the scattering, in
    /// kilometres so that half-float targets hold it; −1 where there is none) in red,
    /// transmittance in green, density samples in blue.
    Depth,
}

impl PixelOutput {
    /// The tag in shader key names (none for the composited image).
    pub fn tag(self) -> Option<&'static str> {
        match self {
            PixelOutput::Composite => None,
            PixelOutput::Samples => Some("count"),
            PixelOutput::Clouds => Some("clouds"),
            PixelOutput::Depth => Some("depth"),
        }
    }
}

/// What the cloud pass fixes at generation time. One per module, so the model's functions keep
/// their plain names (the recorder refuses two different keys in one module).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CloudKey {
    /// Canonical: `light_shafts` only with `haze`, `accurate_phase_function` always off (it is
    /// in `phase`).
    pub features: Features,
    pub phase: PhaseKind,
    /// Layer lane groups (1 = up to four layers, 2 = up to eight).
    pub groups: u32,
    /// What each pixel holds: the composited image, or an instrumented or linear layer.
    pub output: PixelOutput,
    /// The genus' weather, shape and profile functions (the built-ins unless it names its own).
    pub functions: GenusFunctions,
    /// The uber-shader: every choice above is read at run time from the key uniforms
    /// ([`crate::model::choices`]) instead of being fixed in the code; the fields then give the
    /// most the shader can do (every toggle on, two groups).
    pub uber: bool,
}

impl CloudKey {
    /// The canonical key of a shader with `features` for a genus of `phase` and `groups` lane
    /// groups.
    pub fn new(features: Features, phase: &PhaseSpec, groups: u32) -> CloudKey {
        let mut features = features;
        let phase = PhaseKind::of(phase, &features);
        features.accurate_phase_function = false;
        // The shaft march only scales the haze's sunlight: without haze it has no output.
        features.light_shafts &= features.haze;
        // An orthographic camera integrates the air per ray whatever the toggle says.
        features.accurate_air_light &= !features.orthographic;
        // Diffusion replaces the octaves beyond the first (single scattering).
        if features.diffusion {
            features.octaves = 1;
        }
        // A baked path serves one perspective camera: an orthographic camera (a ray from each
        // pixel's own origin) is drawn by the volume. A path asked for draws every layer, a
        // thin high one too: the flat layer is the volume's shortcut (`analysis` says both in
        // `explain`).
        if features.orthographic {
            features.path = Path::Volume;
        }
        if features.path != Path::Volume {
            features.flat_high_layer = false;
        }
        CloudKey {
            features,
            phase,
            groups: groups.clamp(1, 2),
            output: PixelOutput::Composite,
            functions: GenusFunctions::default(),
            uber: false,
        }
    }

    /// This key with the genus functions `functions`.
    pub fn with_functions(self, functions: GenusFunctions) -> CloudKey {
        CloudKey { functions, ..self }
    }

    /// `detail-turb-shafts-haze-shadows-bounce-powder-sunsky-o8-dual-g1`: the tags of the
    /// toggles that are on (table order), the octaves, the phase kind, the lane groups, and
    /// `count` for the instrumented shader.
    pub fn name(&self) -> String {
        if self.uber {
            return "uber".into();
        }
        let mut parts: Vec<String> = Toggle::ALL
            .iter()
            .filter(|t| t.get(&self.features))
            .map(|t| t.tag().to_string())
            .collect();
        parts.push(format!("o{}", self.features.octaves));
        parts.push(self.phase.tag().to_string());
        parts.push(format!("g{}", self.groups));
        if let Some(tag) = self.output.tag() {
            parts.push(tag.into());
        }
        if let Some(tag) = self.features.path.tag() {
            parts.push(tag.into());
        }
        parts.extend(function_tags(&self.functions));
        parts.join("-")
    }

    /// Whether the pixels hold `output` (a generation-time choice the model branches on).
    pub fn writes(&self, output: PixelOutput) -> bool {
        self.output == output
    }

    /// The uber-shader's key: one shader for every genus, preset and toggle, branching at run
    /// time on the key uniforms (for measuring what specialisation buys, not for shipping).
    pub fn uber() -> CloudKey {
        let mut features = Features {
            octaves: 12,
            ..Features::default()
        };
        for &t in Toggle::ALL {
            t.set(
                &mut features,
                !matches!(
                    t,
                    Toggle::AccuratePhaseFunction | Toggle::SceneDepth | Toggle::Orthographic
                ),
            );
        }
        CloudKey {
            features,
            phase: PhaseKind::DualLobe,
            groups: 2,
            output: PixelOutput::Composite,
            // The general forms of the profile and the exponent: the uber-shader draws any genus.
            functions: GenusFunctions {
                profile: crate::model::genus_fns::EXPONENTIAL_PROFILE,
                exponent: crate::model::genus_fns::WEATHER_EXPONENT,
                ..GenusFunctions::default()
            },
            uber: true,
        }
    }

    /// Every canonical key of the built-in genus functions: each combination of the toggles
    /// (light shafts only with haze; the Mie toggle is a phase kind; the accurate air light not
    /// with an orthographic camera, which integrates the air anyway; the flat high layer, the
    /// untiled weather, the engine's scene depth and an orthographic camera with any of them),
    /// 1–12 octaves (one with the diffusion, which replaces the others), the five phase kinds
    /// and one or two lane groups: (4,608 × 12 + 4,608) × 5 × 2 = 599,040 keys, each drawn by
    /// the volume. A genus' own functions multiply these by its choices (see
    /// [`CloudKey::with_functions`]), and each baked path (`crate::Path`) by its own: a path's
    /// keys are these with the path set, less the orthographic camera and the flat layer.
    pub fn reachable() -> Vec<CloudKey> {
        let toggles: Vec<Toggle> = Toggle::ALL
            .iter()
            .copied()
            .filter(|t| *t != Toggle::AccuratePhaseFunction)
            .collect();
        let mut out = Vec::new();
        for bits in 0u32..(1 << toggles.len()) {
            let mut features = Features {
                accurate_phase_function: false,
                ..Features::default()
            };
            for (i, t) in toggles.iter().enumerate() {
                t.set(&mut features, bits & (1 << i) != 0);
            }
            if features.light_shafts && !features.haze {
                continue;
            }
            if features.accurate_air_light && features.orthographic {
                continue;
            }
            let most_octaves = if features.diffusion { 1 } else { 12 };
            for octaves in 1..=most_octaves {
                for phase in PhaseKind::ALL {
                    for groups in 1..=2 {
                        out.push(CloudKey {
                            features: Features {
                                octaves,
                                ..features
                            },
                            phase,
                            groups,
                            output: PixelOutput::Composite,
                            functions: GenusFunctions::default(),
                            uber: false,
                        });
                    }
                }
            }
        }
        out
    }

    /// Whether the shader samples the beer shadow map: for cloud shadows, or for light shafts
    /// (which live in the haze).
    pub fn uses_shadow_map(&self) -> bool {
        let f = self.features;
        f.shadows || (f.haze && f.light_shafts)
    }

    /// Whether the key's passes read the air table (`model::air_table`), which its own pass
    /// fills: every key that composites the air's light and does not integrate it per pixel
    /// (in its cloud pass, or in the bake of an impostor that holds the view).
    pub fn reads_air_table(&self) -> bool {
        let f = self.features;
        !f.accurate_air_light
            && !f.orthographic
            && matches!(self.output, PixelOutput::Composite | PixelOutput::Samples)
    }

    /// Whether the shader reads the slice stack (`model::slices`), which its own pass bakes.
    pub fn reads_slices(&self) -> bool {
        !self.uber && self.features.path == crate::Path::Slices
    }

    /// Whether the shader draws the sky from the 2D path's map (`model::blob2d`), which its own
    /// pass bakes.
    pub fn reads_blob2d(&self) -> bool {
        !self.uber && self.features.path == crate::Path::Blob2d
    }

    /// Whether the shader draws the clouds from the impostor path's octahedral map
    /// (`model::impostor`), which its own pass bakes.
    pub fn reads_impostor(&self) -> bool {
        !self.uber && self.features.path == crate::Path::Impostor
    }

    /// Whether the impostor's bake holds the whole picture per direction (the clouds
    /// composited over the sky or the ground, with the air and the haze: `model::impostor`) and
    /// the cloud pass reads it, adding only the sun's disc. Over the engine's depth, and for
    /// the linear layers (the clouds alone, their depth), the bake holds the march's result and
    /// the cloud pass composites it per pixel.
    pub fn bakes_view(&self) -> bool {
        self.reads_impostor()
            && !self.features.scene_depth
            && matches!(self.output, PixelOutput::Composite | PixelOutput::Samples)
    }

    /// Whether the shader draws the clouds from the mesh path's cluster table
    /// (`model::mesh`), which its own pass fits.
    pub fn reads_mesh(&self) -> bool {
        !self.uber && self.features.path == crate::Path::Mesh
    }

    /// The key the impostor's bake marches each direction with: this key drawn by the volume,
    /// less the engine's depth (the bake's rays are directions, not the engine's pixels: the
    /// cloud pass ends the clouds at the scene where it composites them). Its marches to the
    /// sun read the shadow map as the volume's do: the map's cascades are placed by the sun and
    /// the camera's place, not by where the camera looks, so one map serves every direction.
    pub fn impostor_march(&self) -> CloudKey {
        let mut k = *self;
        k.features.path = crate::Path::Volume;
        k.features.scene_depth = false;
        k
    }

    /// Whether the shader reads a bake of its path (`model::bake`): the slice stack, the 2D
    /// map or the impostor.
    pub fn bakes(&self) -> bool {
        !self.uber && self.features.path.bakes()
    }

    /// The key of this shader's shadow pass, when it samples a shadow map.
    pub fn shadow_key(&self) -> Option<ShadowKey> {
        self.uses_shadow_map().then_some(ShadowKey {
            shape_detail: self.features.shape_detail,
            turbulence: self.features.turbulence,
            untiled_weather: self.features.untiled_weather,
            groups: self.groups,
            functions: self.functions,
        })
    }
}

impl SpecValue for CloudKey {
    fn suffix(&self) -> String {
        String::new()
    }

    fn label(&self) -> String {
        self.name()
    }
}

/// What the shadow pass fixes: only what the density depends on, so shaders that differ in
/// lighting share one shadow pipeline and one atlas.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShadowKey {
    pub shape_detail: bool,
    pub turbulence: bool,
    /// The weather without its tile's repetition, as the clouds it shadows have it.
    pub untiled_weather: bool,
    pub groups: u32,
    /// The genus functions the density is made of.
    pub functions: GenusFunctions,
}

impl ShadowKey {
    /// `detail-turb-g1`.
    pub fn name(&self) -> String {
        let mut parts = Vec::new();
        if self.shape_detail {
            parts.push(Toggle::ShapeDetail.tag().to_string());
        }
        if self.turbulence {
            parts.push(Toggle::Turbulence.tag().to_string());
        }
        if self.untiled_weather {
            parts.push(Toggle::UntiledWeather.tag().to_string());
        }
        parts.push(format!("g{}", self.groups));
        parts.extend(function_tags(&self.functions));
        parts.join("-")
    }

    /// Every shadow key: with or without shape detail, turbulence and the untiled weather, one
    /// or two lane groups.
    pub fn reachable() -> Vec<ShadowKey> {
        let mut out = Vec::new();
        for bits in 0..8u32 {
            for groups in 1..=2 {
                out.push(ShadowKey {
                    shape_detail: bits & 1 != 0,
                    turbulence: bits & 2 != 0,
                    untiled_weather: bits & 4 != 0,
                    groups,
                    functions: GenusFunctions::default(),
                });
            }
        }
        out
    }

    /// The cloud key the density functions are specialised with: this key's erosion stages and
    /// groups, with every lighting toggle off (the shadow pass reads none of them).
    pub fn march_key(&self) -> CloudKey {
        let mut features = Features {
            octaves: 1,
            ..Features::default()
        };
        for &t in Toggle::ALL {
            t.set(&mut features, false);
        }
        features.shape_detail = self.shape_detail;
        features.turbulence = self.turbulence;
        features.untiled_weather = self.untiled_weather;
        CloudKey {
            features,
            phase: PhaseKind::Isotropic,
            groups: self.groups,
            output: PixelOutput::Composite,
            functions: self.functions,
            uber: false,
        }
    }
}

/// One tag per genus function that is not the default: its name (`anvil_shape`,
/// `streak_weather`), prefixed by the slot where the name does not end with it (a height
/// function may serve as a shape or as a profile: `profile_anvil_shape`). Underscores keep each
/// tag one part of the dash-separated key name.
fn function_tags(functions: &GenusFunctions) -> Vec<String> {
    functions
        .custom()
        .into_iter()
        .map(|(slot, name)| {
            if name.ends_with(slot) {
                name.to_string()
            } else {
                format!("{slot}_{name}")
            }
        })
        .collect()
}
