//! The catalogue: which shaders exist, named by key. Every genus at every real-time quality
//! preset resolves to a cloud key (and, when it samples a shadow map, a shadow key) plus
//! uniform values; the catalogue holds each distinct key once, with the genus × preset pairs
//! that share it. That is what `nimbus list` shows, `check` validates, `emit` writes and the
//! snapshots pin.

use std::collections::BTreeMap;

use nimbus_dsl::ir::Module;
use nimbus_dsl::{DslError, ShaderVariant, SpecValue};

use crate::key::{CloudKey, ShadowKey};
use crate::model::clouds::{
    CloudVariant, air_table_module, bake_module, cloud_module, display_module, resolve_module,
    shadow_module,
};
use crate::model::preview::{PhaseModel, preview_module};
use crate::{CloudLibrary, Features, Genus, Quality};

/// A shader's identity: its module and the key that fixes its code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShaderKey {
    /// The false-colour preview of a phase function and density profile.
    Preview(PhaseModel),
    /// The cloud march composited over sky and ground.
    Clouds(CloudKey),
    /// The beer shadow map atlas.
    Shadow(ShadowKey),
    /// The air table (one for every key that reads it).
    AirTable,
    /// The bake of a key of a baked path (the slice stack, the 2D map; its density is the
    /// key's).
    Bake(CloudKey),
    /// Temporal upscaling and accumulation (one for every key).
    Resolve,
    /// The display transform: HDR to display sRGB (one for every key).
    Display,
    /// The kernel that completes the cloud block for a moved sun, for engine hosts without
    /// JavaScript (one for every key).
    SunLight,
    /// The clouds' shadow on the engine's objects, per pixel of its depth buffer (one for every
    /// key that reads the engine's depth and has a shadow atlas).
    SceneShadow,
}

impl ShaderKey {
    /// The key's part of the shader's name (`detail-turb-…-g1`).
    pub fn key_name(&self) -> String {
        match self {
            ShaderKey::Preview(m) => m.suffix(),
            ShaderKey::Clouds(k) => k.name(),
            ShaderKey::Shadow(k) => k.name(),
            ShaderKey::AirTable => "table".into(),
            ShaderKey::Bake(k) => k.name(),
            ShaderKey::Resolve => "temporal".into(),
            ShaderKey::Display => "aces-srgb".into(),
            ShaderKey::SunLight => "light".into(),
            ShaderKey::SceneShadow => "sun".into(),
        }
    }

    /// Order in listings: previews, clouds, shadows, resolve; by name within a module.
    fn rank(&self) -> (u8, String) {
        let m = match self {
            ShaderKey::Preview(_) => 0,
            ShaderKey::Clouds(_) => 1,
            ShaderKey::Shadow(_) => 2,
            ShaderKey::AirTable => 3,
            ShaderKey::Bake(_) => 4,
            ShaderKey::Resolve => 5,
            ShaderKey::Display => 6,
            ShaderKey::SunLight => 7,
            ShaderKey::SceneShadow => 8,
        };
        (m, self.key_name())
    }
}

impl ShaderVariant for ShaderKey {
    fn module(&self) -> &str {
        match self {
            ShaderKey::Preview(_) => "preview",
            ShaderKey::Clouds(_) => "clouds",
            ShaderKey::Shadow(_) => "shadow",
            ShaderKey::AirTable => "air",
            ShaderKey::Bake(k) => match k.features.path {
                crate::Path::Blob2d => "blob2d",
                crate::Path::Impostor => "impostor",
                crate::Path::Mesh => "mesh",
                _ => "slices",
            },
            ShaderKey::Resolve => "resolve",
            ShaderKey::Display => "display",
            ShaderKey::SunLight => "sun",
            ShaderKey::SceneShadow => "scene_shadow",
        }
    }

    fn variant(&self) -> String {
        self.key_name()
    }

    fn record(&self) -> Result<Module, DslError> {
        match self {
            ShaderKey::Preview(m) => preview_module(*m),
            ShaderKey::Clouds(k) => cloud_module(k),
            ShaderKey::Shadow(k) => shadow_module(k),
            ShaderKey::AirTable => air_table_module(),
            ShaderKey::Bake(k) => bake_module(k),
            ShaderKey::Resolve => resolve_module(),
            ShaderKey::Display => display_module(),
            ShaderKey::SunLight => crate::model::sun::sun_light_module(),
            ShaderKey::SceneShadow => crate::model::scene_shadow::scene_shadow_module(),
        }
    }
}

/// One genus at one quality preset: the keys it resolves to. The rest is uniform values.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    pub genus: String,
    pub quality: Quality,
    pub clouds: CloudKey,
    pub shadow: Option<ShadowKey>,
}

impl Assignment {
    /// `cumulus.high`.
    pub fn name(&self) -> String {
        format!("{}.{}", self.genus, self.quality.name())
    }

    /// The keys of the shaders this pair runs.
    pub fn keys(&self) -> Vec<ShaderKey> {
        let mut keys = vec![ShaderKey::Clouds(self.clouds)];
        keys.extend(self.shadow.map(ShaderKey::Shadow));
        if self.clouds.reads_air_table() {
            keys.push(ShaderKey::AirTable);
        }
        if self.clouds.bakes() {
            keys.push(ShaderKey::Bake(self.clouds));
        }
        keys
    }
}

/// A catalogue entry: one distinct shader and the genus × preset pairs that run it.
#[derive(Clone, Debug)]
pub struct CatalogEntry {
    pub key: ShaderKey,
    pub description: String,
    /// `cumulus.high`, ... (empty for shaders no genus selects: previews, resolve).
    pub users: Vec<String>,
}

impl ShaderVariant for CatalogEntry {
    fn module(&self) -> &str {
        self.key.module()
    }

    fn variant(&self) -> String {
        self.key.variant()
    }

    fn record(&self) -> Result<Module, DslError> {
        self.key.record()
    }
}

fn describe(key: &ShaderKey) -> String {
    match key {
        ShaderKey::Preview(_) => "false-colour density profile and phase function preview".into(),
        ShaderKey::Clouds(_) => "cloud march over sky and ground".into(),
        ShaderKey::Shadow(_) => "beer shadow map atlas".into(),
        ShaderKey::AirTable => {
            "the air's light per direction and distance (sky view and aerial perspective)".into()
        }
        ShaderKey::Bake(k) if k.reads_blob2d() => {
            "the 2D map: the clouds' columns (optical depths, powder, altitude, sun) around the \
             camera"
                .into()
        }
        ShaderKey::Bake(k) if k.reads_mesh() => {
            "the cluster table: soft puffs fitted to the clouds around the camera (mass, \
             mean, spread, optical depths to the sun)"
                .into()
        }
        ShaderKey::Bake(k) if k.reads_impostor() => {
            "the impostor: the volume's march from the camera in every direction (light, \
             transmittance, front depth)"
                .into()
        }
        ShaderKey::Bake(_) => {
            "the slice stack: density and optical depths per altitude around the camera".into()
        }
        ShaderKey::Resolve => {
            "temporal upscaling and accumulation, reprojection, history clipping".into()
        }
        ShaderKey::Display => "display transform: exposure, ACES, sRGB".into(),
        ShaderKey::SceneShadow => {
            "the clouds' shadow on the engine's objects, per pixel of its depth buffer".into()
        }
        ShaderKey::SunLight => {
            "sun and sky irradiance and shadow cascades for a moved sun, written into the \
             cloud block (engine hosts without JavaScript)"
                .into()
        }
    }
}

/// The shaders no genus selects: the previews and the temporal resolve.
pub fn catalog() -> Vec<CatalogEntry> {
    PhaseModel::ALL
        .iter()
        .map(|m| ShaderKey::Preview(*m))
        .chain([
            ShaderKey::Resolve,
            ShaderKey::Display,
            ShaderKey::SunLight,
            ShaderKey::SceneShadow,
        ])
        .map(|key| CatalogEntry {
            description: describe(&key),
            key,
            users: Vec::new(),
        })
        .collect()
}

/// The keys of `genus` at `quality` with `features`.
pub fn assign(genus: &Genus, quality: Quality, features: Features) -> Assignment {
    let v = CloudVariant::new(genus, quality, features);
    Assignment {
        genus: genus.name.clone(),
        quality,
        clouds: v.key,
        shadow: v.key.shadow_key(),
    }
}

/// Every genus at every real-time quality preset with the preset's features: the genus ×
/// preset → key table.
pub fn assignments(lib: &CloudLibrary) -> Vec<Assignment> {
    lib.genera
        .values()
        .flat_map(|(_, genus)| Quality::ALL.iter().map(|&q| assign(genus, q, q.features())))
        .collect()
}

/// The distinct shaders of `pairs`, each once with the pairs that share it, in listing order.
pub fn distinct(pairs: &[Assignment]) -> Vec<CatalogEntry> {
    let mut users: BTreeMap<(u8, String), (ShaderKey, Vec<String>)> = BTreeMap::new();
    for a in pairs {
        for key in a.keys() {
            users
                .entry(key.rank())
                .or_insert_with(|| (key, Vec::new()))
                .1
                .push(a.name());
        }
    }
    users
        .into_values()
        .map(|(key, users)| CatalogEntry {
            description: describe(&key),
            key,
            users,
        })
        .collect()
}

/// Every distinct cloud and shadow shader the library's genera need at the real-time presets.
pub fn cloud_catalog(lib: &CloudLibrary) -> Vec<CatalogEntry> {
    distinct(&assignments(lib))
}

/// Shaders by id (`clouds-…`, `preview-hg`) or every shader of a module (`clouds`).
pub fn select(name: &str, lib: Option<&CloudLibrary>) -> Vec<CatalogEntry> {
    let mut all = catalog();
    if let Some(lib) = lib {
        all.extend(cloud_catalog(lib));
    }
    let name = name.trim();
    all.into_iter()
        .filter(|e| e.id() == name || e.module() == name)
        .collect()
}
