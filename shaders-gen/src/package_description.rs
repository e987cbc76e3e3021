//! `nimbus-package.json` and the uniform files beside it, as types: what `emit --engine` writes
//! is serialised from these, and the JSON Schema shipped in every package
//! (`nimbus-package.schema.json`, `nimbus-uniforms.schema.json`) is derived from the same types,
//! so the description, its schema and its readers cannot drift apart.

use std::collections::BTreeMap;

use nimbus_clouds::model::resource::{Resource, ResourceKind};
use nimbus_codegen::manifest::BufferSizes;
use schemars::JsonSchema;
use serde::Serialize;

/// The package description's file.
pub(crate) const PACKAGE_FILE: &str = "nimbus-package.json";
/// Its JSON Schema (draft 2020-12), beside it.
pub(crate) const PACKAGE_SCHEMA_FILE: &str = "nimbus-package.schema.json";
/// The JSON Schema of every file under `uniforms/`.
pub(crate) const UNIFORMS_SCHEMA_FILE: &str = "nimbus-uniforms.schema.json";

/// The description's format; a reader refuses another.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// A Nimbus engine package: the pass graph of every genus × preset pair, the render targets, the
/// textures and the conventions an engine follows to draw the first frame right.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct PackageDescription {
    /// The schema of this file, beside it in the package.
    #[serde(rename = "$schema")]
    pub schema: String,
    /// The description's format (1).
    pub nimbus_package: u32,
    /// The engine the package is for (`three`, `webgpu`, `wgpu`, `vulkan`, `unity`, `metal`).
    pub engine: String,
    /// The shader language of its files.
    pub language: String,
    /// What makes the first frame right, by topic.
    pub conventions: BTreeMap<String, String>,
    /// How the shader files' bindings are named in this language.
    pub bindings: String,
    /// The passes of a frame, in order, in words.
    pub frame: Vec<String>,
    /// How the temporal members are computed each frame.
    pub temporal: Temporal,
    /// Every resource a pass binds, by id: how a host provides it and what it holds.
    pub resources: Vec<ResourceEntry>,
    /// The render targets the host creates.
    pub targets: Targets,
    /// The noise textures, as files of the package.
    pub textures: Vec<TextureDescriptor>,
    /// What made the texels.
    pub textures_generated_by: String,
    /// The half float (IEEE 754 binary16 bits) that each byte `k` of a texture file stands
    /// for, indexed by `k`: `k/255` rounded to the nearest half float. The textures are
    /// uploaded as half floats through this table, as Nimbus's runtime holds them: a GPU that
    /// filters an 8-bit texture in 8-bit arithmetic rounds every filtered value, and the
    /// coverage threshold keeps that rounding as a faint halo of opacity around each cloud.
    pub texel_halves: Vec<u16>,
    /// Each genus × preset pair: its uniform file and its passes.
    pub pairs: Vec<Pair>,
}

/// The temporal sequence's contract.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct Temporal {
    pub sequence: String,
}

/// One resource of the passes' bindings.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct ResourceEntry {
    pub id: Resource,
    pub kind: ResourceKind,
    pub holds: String,
}

impl ResourceEntry {
    pub(crate) fn of(id: Resource) -> Self {
        Self {
            id,
            kind: id.kind(),
            holds: id.holds().to_string(),
        }
    }
}

/// The render targets, by the resource ids that name them.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct Targets {
    pub shadow_atlas: Target,
    pub air_table: Target,
    pub cloud_bake: Target,
    pub clouds_hdr: Target,
    pub scene_shadow: Target,
    pub history_a: Target,
    pub history_b: Target,
    pub screen: Target,
}

/// One render target.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct Target {
    /// Its texel format, in WebGPU's spelling.
    pub format: String,
    /// Its size, in words.
    pub size: String,
    /// How the passes that read it sample it, where that matters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampled_as: Option<String>,
}

/// Whether a texture file holds a plane or a volume.
#[derive(Clone, Copy, Serialize, JsonSchema)]
pub(crate) enum TextureDimension {
    #[serde(rename = "2d")]
    D2,
    #[serde(rename = "3d")]
    D3,
}

/// One noise texture file.
#[derive(Clone, Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct TextureDescriptor {
    /// The resource it is (`weather`, `shape`, `detail`, `turbulence`).
    pub name: Resource,
    /// Its file in the package.
    pub file: String,
    pub dimension: TextureDimension,
    /// Texels per side: two numbers for 2D, three for 3D.
    pub size: Vec<u32>,
    /// The texel format to create, in WebGPU's spelling (`rgba16float`: the file's bytes
    /// widened through `texel_halves`).
    pub format: String,
    /// The texel format of the file, in WebGPU's spelling.
    pub file_format: String,
    /// How the file's bytes are laid out.
    pub layout: String,
    pub colour_space: String,
    pub address_mode: String,
    pub filter: String,
    pub mipmaps: bool,
}

/// What a pair's key asks of the host's camera.
#[derive(Clone, Copy, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub(crate) enum CameraKind {
    Perspective,
    Orthographic,
}

/// The size of a pair's shadow atlas (its cascades in a grid of tiles) or air table.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct AtlasSize {
    pub width: u32,
    pub height: u32,
}

/// The bake of a pair drawn by a baked path (`slices`, `impostor`, `mesh`, `blob2d`): its size, and what does not
/// make it out of date. The bake depends on the pair's block less these members (the view, the
/// frame's jitter, the composite's switches, the haze and the shadow cascades); a host redraws
/// it when any other member changed since it was drawn (drawing it every frame is correct too).
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct Bake {
    pub width: u32,
    pub height: u32,
    /// Member paths of the block (a member and everything under it) the bake ignores.
    pub ignores: Vec<String>,
}

/// One genus × preset pair.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct Pair {
    /// `<genus>.<preset>`.
    pub pair: String,
    pub genus: String,
    pub quality: String,
    /// Its cloud block's uniform file.
    pub uniforms: String,
    /// What the host's camera must be for this pair's key.
    pub camera: CameraKind,
    /// Whether the pair reads the engine's depth buffer (`scene_depth` then has to be given
    /// with each frame).
    pub scene_depth: bool,
    /// The shadow atlas's size, when the pair has one.
    pub shadow_atlas: Option<AtlasSize>,
    /// The air table's size, when the pair has an air pass.
    pub air_table: Option<AtlasSize>,
    /// The bake, when the pair is drawn by a baked path.
    pub cloud_bake: Option<Bake>,
    /// Its passes, in the order of a frame.
    pub passes: Vec<PassDescription>,
}

/// The passes of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Pass {
    SunLight,
    Shadow,
    /// The clouds' shadow on the engine's objects.
    SceneShadow,
    /// The air table the clouds pass reads (`air_table`).
    Air,
    /// The bake the clouds pass reads (`cloud_bake`; the baked paths).
    Bake,
    Clouds,
    Resolve,
    Display,
}

/// One pass of a pair.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct PassDescription {
    pub pass: Pass,
    /// The shader's id (`<module>-<key>`).
    pub shader: String,
    pub language: String,
    /// The module's entry points by stage (`vertex`, `fragment`, `compute`).
    pub entry_points: BTreeMap<String, String>,
    /// Its files (a WGSL file holds every entry point; other languages have a file each).
    pub files: Vec<ShaderFile>,
    /// Every binding slot, with the resource it holds.
    pub bindings: Vec<BindingDescription>,
    /// WebGPU and wgpu: the `GPUBindGroupLayoutDescriptor`, to hand to the API as it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bind_group_layout: Option<BindGroupLayout>,
    /// Vulkan: the descriptor-set layout.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub descriptor_set_layout: Option<DescriptorSetLayout>,
    /// Compute passes: the workgroups to dispatch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dispatch: Option<[u32; 3]>,
    /// What the pass writes: one of `targets` (its whole area), or for `sun_light` the `pair`
    /// block.
    pub writes: Output,
    /// Vulkan: the barriers to record before the pass, as the pass graph implies them (what an
    /// earlier pass wrote and this one reads, and this pass's own target).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vulkan_barriers: Option<Vec<VulkanBarrier>>,
}

/// What a pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Output {
    /// The `pair` block (storage + uniform), completed by the `sun_light` kernel.
    Pair,
    ShadowAtlas,
    SceneShadow,
    AirTable,
    CloudBake,
    CloudsHdr,
    /// The history target not read this frame (`history_a` and `history_b` alternate).
    History,
    /// The picture: the swapchain image or the engine's next pass.
    Screen,
}

/// A `vkCmdPipelineBarrier` before a pass: a `VkBufferMemoryBarrier` for a block, a
/// `VkImageMemoryBarrier` (with its layouts) for a target. Flags are `|`-joined names.
#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct VulkanBarrier {
    /// The resource id (`pair`, `shadow_atlas`, …) or, for the pass's own target, the target.
    pub resource: String,
    /// Why the barrier is there.
    pub reason: String,
    pub src_stage_mask: String,
    pub src_access_mask: String,
    pub dst_stage_mask: String,
    pub dst_access_mask: String,
    /// Images: the layout before and after.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub old_layout: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub new_layout: Option<String>,
}

/// One shader file of a pass.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct ShaderFile {
    pub file: String,
    /// Its entry point, where the file holds one (null for WGSL, which holds them all).
    pub entry_point: Option<String>,
    pub stage: Option<String>,
    /// Its binding manifest, beside it.
    pub manifest: Option<String>,
    /// MSL: the buffer of storage-buffer sizes.
    pub buffer_sizes: Option<BufferSizes>,
}

/// One binding slot of a pass.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct BindingDescription {
    pub group: u32,
    pub binding: u32,
    /// The name the WGSL source gives it.
    pub name: String,
    /// `uniform`, `storage`, `texture` or `sampler`.
    pub kind: String,
    pub wgsl_type: String,
    /// What a host binds there.
    pub holds: ResourceEntry,
    /// How each file names it.
    pub in_files: Vec<NameInFile>,
}

/// How one file names a binding: directly, or as a GLSL combined sampler.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct NameInFile {
    pub stage: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub combined_sampler: Option<String>,
}

/// A `GPUBindGroupLayoutDescriptor` (its group's index beside it).
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct BindGroupLayout {
    pub group: u32,
    pub entries: Vec<GpuLayoutEntry>,
}

/// A `GPUBindGroupLayoutEntry` as the API takes it; `visibilityNames` and `samplerDescriptor`
/// are Nimbus's (the API ignores members it does not know).
#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct GpuLayoutEntry {
    pub binding: u32,
    /// `GPUShaderStage` flags: VERTEX 1, FRAGMENT 2, COMPUTE 4.
    pub visibility: u32,
    pub visibility_names: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buffer: Option<GpuBufferLayout>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<GpuTextureLayout>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler: Option<GpuSamplerLayout>,
    /// The `GPUSamplerDescriptor` to create the sampler with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler_descriptor: Option<SamplerDescriptor>,
}

#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct GpuBufferLayout {
    /// `uniform`, `storage` or `read-only-storage`.
    #[serde(rename = "type")]
    pub kind: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_binding_size: Option<u64>,
}

#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct GpuTextureLayout {
    /// `float`, or `unfilterable-float` for the engine's depth.
    pub sample_type: String,
    /// `2d` or `3d`.
    pub view_dimension: String,
}

#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct GpuSamplerLayout {
    /// `filtering`.
    #[serde(rename = "type")]
    pub kind: String,
}

/// A sampler's state in WebGPU's spelling (`GPUSamplerDescriptor`); Vulkan's modes are the same.
#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct SamplerDescriptor {
    pub address_mode_u: String,
    pub address_mode_v: String,
    pub address_mode_w: String,
    pub mag_filter: String,
    pub min_filter: String,
    pub mipmap_filter: String,
}

/// A Vulkan descriptor-set layout.
/// A sampler's state as `VkSamplerCreateInfo` fields, by enum name.
#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct VulkanSampler {
    /// `VK_FILTER_*`.
    pub mag_filter: String,
    pub min_filter: String,
    /// `VK_SAMPLER_MIPMAP_MODE_*`.
    pub mipmap_mode: String,
    /// `VK_SAMPLER_ADDRESS_MODE_*`.
    pub address_mode_u: String,
    pub address_mode_v: String,
    pub address_mode_w: String,
}

#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct DescriptorSetLayout {
    pub set: u32,
    pub bindings: Vec<VulkanLayoutBinding>,
}

/// A `VkDescriptorSetLayoutBinding`; `stageFlagNames` and `sampler` are Nimbus's.
#[derive(Serialize, JsonSchema)]
#[serde(rename_all = "camelCase")]
#[schemars(deny_unknown_fields)]
pub(crate) struct VulkanLayoutBinding {
    pub binding: u32,
    /// `VK_DESCRIPTOR_TYPE_*`.
    pub descriptor_type: String,
    pub descriptor_count: u32,
    /// `VkShaderStageFlags`: VERTEX 0x1, FRAGMENT 0x10, COMPUTE 0x20.
    pub stage_flags: u32,
    pub stage_flag_names: String,
    /// Samplers: the state to create it with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler: Option<VulkanSampler>,
}

/// A uniform file (`uniforms/*.json`): one block's bytes and its members.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct UniformBlockFile {
    /// The schema of this file, at the package's root.
    #[serde(rename = "$schema")]
    pub schema: String,
    /// Bytes, a multiple of 16.
    pub size: usize,
    /// How the members are laid out, in words.
    pub layout: String,
    /// The whole block, two hex digits a byte.
    pub bytes_hex: String,
    pub members: Vec<BlockMember>,
    /// The pair, for a pair's cloud block.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pair: Option<String>,
    /// The scene the values are for, for a pair's cloud block.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
}

/// One leaf member of a uniform block.
#[derive(Serialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct BlockMember {
    /// Dotted path with array indices (`groups[1].min_height`).
    pub member: String,
    /// Bytes from the block's start.
    pub offset: u32,
    /// Its WGSL type.
    #[serde(rename = "type")]
    pub ty: String,
    /// Its scalar components (matrices column by column).
    pub value: Vec<f64>,
    /// When a host sets it, where that is not never.
    pub set: Option<String>,
}

/// The schema files of a package: `(file, pretty JSON)`.
pub(crate) fn schema_files() -> Vec<(&'static str, Vec<u8>)> {
    [
        (
            PACKAGE_SCHEMA_FILE,
            schemars::schema_for!(PackageDescription),
        ),
        (
            UNIFORMS_SCHEMA_FILE,
            schemars::schema_for!(UniformBlockFile),
        ),
    ]
    .into_iter()
    .map(|(file, schema)| (file, pretty(&schema)))
    .collect()
}

/// Pretty JSON with a trailing newline.
pub(crate) fn pretty<T: Serialize>(v: &T) -> Vec<u8> {
    let mut s = serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("\"{e}\""));
    s.push('\n');
    s.into_bytes()
}
