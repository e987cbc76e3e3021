//! Binding manifests: JSON written beside each GLSL, HLSL and MSL file so another engine can
//! bind uniforms and textures by name (naga renames them per target), plus the uniform struct
//! layouts and the override values that were baked in.

use serde::Serialize;

/// One resource binding of an entry point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ManifestBinding {
    /// The WGSL (source) name of the global.
    pub name: String,
    /// `uniform`, `storage`, `texture` or `sampler`.
    pub kind: &'static str,
    pub group: u32,
    pub binding: u32,
    /// The WGSL type.
    pub wgsl_type: String,
    /// What to bind in the target: a GLSL block name, an HLSL register, an MSL slot. Empty
    /// for GLSL textures and samplers, which GLSL only knows combined: see `combined_samplers`.
    pub target_name: String,
    /// Address and filter modes, for samplers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler: Option<ManifestSampler>,
}

/// A sampler's state as WebGPU spells it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ManifestSampler {
    /// `repeat`, `clamp-to-edge` or `mirror-repeat`, on every axis.
    pub address_mode: &'static str,
    /// `nearest` or `linear`, for magnification, minification and mipmaps.
    pub filter: &'static str,
}

/// One GLSL combined sampler (`uniform sampler2D name;`): the texture and sampler bindings it
/// joins, and the state to create it with.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CombinedSampler {
    /// The name in the GLSL source, as naga wrote it.
    pub name: String,
    /// The WGSL names of the texture and the sampler it combines (none for a texture the
    /// entry point only loads by texel, with `texelFetch`).
    pub texture: String,
    pub sampler: Option<String>,
    pub address_mode: &'static str,
    pub filter: &'static str,
}

/// One member of a uniform struct, with its byte offset (from naga's layout).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ManifestField {
    pub name: String,
    /// The member's name in the target language (naga appends `_` to names ending in a digit).
    pub target_name: String,
    pub wgsl_type: String,
    pub offset: u32,
}

/// A struct's layout.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ManifestStruct {
    pub name: String,
    pub size: u32,
    pub fields: Vec<ManifestField>,
}

/// A pipeline-overridable constant and the value baked into this output.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ManifestOverride {
    pub name: String,
    pub value: f64,
}

/// MSL's `_mslBufferSizes` argument: a `uint` per runtime-sized storage buffer, holding its
/// size in bytes.
#[derive(Clone, Debug, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BufferSizes {
    /// `[[buffer(N)]]`: the slot after the declared buffers.
    pub target_name: String,
    pub members: Vec<BufferSize>,
}

/// One member of [`BufferSizes`].
#[derive(Clone, Debug, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BufferSize {
    /// `size1`.
    pub member: String,
    /// The WGSL name of the storage buffer whose byte size it holds.
    pub binding: String,
}

/// Everything a host needs to bind one file of one target.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BindingManifest {
    pub module: String,
    pub variant: String,
    pub target: String,
    /// The file's entry points by stage (`vertex`, `fragment`, `compute`): one in a GLSL or
    /// MSL file, every one of the module in an HLSL file.
    pub entry_points: std::collections::BTreeMap<String, String>,
    pub bindings: Vec<ManifestBinding>,
    /// GLSL only: every combined sampler the entry point declares.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub combined_samplers: Vec<CombinedSampler>,
    /// MSL only, when a storage buffer is runtime-sized: the extra buffer of byte sizes the
    /// host binds beside the declared ones.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buffer_sizes: Option<BufferSizes>,
    pub structs: Vec<ManifestStruct>,
    pub overrides: Vec<ManifestOverride>,
}

impl BindingManifest {
    /// Pretty JSON with a trailing newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self)
            .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
        s.push('\n');
        s
    }
}
