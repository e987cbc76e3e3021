//! Rendering a frame: the passes a cloud variant needs, and only those.
//!
//! 1. Shadow: the beer shadow map atlas, when the variant samples it (shadows, or light shafts
//!    in haze), and only when its inputs changed since it was last drawn (sun, layers,
//!    weather, variant). Otherwise neither its pipeline nor its texture exists.
//! 2. Clouds: the march composited over the sky or ground, at full resolution or one pixel in
//!    sixteen (temporal upscaling).
//! 3. Resolve: reconstruction of the full image from the history, when upscaling or when
//!    several frames are accumulated.
//!
//! Textures are made on first use, and only those the variant's shader binds: a variant
//! without shape detail never creates the detail texture.

use std::collections::{BTreeMap, HashMap};

use glam::{Mat4, Vec2, Vec3, Vec4};
use half::f16;
use nimbus_clouds::CloudKey;
use nimbus_clouds::Quality;
use nimbus_clouds::catalog::ShaderKey;
use nimbus_clouds::frame_sequence::{cloud_frame, resolve_frame};
use nimbus_clouds::model::air_table::{AirTableInputs, air_table_size};
use nimbus_clouds::model::bake::{bake_inputs, bake_size};
use nimbus_clouds::model::choices::KeyUniforms;
use nimbus_clouds::model::clouds::{CloudBinding, ResolveBinding};
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::resolve::ResolveParams;
use nimbus_clouds::model::shadow::{
    CascadeLookup, anchored_tiles, atlas_columns, redrawn_tiles, shadow_anchor,
};
use nimbus_clouds::model::tile_bands::{BandDraw, TileRedraw, band_redraw, tiles_out_of_date};
use nimbus_clouds::wind::Drift;
use nimbus_codegen::{BindingInfo, BindingKind};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::ir::{AddressMode, FilterMode, SamplerDesc};
use nimbus_dsl::layout::{UniformBytes, align_size};

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::pipelines::{CachedPipeline, HDR_FORMAT, PipelineCache};
use crate::textures::{GpuTexture, NoiseKind};
pub use nimbus_clouds::frame::{Frame, FrameError};

/// Texel counts per side of the procedural textures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureSizes {
    pub weather: u32,
    pub shape: u32,
    pub detail: u32,
    pub turbulence: u32,
}

impl Default for TextureSizes {
    /// The sizes of @takram/three-clouds: 128³ shape, 32³ detail.
    fn default() -> Self {
        Self {
            weather: 512,
            shape: 128,
            detail: nimbus_clouds::model::noise::DETAIL_SIZE,
            turbulence: 128,
        }
    }
}

impl TextureSizes {
    fn of(&self, kind: NoiseKind) -> u32 {
        match kind {
            NoiseKind::Weather => self.weather,
            NoiseKind::Shape => self.shape,
            NoiseKind::Detail => self.detail,
            NoiseKind::Turbulence => self.turbulence,
        }
    }
}

/// Linear HDR pixels, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl Image {
    /// Whether no pixel has any light (a night sky, or an adapter that drew nothing).
    pub fn is_black(&self) -> bool {
        self.pixels.iter().all(|p| p[0].max(p[1]).max(p[2]) <= 0.0)
    }
}

/// What the renderer has created, for tests and reports: a toggle that is off must leave no
/// trace here.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Pipelines built so far (pass and key).
    pub pipelines: Vec<String>,
    /// Textures allocated so far, by role.
    pub textures: Vec<String>,
    /// Passes recorded by the last `render` call, in order, one entry per pass.
    pub passes: Vec<&'static str>,
}

/// The uniform bytes one frame of a `render` call wrote: the cloud block and, when the frame
/// was resolved, the resolve block (see [`Renderer::set_uniform_log`]).
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenFrame {
    pub clouds: Vec<u8>,
    pub resolve: Option<Vec<u8>>,
}

/// Where a cloud texture comes from.
pub enum TextureSource {
    /// Generated on the GPU by the noise kernels.
    Procedural,
    /// Supplied by the user (see [`crate::user_textures`]).
    User(GpuTexture),
}

/// A render target that is also sampled (cloud output, history, shadow atlas).
struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
}

/// History kept between frames: two targets the resolve ping-pongs between.
struct History {
    targets: [Target; 2],
    /// Index of the target holding the latest resolved frame.
    latest: usize,
    upscale: bool,
    view_projection: Mat4,
    /// The wind's drift at the latest frame (the clouds' move since is the next frame's shift).
    wind: Drift,
    frames: u32,
}

/// A bind group and the resource epoch it was made in: it is remade only when a resource it
/// may reference was replaced (see [`Renderer::epoch`]) or its pipeline changed.
struct BoundGroup {
    group: wgpu::BindGroup,
    key: ShaderKey,
    epoch: u64,
}

/// The shadow pass: its uniform buffer, bind group and atlas, kept across frames.
struct ShadowPass {
    uniform: wgpu::Buffer,
    group: Option<BoundGroup>,
    atlas: Target,
    /// What the atlas was last rendered from (key and uniform bytes): it is redrawn only when
    /// the sun, the layers, the weather or the key change.
    inputs: Option<(ShaderKey, Vec<u8>)>,
    /// A change of the pass's key alone being spread over frames (no-stall): the new key and
    /// how many bands of cascade tiles ([`REFRESH_BAND`]), finest first, it has redrawn.
    refreshing: Option<(ShaderKey, u32)>,
    /// Cascades in rotation ([`Renderer::set_cascade_rotation`]): every tile's transform as
    /// drawn, relative to the clouds' anchor (`None` until the atlas is drawn whole), and where
    /// the redraw in bands stands ([`band_redraw`]).
    tiles: Option<CascadeLookup>,
    redraw: TileRedraw,
    /// The tile in progress: what its bands are drawn from, and the atlas they are drawn into
    /// (made with the first band), its square copied into `atlas` with the last.
    banded: Option<BandedTile>,
    back: Option<Target>,
}

/// What a cascade tile drawn in bands is drawn from, taken with its first band: the block as
/// it stood, with the sun's lookup and the clouds' anchor of that frame, which the tile keeps
/// once its last band is drawn.
struct BandedTile {
    key: ShaderKey,
    block: CloudUniforms,
    current: CascadeLookup,
    anchor: Vec3,
}

/// Texel rows of the shadow atlas redrawn per frame when only the shadow key changed (with
/// no-stall): a 512-texel tile of `high` in four bands, each about the cost of a frame at
/// 160×90 on llvmpipe (a whole tile was five).
const REFRESH_BAND: u32 = 128;

/// A full-screen pass into a target of its own, kept across frames and redrawn only when what
/// it is drawn from (`I`) changes: its uniform buffer, bind group and target.
struct CachedPass<I> {
    uniform: wgpu::Buffer,
    group: Option<BoundGroup>,
    target: Target,
    inputs: Option<I>,
}

impl<I> CachedPass<I> {
    fn new(gpu: &Gpu, label: &str, uniform_size: usize, (w, h): (u32, u32)) -> Self {
        CachedPass {
            uniform: uniform_buffer(gpu, &format!("{label} uniforms"), uniform_size),
            group: None,
            target: target(gpu, label, w, h),
            inputs: None,
        }
    }
}

/// The air table pass, redrawn when the sun, the camera's altitude or the atmosphere changes.
type AirPass = CachedPass<AirTableInputs>;

/// The air table drawn in bands (cascades in rotation, [`Renderer::set_cascade_rotation`]), as
/// a shadow tile is ([`band_redraw`], one tile): where the redraw stands, the inputs it was
/// last asked for, the block (and its inputs) the bands in progress are drawn from, and the
/// table they are drawn into, copied into the air pass's with the last band.
struct AirBands {
    redraw: TileRedraw,
    requested: AirTableInputs,
    drawing: Option<(CloudUniforms, AirTableInputs)>,
    back: Target,
}

/// The bake pass (the baked paths: the slice stack, the 2D map), redrawn when its key or what
/// the bake depends on changes (the sun, the camera's place, the layers, the weather; not the
/// view).
/// The bake's inputs: its key, the block members it depends on, and the air table's
/// generation (the renderer's `air_generation`: a table drawn in bands reaches the bake frames
/// after the block's sun moved).
type BakePass = CachedPass<(ShaderKey, nimbus_dsl::layout::Members, u64)>;

/// The cloud pass: its uniform buffer, bind group and low-resolution target.
struct CloudPass {
    uniform: wgpu::Buffer,
    group: Option<BoundGroup>,
    target: Target,
}

/// The resolve pass: its uniform buffer and one bind group per ping-pong direction.
struct ResolvePass {
    uniform: wgpu::Buffer,
    groups: [Option<BoundGroup>; 2],
}

/// Timestamp queries around every pass of one `render` call, and the buffers they resolve
/// into; kept while the capacity suffices.
struct PassTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    capacity: u32,
    used: u32,
}

impl PassTimer {
    /// Timestamp writes for the next pass, or none when the adapter has no timestamps or the
    /// set is full.
    fn next(timer: &mut Option<PassTimer>) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let t = timer.as_mut()?;
        if t.used + 2 > t.capacity {
            return None;
        }
        t.used += 2;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &t.queries,
            beginning_of_pass_write_index: Some(t.used - 2),
            end_of_pass_write_index: Some(t.used - 1),
        })
    }
}

/// A renderer over one GPU. Each pass owns its uniform buffer, bind group and target and keeps
/// them across frames; textures are made on first use and only those a pipeline binds;
/// pipelines are cached by shader key. After the first frame of a given size and key, a
/// frame creates no buffer, texture or bind group.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    sizes: TextureSizes,
    textures: BTreeMap<NoiseKind, GpuTexture>,
    user: BTreeMap<NoiseKind, GpuTexture>,
    samplers: HashMap<SamplerDesc, wgpu::Sampler>,
    pipelines: PipelineCache,
    shadow: Option<ShadowPass>,
    air: Option<AirPass>,
    air_bands: Option<AirBands>,
    /// Bumped whenever the air table the passes read changes (drawn whole, or a table drawn
    /// in bands copied in).
    air_generation: u64,
    bake: Option<BakePass>,
    clouds: Option<CloudPass>,
    resolve: Option<ResolvePass>,
    history: Option<History>,
    timer: Option<PassTimer>,
    readback: Option<wgpu::Buffer>,
    /// Bumped whenever a texture a bind group may reference is replaced.
    epoch: u64,
    passes: Vec<&'static str>,
    /// GPU time of the passes of the last `render` call, where the adapter has timestamps.
    gpu_time_ms: Option<f64>,
    /// Render the cloud pass with the uber-shader (every key choice a run-time branch).
    uber: bool,
    /// The uber-shader's key uniforms, and the stand-in shadow map it binds when the frame
    /// has no shadow pass.
    uber_resources: Option<(wgpu::Buffer, Target)>,
    /// No stall when the effects change ([`Self::set_no_stall`]).
    no_stall: bool,
    /// One out-of-date cascade tile redrawn per frame ([`Self::set_cascade_rotation`]).
    cascade_rotation: bool,
    /// The last specialised cloud key drawn with: the stand-in while a new key is built.
    last_clouds: Option<CloudKey>,
    /// Whether the last frame drew its clouds with a stand-in while its own key was built.
    stand_in: bool,
    /// Every frame's uniform bytes, while logging (tests that hold engine hosts to the
    /// runtime's frame sequence).
    uniform_log: Option<Vec<WrittenFrame>>,
    /// The engine's depth and its encoding for `scene-depth` keys, replaced with each frame's.
    scene: Option<(wgpu::Buffer, GpuTexture)>,
}

/// The cloud bindings a pipeline keeps (typed, by slot).
fn cloud_bindings(p: &CachedPipeline) -> impl Iterator<Item = (&BindingInfo, CloudBinding)> {
    p.bindings
        .iter()
        .filter_map(|b| CloudBinding::at(b.group, b.binding).map(|c| (b, c)))
}

fn wgpu_sampler(gpu: &Gpu, desc: SamplerDesc) -> wgpu::Sampler {
    let address = match desc.address {
        AddressMode::Repeat => wgpu::AddressMode::Repeat,
        AddressMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        AddressMode::MirrorRepeat => wgpu::AddressMode::MirrorRepeat,
    };
    let filter = match desc.filter {
        FilterMode::Nearest => wgpu::FilterMode::Nearest,
        FilterMode::Linear => wgpu::FilterMode::Linear,
    };
    gpu.sampler(
        &format!("{} {}", desc.filter.name(), desc.address.name()),
        address,
        filter,
    )
}

fn uniform_buffer(gpu: &Gpu, label: &str, size: usize) -> wgpu::Buffer {
    gpu.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        // Whole 16-byte words, which a flattened block binds.
        size: size.div_ceil(16) as u64 * 16,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn target(gpu: &Gpu, label: &str, width: u32, height: u32) -> Target {
    target_of(gpu, label, width, height, HDR_FORMAT)
}

fn target_of(
    gpu: &Gpu,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
) -> Target {
    let texture = gpu.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        // Copies in too: a cascade tile drawn in bands reaches the shadow atlas by a copy.
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    Target {
        texture,
        view,
        width,
        height,
        format,
    }
}

/// A buffer the GPU copies a target into for the CPU to read.
fn readback_buffer(gpu: &Gpu, size: u64) -> wgpu::Buffer {
    gpu.create_buffer(&wgpu::BufferDescriptor {
        label: Some("frame readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn size_of(t: &Target) -> (u32, u32) {
    (t.width, t.height)
}

impl<'g> Renderer<'g> {
    pub fn new(gpu: &'g Gpu, sizes: TextureSizes) -> Self {
        Renderer {
            gpu,
            sizes,
            textures: BTreeMap::new(),
            user: BTreeMap::new(),
            samplers: HashMap::new(),
            pipelines: PipelineCache::default(),
            shadow: None,
            air: None,
            air_bands: None,
            air_generation: 0,
            bake: None,
            clouds: None,
            resolve: None,
            history: None,
            timer: None,
            readback: None,
            epoch: 0,
            passes: Vec::new(),
            gpu_time_ms: None,
            uber: false,
            uber_resources: None,
            no_stall: false,
            cascade_rotation: false,
            last_clouds: None,
            stand_in: false,
            uniform_log: None,
            scene: None,
        }
    }

    /// No stall when a scene's effects change (a toggle, a preset), for game loops: the
    /// pipelines of a key this renderer has not drawn with are built on threads of their own,
    /// and until they are ready the clouds are drawn with the key drawn before (the same genus
    /// functions: the effects switch a few frames late) and the shadow atlas drawn before
    /// stays. A genus of other functions waits for its own key: no pipeline without its code
    /// can draw its shapes. When the shadow pass's key changes and nothing else does (the
    /// clouds and the sun where they were), the atlas is redrawn a band of a cascade tile per
    /// frame ([`REFRESH_BAND`] texel rows), the finest cascade first. Only the very first frame, with nothing to draw with, waits. Off by
    /// default: an image rendered once is drawn whole with its own key.
    pub fn set_no_stall(&mut self, on: bool) {
        self.no_stall = on;
    }

    /// Cascades in rotation, for game loops whose sun, camera or wind moves every frame: once
    /// the shadow atlas has been drawn whole, a change of what it shows makes every tile out
    /// of date and each frame draws a band of one of them ([`band_redraw`]: at most
    /// `BAND_TEXELS` texels), in turn, instead of the whole atlas, into a back atlas from the
    /// block as it stood at the tile's first band; the tile is copied into the atlas with its
    /// last. Each tile is read through the transform it was drawn with, moved to where its
    /// clouds are now (`shadow::redrawn_tiles`, `shadow::anchored_tiles`, as the JavaScript
    /// hosts do), so a tile a few frames old shows the clouds' shadows for a sun a few frames
    /// old, in the right place. The air table, once drawn whole, is redrawn in bands likewise.
    /// Off by default: an image rendered once is drawn with its whole atlas and table.
    pub fn set_cascade_rotation(&mut self, on: bool) {
        if !on {
            // Tiles left out of date or half drawn by the rotation are redrawn whole on the next
            // frame (read through the sun as it is, they would show shadows out of place); a
            // table in progress is dropped (the air table is redrawn whole when out of date).
            if let Some(p) = &mut self.shadow
                && (p.redraw.stale != 0 || p.redraw.band != 0)
            {
                p.inputs = None;
                p.redraw = TileRedraw::default();
                p.banded = None;
            }
            self.air_bands = None;
        }
        self.cascade_rotation = on;
    }

    /// Whether the last frame drew its clouds with a stand-in because its own key's pipeline
    /// was still being built ([`Self::set_no_stall`]).
    pub fn drew_stand_in(&self) -> bool {
        self.stand_in
    }

    /// Renders the cloud pass with the uber-shader: the same model with every generation-time
    /// choice (toggles, octaves, phase kind, layer groups) read from uniforms and branched on
    /// at run time, to measure what specialisation buys. Images match the specialised shaders'.
    pub fn set_uber_shader(&mut self, on: bool) {
        if self.uber != on {
            self.uber = on;
            self.epoch += 1;
        }
    }

    /// Binds every uniform block as an array of `vec4` words unpacked by the shader, the layout
    /// of the three.js engine package; images match the struct-bound shaders'.
    pub fn set_flat_uniforms(&mut self, on: bool) {
        self.pipelines.set_flat_uniforms(on);
        self.epoch += 1;
    }

    /// Creates every later pipeline from `input` (the lowered module by default; the printed
    /// WGSL to show that both draw the same picture).
    pub fn set_shader_input(&mut self, input: crate::ShaderInput) {
        self.pipelines.set_shader_input(input);
        self.epoch += 1;
    }

    /// Keeps (or stops keeping, and forgets) the bytes of every cloud and resolve block the
    /// frames write, in order: what an engine host must write for the same frames.
    pub fn set_uniform_log(&mut self, on: bool) {
        self.uniform_log = on.then(Vec::new);
    }

    /// The blocks written since logging began.
    pub fn uniform_log(&self) -> &[WrittenFrame] {
        self.uniform_log.as_deref().unwrap_or(&[])
    }

    /// Uses a user texture for `kind` instead of the procedural one.
    pub fn set_texture(&mut self, kind: NoiseKind, source: TextureSource) {
        self.textures.remove(&kind);
        match source {
            TextureSource::Procedural => {
                self.user.remove(&kind);
            }
            TextureSource::User(t) => {
                self.user.insert(kind, t);
            }
        }
        self.epoch += 1;
        // The atlas and the bake were baked from the old texture: redraw them.
        if let Some(p) = &mut self.shadow {
            p.inputs = None;
        }
        if let Some(p) = &mut self.bake {
            p.inputs = None;
        }
    }

    /// Pipelines built so far (one per shader key).
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.built().len()
    }

    pub fn stats(&self) -> RenderStats {
        let role = |k: &NoiseKind| format!("{}_texture", k.name());
        let mut textures: Vec<String> = self.textures.keys().map(role).collect();
        textures.extend(self.user.keys().map(|k| format!("{} (user)", role(k))));
        if let Some(s) = &self.shadow {
            textures.push(format!("shadow_map ({}x{})", s.atlas.width, s.atlas.height));
        }
        if let Some(a) = &self.air {
            textures.push(format!(
                "air_table ({}x{})",
                a.target.width, a.target.height
            ));
        }
        if let Some(p) = &self.bake {
            textures.push(format!(
                "cloud_bake ({}x{})",
                p.target.width, p.target.height
            ));
        }
        if let Some(h) = &self.history {
            textures.push(format!(
                "history ({}x{}, 2 targets)",
                h.targets[0].width, h.targets[0].height
            ));
        }
        RenderStats {
            pipelines: self.pipelines.built().iter().map(|k| k.id()).collect(),
            textures,
            passes: self.passes.clone(),
        }
    }

    fn noise(&mut self, kind: NoiseKind) -> Result<(), RuntimeError> {
        if !self.user.contains_key(&kind) && !self.textures.contains_key(&kind) {
            let t = self.gpu.noise_texture(kind, self.sizes.of(kind))?;
            self.textures.insert(kind, t);
            self.epoch += 1;
        }
        Ok(())
    }

    fn check_size(&self, what: &str, width: u32, height: u32) -> Result<(), RuntimeError> {
        self.gpu.check_picture(what, width, height)
    }

    /// Builds the pipeline of `key`, the textures and samplers its bindings name.
    /// The cloud key this frame draws with for `wanted`: `wanted` itself, unless no-stall is
    /// on and its pipeline is still being built (requested here, never waited for); then the
    /// key drawn before, when it has the same genus functions. A genus of other functions has
    /// no stand-in (every pipeline that draws its shapes holds its code, the uber-shader's
    /// too): its first frame waits for its own key.
    fn clouds_key_for(&mut self, wanted: CloudKey) -> Result<ShaderKey, RuntimeError> {
        let key = ShaderKey::Clouds(wanted);
        if !self.no_stall || self.pipelines.ready(self.gpu, key)? {
            return Ok(key);
        }
        if let Some(previous) = self.last_clouds
            && previous.functions == wanted.functions
            && self
                .pipelines
                .ready(self.gpu, ShaderKey::Clouds(previous))?
        {
            self.pipelines.request(self.gpu, key);
            return Ok(ShaderKey::Clouds(previous));
        }
        Ok(key)
    }

    fn prepare(&mut self, key: ShaderKey) -> Result<(), RuntimeError> {
        let pipeline = self.pipelines.get_or_build(self.gpu, key)?;
        let mut kinds = Vec::new();
        let mut samplers = Vec::new();
        for b in &pipeline.bindings {
            if let BindingKind::Sampler(desc) = b.kind {
                samplers.push(desc);
            }
        }
        for (_, c) in cloud_bindings(pipeline) {
            kinds.extend(NoiseKind::of(c.resource()));
        }
        for k in kinds {
            self.noise(k)?;
        }
        for desc in samplers {
            if !self.samplers.contains_key(&desc) {
                let s = wgpu_sampler(self.gpu, desc);
                self.samplers.insert(desc, s);
            }
        }
        Ok(())
    }

    fn sampler(&self, b: &BindingInfo) -> Option<wgpu::BindingResource<'_>> {
        match b.kind {
            BindingKind::Sampler(desc) => {
                self.samplers.get(&desc).map(wgpu::BindingResource::Sampler)
            }
            _ => None,
        }
    }

    /// A bind group for a cloud-binding pipeline (clouds or shadow pass).
    fn cloud_group(
        &self,
        key: ShaderKey,
        uniform: &wgpu::Buffer,
    ) -> Result<wgpu::BindGroup, RuntimeError> {
        let pipeline = self.pipelines.get(&key)?;
        let mut entries = Vec::new();
        for (b, c) in cloud_bindings(pipeline) {
            let resource = match c {
                CloudBinding::Uniforms => Some(uniform.as_entire_binding()),
                CloudBinding::ShadowMap => self
                    .shadow
                    .as_ref()
                    .map(|s| &s.atlas.view)
                    .or_else(|| self.uber_resources.as_ref().map(|(_, t)| &t.view))
                    .map(wgpu::BindingResource::TextureView),
                CloudBinding::Key => self
                    .uber_resources
                    .as_ref()
                    .map(|(b, _)| b.as_entire_binding()),
                CloudBinding::Sampler => self.sampler(b),
                CloudBinding::SceneDepth => self
                    .scene
                    .as_ref()
                    .map(|(_, t)| wgpu::BindingResource::TextureView(&t.view)),
                CloudBinding::Scene => self.scene.as_ref().map(|(b, _)| b.as_entire_binding()),
                CloudBinding::AirTable => self
                    .air
                    .as_ref()
                    .map(|a| wgpu::BindingResource::TextureView(&a.target.view)),
                CloudBinding::Bake => self
                    .bake
                    .as_ref()
                    .map(|p| wgpu::BindingResource::TextureView(&p.target.view)),
                CloudBinding::Weather
                | CloudBinding::Shape
                | CloudBinding::Detail
                | CloudBinding::Turbulence => NoiseKind::of(c.resource())
                    .and_then(|k| self.user.get(&k).or_else(|| self.textures.get(&k)))
                    .map(|t| wgpu::BindingResource::TextureView(&t.view)),
            };
            entries.push(self.entry(b, resource)?);
        }
        self.check_all_bound(&key, pipeline, entries.len())?;
        Ok(self.gpu.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&key.id()),
            layout: &pipeline.layout,
            entries: &entries,
        }))
    }

    fn entry<'a>(
        &self,
        b: &BindingInfo,
        resource: Option<wgpu::BindingResource<'a>>,
    ) -> Result<wgpu::BindGroupEntry<'a>, RuntimeError> {
        let resource = resource.ok_or_else(|| {
            RuntimeError::Kernel(format!(
                "nothing to bind to `{}` (group {}, binding {})",
                b.name, b.group, b.binding
            ))
        })?;
        Ok(wgpu::BindGroupEntry {
            binding: b.binding,
            resource,
        })
    }

    fn check_all_bound(
        &self,
        key: &ShaderKey,
        pipeline: &CachedPipeline,
        bound: usize,
    ) -> Result<(), RuntimeError> {
        if bound != pipeline.bindings.len() {
            return Err(RuntimeError::Kernel(format!(
                "`{}` declares {} bindings the renderer does not know",
                key.id(),
                pipeline.bindings.len() - bound
            )));
        }
        Ok(())
    }

    /// The resolve pass's bind group reading `history[read]`.
    fn resolve_group(&self, read: usize) -> Result<wgpu::BindGroup, RuntimeError> {
        let key = ShaderKey::Resolve;
        let pipeline = self.pipelines.get(&key)?;
        let (Some(pass), Some(clouds), Some(history)) =
            (&self.resolve, &self.clouds, &self.history)
        else {
            return Err(RuntimeError::Kernel(
                "the resolve pass runs without its resources".into(),
            ));
        };
        let mut entries = Vec::new();
        for b in &pipeline.bindings {
            let Some(r) = ResolveBinding::at(b.group, b.binding) else {
                continue;
            };
            let resource = match r {
                ResolveBinding::Params => Some(pass.uniform.as_entire_binding()),
                ResolveBinding::Current => {
                    Some(wgpu::BindingResource::TextureView(&clouds.target.view))
                }
                ResolveBinding::History => Some(wgpu::BindingResource::TextureView(
                    &history.targets[read].view,
                )),
                ResolveBinding::Nearest | ResolveBinding::Linear => self.sampler(b),
            };
            entries.push(self.entry(b, resource)?);
        }
        self.check_all_bound(&key, pipeline, entries.len())?;
        Ok(self.gpu.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("resolve"),
            layout: &pipeline.layout,
            entries: &entries,
        }))
    }

    /// The air table's pipeline and target, for a cloud pipeline or a bake that reads it (made
    /// with the other targets, before any bind group of the frame), or none.
    fn ensure_air_table(
        &mut self,
        readers: &[ShaderKey],
        uniform_size: usize,
    ) -> Result<(), RuntimeError> {
        let mut reads = false;
        for key in readers {
            reads |=
                cloud_bindings(self.pipelines.get(key)?).any(|(_, c)| c == CloudBinding::AirTable);
        }
        if !reads {
            return Ok(());
        }
        self.prepare(ShaderKey::AirTable)?;
        if self.air.is_none() {
            self.air = Some(AirPass::new(
                self.gpu,
                "air table",
                uniform_size,
                air_table_size(),
            ));
            self.epoch += 1;
        }
        Ok(())
    }

    /// The bake's pipeline and target, for a cloud key of a baked path (made with the other
    /// targets, before any bind group of the frame); none for another key. The target is made
    /// again when the path's bake has another size.
    fn ensure_bake(&mut self, clouds: CloudKey, uniform_size: usize) -> Result<(), RuntimeError> {
        let size = bake_size(clouds.features.path).filter(|_| clouds.bakes());
        let Some((w, h)) = size else {
            if self.bake.take().is_some() {
                self.epoch += 1;
            }
            return Ok(());
        };
        self.prepare(ShaderKey::Bake(clouds))?;
        if self.bake.as_ref().map(|p| size_of(&p.target)) != Some((w, h)) {
            self.check_size("the path's bake", w, h)?;
            self.bake = Some(BakePass::new(self.gpu, "bake", uniform_size, (w, h)));
            self.epoch += 1;
        }
        Ok(())
    }

    /// Redraws the bake of `clouds` when its key or what it depends on
    /// ([`bake_inputs`]) changed since it was drawn.
    fn draw_bake(
        &mut self,
        clouds: CloudKey,
        u: &CloudUniforms,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<PassTimer>,
    ) -> Result<(), RuntimeError> {
        let Some(mut pass) = self.bake.take() else {
            return Ok(());
        };
        let key = ShaderKey::Bake(clouds);
        let generation = self.air_generation;
        let drawn = bake_inputs(u, &clouds)
            .map_err(RuntimeError::from)
            .and_then(|inputs| {
                let inputs = (key, inputs, generation);
                self.draw_cached(&mut pass, key, inputs, u, encoder, timer, "bake")
            });
        self.bake = Some(pass);
        drawn
    }

    /// Draws `pass` (its pipeline `key`) from the block `u` unless it was last drawn from the
    /// same `inputs`; its bind group is made again when the resources' epoch moved on. The pass
    /// is out of the renderer while it draws (its own module never reads its own target).
    #[expect(
        clippy::too_many_arguments,
        reason = "a pass, its key and inputs, the block, and the frame's encoder and timer"
    )]
    fn draw_cached<I: PartialEq>(
        &mut self,
        pass: &mut CachedPass<I>,
        key: ShaderKey,
        inputs: I,
        u: &CloudUniforms,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<PassTimer>,
        label: &'static str,
    ) -> Result<(), RuntimeError> {
        if pass.inputs.as_ref() == Some(&inputs) {
            return Ok(());
        }
        let epoch = self.epoch;
        if !matches!(&pass.group, Some(g) if g.key == key && g.epoch == epoch) {
            let group = self.cloud_group(key, &pass.uniform)?;
            pass.group = Some(BoundGroup { group, key, epoch });
        }
        let pipeline = self.pipelines.get(&key)?;
        let group = pass.group.as_ref().ok_or_else(missing)?;
        self.gpu
            .queue()
            .write_buffer(&pass.uniform, 0, &u.to_uniform_bytes()?);
        draw(
            encoder,
            label,
            &pass.target.view,
            &pipeline.pipeline,
            &group.group,
            PassTimer::next(timer),
            None,
        );
        self.passes.push(label);
        pass.inputs = Some(inputs);
        Ok(())
    }

    /// The bake as last drawn (the slice stack or the 2D map), or `None` when the last frame's
    /// key has none.
    pub fn baked(&mut self) -> Result<Option<Image>, RuntimeError> {
        self.read_kept(|r| r.bake.as_ref().map(|p| &p.target))
    }

    /// A target the renderer keeps across frames (`target` picks it, `None` when the last
    /// key had none), read back.
    fn read_kept(
        &mut self,
        target: impl Fn(&Self) -> Option<&Target>,
    ) -> Result<Option<Image>, RuntimeError> {
        let Some((w, h)) = target(self).map(size_of) else {
            return Ok(None);
        };
        self.ensure_readback(w, h);
        let t = target(self).ok_or_else(missing)?;
        self.read_back(t).map(Some)
    }

    /// Cascades in rotation ([`Self::set_cascade_rotation`]): draws this frame's band of the
    /// tile in progress, or the first of the next out-of-date tile ([`band_redraw`]), into the
    /// back atlas from the block as it stood at that tile's first band; with its last band the
    /// tile is copied into the atlas and keeps that block's transform. Writes every tile's
    /// transform, moved to where its clouds are now, into the frame's block.
    #[allow(
        clippy::too_many_arguments,
        reason = "the pass's key, the frame's block, anchor and switch, encoder and timer"
    )]
    fn rotate_cascades(
        &mut self,
        key: ShaderKey,
        u: &mut CloudUniforms,
        anchor: Vec3,
        draw_band: bool,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<PassTimer>,
    ) -> Result<(), RuntimeError> {
        let Some(p) = self.shadow.as_mut() else {
            return Ok(());
        };
        let count = u.shadow.cascade_count;
        let side = u.shadow.map_size as u32;
        // The key or the tiles' layout changed under a tile in progress (the atlas kept its
        // size): that tile is dropped and redrawn in its turn, all of it by one key.
        if p.banded.as_ref().is_some_and(|b| {
            b.key != key
                || b.block.shadow.map_size != u.shadow.map_size
                || b.block.shadow.cascade_count != count
        }) {
            p.redraw = tiles_out_of_date(
                TileRedraw {
                    band: 0,
                    ..p.redraw
                },
                count,
            );
            p.banded = None;
        }
        let step = if draw_band {
            band_redraw(p.redraw, count, side, side)
        } else {
            // Nothing drawn, the redraw where it stands.
            BandDraw {
                state: p.redraw,
                tile: count,
                x: 0,
                y: 0,
                top: 0,
                height: 0,
                first: 0,
                last: 0,
            }
        };
        p.redraw = step.state;
        if step.first == 1 {
            p.banded = Some(BandedTile {
                key,
                block: *u,
                current: u.shadow.lookup,
                anchor,
            });
        }
        if step.height > 0 {
            if p.back.is_none() {
                let (w, h) = size_of(&p.atlas);
                p.back = Some(target(self.gpu, "shadow back atlas", w, h));
            }
            let epoch = self.epoch;
            let rebuild = !matches!(&p.group, Some(g) if g.key == key && g.epoch == epoch);
            if rebuild {
                let p = self.shadow.as_ref().ok_or_else(missing)?;
                let group = self.cloud_group(key, &p.uniform)?;
                if let Some(p) = &mut self.shadow {
                    p.group = Some(BoundGroup { group, key, epoch });
                }
            }
            let pipeline = self.pipelines.get(&key)?;
            let p = self.shadow.as_ref().ok_or_else(missing)?;
            let group = p.group.as_ref().ok_or_else(missing)?;
            let banded = p.banded.as_ref().ok_or_else(missing)?;
            let back = p.back.as_ref().ok_or_else(missing)?;
            self.gpu
                .queue()
                .write_buffer(&p.uniform, 0, &banded.block.to_uniform_bytes()?);
            draw(
                encoder,
                "shadow",
                &back.view,
                &pipeline.pipeline,
                &group.group,
                PassTimer::next(timer),
                Some([step.x, step.y + step.top, side, step.height]),
            );
            self.passes.push("shadow");
            if step.last == 1 {
                copy_region(encoder, back, &p.atlas, [step.x, step.y, side, side]);
                let (current, drawn_at) = (banded.current, banded.anchor);
                if let Some(p) = &mut self.shadow {
                    // Lanes past the cascade count hold no tile: they follow the sun, as a
                    // whole redraw's do.
                    let mut redraw = Vec4::ZERO;
                    for lane in 0..4 {
                        if lane == step.tile || lane >= count {
                            redraw[lane as usize] = 1.0;
                        }
                    }
                    let kept = p.tiles.unwrap_or(current);
                    p.tiles = Some(redrawn_tiles(kept, current, drawn_at, redraw));
                    p.banded = None;
                }
            }
        }
        if let Some(tiles) = self.shadow.as_ref().and_then(|p| p.tiles) {
            u.shadow.lookup = anchored_tiles(tiles, anchor);
        }
        Ok(())
    }

    /// Redraws the air table when the sun, the camera's altitude or the atmosphere changed
    /// since it was drawn.
    fn draw_air_table(
        &mut self,
        u: &CloudUniforms,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<PassTimer>,
    ) -> Result<(), RuntimeError> {
        let Some(mut pass) = self.air.take() else {
            return Ok(());
        };
        let inputs = AirTableInputs::of(u);
        let drawn = match pass.inputs {
            Some(drawn) if self.cascade_rotation => {
                self.draw_air_band(&mut pass, drawn, inputs, u, encoder, timer)
            }
            _ => {
                // Drawn whole: a table in progress is dropped.
                self.air_bands = None;
                let before = pass.inputs;
                let drawn = self.draw_cached(
                    &mut pass,
                    ShaderKey::AirTable,
                    inputs,
                    u,
                    encoder,
                    timer,
                    "air",
                );
                if pass.inputs != before {
                    self.air_generation += 1;
                }
                drawn
            }
        };
        self.air = Some(pass);
        drawn
    }

    /// Cascades in rotation: this frame's band of the air table ([`band_redraw`], one tile),
    /// drawn into the back table from the block as it stood at the first band, the table
    /// copied into `pass`'s with the last (`drawn`: the inputs `pass`'s table was drawn from).
    fn draw_air_band(
        &mut self,
        pass: &mut AirPass,
        drawn: AirTableInputs,
        inputs: AirTableInputs,
        u: &CloudUniforms,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<PassTimer>,
    ) -> Result<(), RuntimeError> {
        let (w, h) = size_of(&pass.target);
        let gpu = self.gpu;
        let bands = self.air_bands.get_or_insert_with(|| AirBands {
            redraw: TileRedraw::default(),
            requested: drawn,
            drawing: None,
            back: target(gpu, "air table back", w, h),
        });
        if bands.requested != inputs {
            bands.redraw = tiles_out_of_date(bands.redraw, 1);
            bands.requested = inputs;
        }
        let step = band_redraw(bands.redraw, 1, w, h);
        bands.redraw = step.state;
        if step.first == 1 {
            bands.drawing = Some((*u, inputs));
        }
        if step.height == 0 {
            return Ok(());
        }
        let epoch = self.epoch;
        let key = ShaderKey::AirTable;
        if !matches!(&pass.group, Some(g) if g.key == key && g.epoch == epoch) {
            let group = self.cloud_group(key, &pass.uniform)?;
            pass.group = Some(BoundGroup { group, key, epoch });
        }
        let pipeline = self.pipelines.get(&key)?;
        let group = pass.group.as_ref().ok_or_else(missing)?;
        let bands = self.air_bands.as_ref().ok_or_else(missing)?;
        let (block, from) = bands.drawing.ok_or_else(missing)?;
        self.gpu
            .queue()
            .write_buffer(&pass.uniform, 0, &block.to_uniform_bytes()?);
        draw(
            encoder,
            "air",
            &bands.back.view,
            &pipeline.pipeline,
            &group.group,
            PassTimer::next(timer),
            Some([step.x, step.y + step.top, w, step.height]),
        );
        self.passes.push("air");
        if step.last == 1 {
            copy_region(encoder, &bands.back, &pass.target, [0, 0, w, h]);
            pass.inputs = Some(from);
            self.air_generation += 1;
        }
        Ok(())
    }

    /// The uniforms of `frame` at frame index 0 ([`Frame::uniforms`], the model's).
    pub fn uniforms(frame: &Frame) -> CloudUniforms {
        frame.uniforms()
    }

    /// Query set and buffers for `capacity` timestamps, kept while large enough.
    fn timer(&mut self, frames: u32) -> Option<PassTimer> {
        let device = self.gpu.device();
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        // Shadow, air and bake, then clouds and resolve per frame: two timestamps each.
        let capacity = (2 * (3 + 2 * frames)).min(4096);
        if let Some(mut t) = self.timer.take()
            && t.capacity >= capacity
        {
            t.used = 0;
            return Some(t);
        }
        let size = u64::from(capacity) * 8;
        Some(PassTimer {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            }),
            resolve: self.gpu.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: self.gpu.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            capacity,
            used: 0,
        })
    }

    /// Renders `frame` (all its accumulation frames); `progress` hears of each frame done.
    ///
    /// A frame may be black (a night sky, the sun far below the horizon): that is a result.
    /// An adapter that draws nothing also gives black, so a black frame is followed by a small
    /// daylight probe of the same genus on the same adapter (a renderer of its own); only when
    /// that is black too is the adapter blamed ([`RuntimeError::BadFrame`]).
    pub fn render_with_progress(
        &mut self,
        frame: &Frame,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<Image, RuntimeError> {
        let image = self.render_frames(frame, progress)?;
        if image.is_black() {
            // A renderer of its own, so this one's history, targets, passes and timings stay
            // those of the user's frames.
            let mut probe = Frame::new(frame.genus.clone(), Quality::Low, 16, 9);
            probe.frames = 1;
            probe.sun_elevation_deg = 45.0;
            probe.genus.coverage = 0.5;
            let mut prober = Renderer::new(self.gpu, self.sizes);
            if prober.render_frames(&probe, &mut |_, _| {})?.is_black() {
                return Err(RuntimeError::BadFrame(
                    "every pixel is black, and so is a daylight probe frame: the adapter \
                     produced no output"
                        .into(),
                ));
            }
        }
        Ok(image)
    }

    fn render_frames(
        &mut self,
        frame: &Frame,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<Image, RuntimeError> {
        frame.validate()?;
        self.check_size("the image", frame.width, frame.height)?;
        self.ensure_readback(frame.width, frame.height);
        let frames = frame.frames.max(1);
        let variant = frame.variant();
        let clouds_key = if self.uber {
            // The functions are the genus' code, not a run-time choice: the uber-shader has
            // them too.
            ShaderKey::Clouds(CloudKey::uber().with_functions(variant.key.functions))
        } else {
            self.clouds_key_for(variant.key)?
        };
        self.stand_in = !self.uber && clouds_key != ShaderKey::Clouds(variant.key);
        if !self.stand_in && !self.uber {
            self.last_clouds = Some(variant.key);
        }
        let uber = self.uber;
        let shadow_key = variant.key.shadow_key().map(ShaderKey::Shadow);
        self.passes.clear();
        self.gpu_time_ms = None;
        let mut timer = self.timer(frames);
        let mut u = Self::uniforms(frame);
        let uniform_size = u.to_uniform_bytes()?.len();

        // Pipelines first: their bindings decide which textures and samplers exist.
        self.prepare(clouds_key)?;
        // The detail's level of detail follows the texture bound: its texel size and means.
        let detail = self
            .user
            .get(&NoiseKind::Detail)
            .or_else(|| self.textures.get(&NoiseKind::Detail));
        if let Some(t) = detail {
            let moments = t.red_moments.unwrap_or(u.media.detail_moments);
            u.media = u.media.with_detail_lod(t.size, moments);
        }
        // The uber-shader's key uniforms; a stand-in (the key drawn before) may bind a shadow
        // map this frame's key has dropped: the stand-in map serves both.
        if uber || self.stand_in {
            if self.uber_resources.is_none() {
                let key = uniform_buffer(
                    self.gpu,
                    "uber key uniforms",
                    align_size(KeyUniforms::shader_type()).1 as usize,
                );
                self.uber_resources = Some((key, target(self.gpu, "no shadow", 1, 1)));
                self.epoch += 1;
            }
            if let Some((b, _)) = &self.uber_resources {
                let bytes = KeyUniforms::of(&variant.key).to_uniform_bytes()?;
                self.gpu.queue().write_buffer(b, 0, &bytes);
            }
        }
        // The camera's orientation and the image size do not enter the atlas.
        let atlas_bytes = {
            let mut inputs = u;
            inputs.inverse_view_projection = Mat4::IDENTITY;
            inputs.resolution = Vec2::ZERO;
            inputs.to_uniform_bytes()?
        };
        // A shadow key still being built: the atlas drawn with the previous one stands in when
        // only the key changed (the same clouds, sun and layout), redrawn once the key's
        // pipeline is ready; anything else waits for the key.
        let keep_atlas = match shadow_key {
            Some(k) if self.no_stall && !self.pipelines.ready(self.gpu, k)? => {
                self.pipelines.request(self.gpu, k);
                self.shadow.as_ref().is_some_and(|p| {
                    size_of(&p.atlas) == u.shadow.atlas_size()
                        && p.inputs.as_ref().is_some_and(|(_, b)| *b == atlas_bytes)
                })
            }
            _ => false,
        };
        if let Some(k) = shadow_key
            && !keep_atlas
        {
            self.prepare(k)?;
        }
        // The engine's depth: a new texture each frame (its bind group follows), the camera's
        // encoding in a block of its own.
        if let Some(depth) = &frame.scene_depth {
            let (forward, _) = frame.camera_basis();
            let params = depth.params_for(frame.view_projection(), forward);
            let bytes = params.to_uniform_bytes()?;
            let buffer = match self.scene.take() {
                Some((b, _)) => b,
                None => uniform_buffer(self.gpu, "scene depth uniforms", bytes.len()),
            };
            self.gpu.queue().write_buffer(&buffer, 0, &bytes);
            self.scene = Some((buffer, self.gpu.scene_depth_texture(depth)));
            self.epoch += 1;
        } else if self.scene.take().is_some() {
            self.epoch += 1;
        }
        let resolve = frame.upscale || frames > 1;
        if resolve {
            self.prepare(ShaderKey::Resolve)?;
        }

        // Targets first (the cloud pass's, the history), so that every bind group below is
        // made after the last resource it references: the cloud pass's target, kept while
        // its size holds.
        let scale = if frame.upscale { 4 } else { 1 };
        let (lw, lh) = (frame.width.div_ceil(scale), frame.height.div_ceil(scale));
        if !matches!(&self.clouds, Some(p) if size_of(&p.target) == (lw, lh)) {
            let uniform = match self.clouds.take() {
                Some(p) => p.uniform,
                None => uniform_buffer(self.gpu, "cloud uniforms", uniform_size),
            };
            self.clouds = Some(CloudPass {
                uniform,
                group: None,
                target: target(self.gpu, "clouds", lw, lh),
            });
            self.epoch += 1;
        }

        // History: kept across calls of the same size and mode; restarted unless continued.
        let view_projection = frame.view_projection();
        let same = matches!(&self.history, Some(h) if h.upscale == frame.upscale
            && size_of(&h.targets[0]) == (frame.width, frame.height));
        if resolve {
            if !same {
                let accumulation = self.gpu.accumulation_format();
                self.history = Some(History {
                    targets: [
                        target_of(
                            self.gpu,
                            "history A",
                            frame.width,
                            frame.height,
                            accumulation,
                        ),
                        target_of(
                            self.gpu,
                            "history B",
                            frame.width,
                            frame.height,
                            accumulation,
                        ),
                    ],
                    latest: 0,
                    upscale: frame.upscale,
                    view_projection,
                    wind: frame.wind,
                    frames: 0,
                });
                self.epoch += 1;
            } else if !frame.continue_history
                && let Some(h) = &mut self.history
            {
                // A fresh start on the kept targets: frame 0 ignores the history.
                h.frames = 0;
                h.view_projection = view_projection;
                h.wind = frame.wind;
            }
            if self.resolve.is_none() {
                self.resolve = Some(ResolvePass {
                    uniform: uniform_buffer(
                        self.gpu,
                        "resolve uniforms",
                        align_size(ResolveParams::shader_type()).1 as usize,
                    ),
                    groups: [None, None],
                });
            }
        } else if self.history.take().is_some() {
            // The resolve pass's bind groups hold the history targets: release them too.
            self.resolve = None;
            self.epoch += 1;
        }

        // The bake first: an impostor's that holds the whole view reads the air table where
        // its cloud pass does not.
        let mut air_readers = vec![clouds_key];
        if let ShaderKey::Clouds(k) = clouds_key {
            self.ensure_bake(k, uniform_size)?;
            if self.bake.is_some() {
                air_readers.push(ShaderKey::Bake(k));
            }
        }
        self.ensure_air_table(&air_readers, uniform_size)?;

        // Shadow atlas: kept while its size holds, redrawn only when its inputs change.
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        if keep_atlas {
            // No shadow pass this frame: the atlas stands as it was, its tiles read as drawn.
            if let Some(tiles) = self.shadow.as_ref().and_then(|p| p.tiles)
                && self.cascade_rotation
            {
                let anchor = shadow_anchor(u.camera_offset, u.camera_altitude, u.media.wind_drift);
                u.shadow.lookup = anchored_tiles(tiles, anchor);
            }
        } else if let Some(key) = shadow_key {
            let s = u.shadow;
            let (w, h) = s.atlas_size();
            self.check_size("the shadow atlas (its cascades in a grid)", w, h)?;
            if !matches!(&self.shadow, Some(p) if size_of(&p.atlas) == (w, h)) {
                let uniform = match self.shadow.take() {
                    Some(p) => p.uniform,
                    None => uniform_buffer(self.gpu, "shadow uniforms", uniform_size),
                };
                self.shadow = Some(ShadowPass {
                    uniform,
                    group: None,
                    atlas: target(self.gpu, "shadow atlas", w, h),
                    inputs: None,
                    refreshing: None,
                    tiles: None,
                    redraw: TileRedraw::default(),
                    banded: None,
                    back: None,
                });
                self.epoch += 1;
            }
            let inputs = (key, atlas_bytes);
            let anchor = shadow_anchor(u.camera_offset, u.camera_altitude, u.media.wind_drift);
            let stale = self
                .shadow
                .as_ref()
                .is_some_and(|p| p.inputs.as_ref() != Some(&inputs));
            let mut continue_refresh = false;
            // A band of a key change drawn this frame (no-stall): the rotation draws none, the
            // two sharing the shadow pass's uniform buffer.
            let mut refreshed = false;
            if stale {
                let rebuild = !matches!(&self.shadow, Some(ShadowPass { group: Some(g), .. })
                    if g.key == key && g.epoch == self.epoch);
                if rebuild {
                    let group = {
                        let p = self.shadow.as_ref().ok_or_else(missing)?;
                        self.cloud_group(key, &p.uniform)?
                    };
                    let epoch = self.epoch;
                    if let Some(p) = &mut self.shadow {
                        p.group = Some(BoundGroup { group, key, epoch });
                    }
                }
                let pipeline = self.pipelines.get(&key)?;
                let p = self.shadow.as_ref().ok_or_else(missing)?;
                let group = p.group.as_ref().ok_or_else(missing)?;
                // Only the key changed (the clouds and the sun stand where they were): with
                // no-stall, one band of a tile per frame, the finest cascade first; the bands
                // not yet redrawn hold the same shadows, drawn by the previous key.
                let tile = (self.no_stall
                    && p.inputs.as_ref().is_some_and(|(_, b)| *b == inputs.1))
                .then(|| match p.refreshing {
                    Some((k, done)) if k == key => done,
                    _ => 0,
                });
                let side = s.map_size as u32;
                let bands = side.div_ceil(REFRESH_BAND).max(1);
                let regions = s.cascade_count * bands;
                let region = tile.map(|i| {
                    let (k, band) = (i / bands, i % bands);
                    let columns = atlas_columns(s.cascade_count);
                    let rows = side / bands;
                    [
                        (k % columns) * side,
                        (k / columns) * side + band * rows,
                        side,
                        rows,
                    ]
                });
                // In rotation, once drawn whole: every tile out of date, one drawn below.
                let rotate = tile.is_none() && self.cascade_rotation && p.tiles.is_some();
                if !rotate {
                    self.gpu
                        .queue()
                        .write_buffer(&p.uniform, 0, &u.to_uniform_bytes()?);
                    draw(
                        &mut encoder,
                        "shadow",
                        &p.atlas.view,
                        &pipeline.pipeline,
                        &group.group,
                        PassTimer::next(&mut timer),
                        region,
                    );
                    self.passes.push("shadow");
                }
                if let Some(p) = &mut self.shadow {
                    if tile.is_some() && p.redraw.band != 0 {
                        // A band of the new key over a tile in progress (drawn by the old key
                        // into the back atlas): that tile is dropped and redrawn in its turn,
                        // so its copy cannot undo the refresh.
                        p.redraw = TileRedraw {
                            stale: p.redraw.stale | (1 << p.redraw.tile),
                            band: 0,
                            ..p.redraw
                        };
                        p.banded = None;
                    }
                    refreshed = tile.is_some();
                    match tile {
                        Some(k) if k + 1 < regions => {
                            p.refreshing = Some((key, k + 1));
                            continue_refresh = true;
                        }
                        _ => p.refreshing = None,
                    }
                    if rotate {
                        p.redraw = tiles_out_of_date(p.redraw, s.cascade_count);
                    } else if tile.is_none() {
                        // Drawn whole: every tile for the sun as it is, around the camera; a
                        // tile in progress is dropped.
                        p.tiles = Some(redrawn_tiles(
                            u.shadow.lookup,
                            u.shadow.lookup,
                            anchor,
                            Vec4::ONE,
                        ));
                        p.redraw = TileRedraw::default();
                        p.banded = None;
                    }
                }
                if let Some(p) = &mut self.shadow
                    && !continue_refresh
                {
                    p.inputs = Some(inputs);
                }
            }
            if self.cascade_rotation {
                self.rotate_cascades(key, &mut u, anchor, !refreshed, &mut encoder, &mut timer)?;
            }
        } else if self.shadow.take().is_some() {
            // No shadows in this key: the atlas of an earlier one is not kept.
            self.epoch += 1;
        }
        self.draw_air_table(&u, &mut encoder, &mut timer)?;
        if let ShaderKey::Clouds(k) = clouds_key {
            self.draw_bake(k, &u, &mut encoder, &mut timer)?;
        }
        self.gpu.queue().submit([encoder.finish()]);

        // Bind groups, remade only when a resource or the key changed.
        let stale = |g: &Option<BoundGroup>, key: ShaderKey, epoch: u64| !matches!(g, Some(b) if b.key == key && b.epoch == epoch);
        let epoch = self.epoch;
        if self
            .clouds
            .as_ref()
            .is_some_and(|p| stale(&p.group, clouds_key, epoch))
        {
            let group = {
                let p = self.clouds.as_ref().ok_or_else(missing)?;
                self.cloud_group(clouds_key, &p.uniform)?
            };
            if let Some(p) = &mut self.clouds {
                p.group = Some(BoundGroup {
                    group,
                    key: clouds_key,
                    epoch,
                });
            }
        }
        if resolve {
            for read in 0..2 {
                let rebuild = self
                    .resolve
                    .as_ref()
                    .is_some_and(|p| stale(&p.groups[read], ShaderKey::Resolve, epoch));
                if rebuild {
                    let group = self.resolve_group(read)?;
                    if let Some(p) = &mut self.resolve {
                        p.groups[read] = Some(BoundGroup {
                            group,
                            key: ShaderKey::Resolve,
                            epoch,
                        });
                    }
                }
            }
        }

        for f in 0..frames {
            let previous_frames = self.history.as_ref().map_or(0, |h| h.frames);
            let index = previous_frames + f;
            // The host's share of the frame, from the same functions engine hosts run
            // (`nimbus-frame.js`).
            let step = cloud_frame(index, frame.seed, u32::from(frame.upscale));
            u.frame = step.frame;
            u.jitter = step.jitter;
            u.pixel_offset = step.pixel_offset;
            u.pixel_scale = step.pixel_scale;
            u.subpixel = step.subpixel;
            let clouds = self.clouds.as_ref().ok_or_else(missing)?;
            let cloud_bytes = u.to_uniform_bytes()?;
            self.gpu
                .queue()
                .write_buffer(&clouds.uniform, 0, &cloud_bytes);
            let mut resolve_bytes = None;
            let mut encoder = self
                .gpu
                .device()
                .create_command_encoder(&Default::default());
            let pipeline = self.pipelines.get(&clouds_key)?;
            let group = clouds.group.as_ref().ok_or_else(missing)?;
            draw(
                &mut encoder,
                "clouds",
                &clouds.target.view,
                &pipeline.pipeline,
                &group.group,
                PassTimer::next(&mut timer),
                None,
            );
            self.passes.push("clouds");
            if let (Some(h), Some(pass)) = (&self.history, &self.resolve) {
                // Where a ray first meets the clouds (the slab's face towards the camera: the
                // bases seen from below, the tops from above), which the history follows with
                // the wind (no move within one call: its frames share one drift).
                let cloud_altitude = nimbus_clouds::model::resolve::facing_altitude(
                    u.camera_altitude,
                    u.march.min_height,
                    u.march.max_height,
                );
                let packed = |d: &Drift| d.ground.extend(d.per_metre.x).extend(d.per_metre.y);
                let step = resolve_frame(
                    index,
                    u32::from(frame.upscale),
                    u32::from(h.view_projection != view_projection),
                    packed(&frame.wind),
                    packed(&h.wind),
                    cloud_altitude,
                    u.resolution,
                );
                let params = ResolveParams {
                    inverse_view_projection: view_projection.inverse(),
                    previous_view_projection: h.view_projection,
                    cloud_shift: if frame.reproject_wind {
                        step.cloud_shift
                    } else {
                        Vec3::ZERO
                    },
                    cloud_altitude,
                    camera_altitude: u.camera_altitude,
                    planet_radius: u.march.radius,
                    resolution: u.resolution,
                    low_resolution: step.low_resolution,
                    pixel_offset: step.pixel_offset,
                    pixel_scale: step.pixel_scale,
                    current_weight: step.current_weight,
                    variance_gamma: step.variance_gamma,
                    history_valid: step.history_valid,
                };
                let (read, write) = (h.latest, 1 - h.latest);
                let bytes = params.to_uniform_bytes()?;
                self.gpu.queue().write_buffer(&pass.uniform, 0, &bytes);
                resolve_bytes = Some(bytes);
                let pipeline = self.pipelines.get(&ShaderKey::Resolve)?;
                let group = pass.groups[read].as_ref().ok_or_else(missing)?;
                draw(
                    &mut encoder,
                    "resolve",
                    &h.targets[write].view,
                    &pipeline.pipeline,
                    &group.group,
                    PassTimer::next(&mut timer),
                    None,
                );
                self.passes.push("resolve");
            }
            self.gpu.queue().submit([encoder.finish()]);
            if let Some(log) = &mut self.uniform_log {
                log.push(WrittenFrame {
                    clouds: cloud_bytes,
                    resolve: resolve_bytes,
                });
            }
            if let Some(h) = &mut self.history {
                h.latest = 1 - h.latest;
                h.view_projection = view_projection;
                h.wind = frame.wind;
            }
            progress(f + 1, frames);
        }
        if let Some(h) = &mut self.history {
            h.frames += frames;
        }
        if let Some(t) = &timer {
            self.gpu_time_ms = Some(self.read_timestamps(t)?);
        }
        self.timer = timer;
        let image = match (&self.history, &self.clouds) {
            (Some(h), _) => self.read_back(&h.targets[h.latest])?,
            (None, Some(c)) => self.read_back(&c.target)?,
            (None, None) => return Err(missing()),
        };
        Ok(image)
    }

    /// GPU time of the passes of the last `render` call (ms), from timestamp queries; `None`
    /// where the adapter has none (time the call on the CPU instead).
    pub fn last_gpu_time_ms(&self) -> Option<f64> {
        self.gpu_time_ms
    }

    /// Sum over the timed passes of end − start, in milliseconds.
    fn read_timestamps(&self, timer: &PassTimer) -> Result<f64, RuntimeError> {
        if timer.used == 0 {
            return Ok(0.0);
        }
        let size = u64::from(timer.used) * 8;
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        encoder.resolve_query_set(&timer.queries, 0..timer.used, &timer.resolve, 0);
        encoder.copy_buffer_to_buffer(&timer.resolve, 0, &timer.readback, 0, size);
        self.gpu.queue().submit([encoder.finish()]);
        let bytes = self.gpu.map_read(&timer.readback)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes[..size as usize]);
        let period_ns = f64::from(self.gpu.queue().get_timestamp_period());
        let total: u64 = ticks
            .chunks_exact(2)
            .map(|p| p[1].saturating_sub(p[0]))
            .sum();
        Ok(total as f64 * period_ns * 1e-6)
    }

    /// The shadow atlas of the last frame (front depth, mean extinction, max optical depth,
    /// tail per texel), if the last key had one.
    pub fn shadow_atlas(&mut self) -> Result<Option<Image>, RuntimeError> {
        self.read_kept(|r| r.shadow.as_ref().map(|p| &p.atlas))
    }

    /// The air table the last frame read (Rayleigh, Mie and optical-depth bands), if its key
    /// reads one.
    pub fn air_table(&mut self) -> Result<Option<Image>, RuntimeError> {
        self.read_kept(|r| r.air.as_ref().map(|p| &p.target))
    }

    /// The clouds' shadow on the scene of the last frame (the `scene_shadow` pass): per pixel of
    /// its depth buffer, the sun's light through the clouds at the surface there (red, green and
    /// blue alike; 1 where the scene has no surface), read from the last frame's shadow atlas.
    /// `None` unless the last frame had a [`Frame::scene_depth`] and its key a shadow atlas.
    pub fn scene_shadow(&mut self) -> Result<Option<Image>, RuntimeError> {
        let Some((_, depth)) = &self.scene else {
            return Ok(None);
        };
        if self.shadow.is_none() || self.clouds.is_none() {
            return Ok(None);
        }
        let (width, height) = (depth.texture.width(), depth.texture.height());
        let key = ShaderKey::SceneShadow;
        self.prepare(key)?;
        let clouds = self.clouds.as_ref().ok_or_else(missing)?;
        let group = self.cloud_group(key, &clouds.uniform)?;
        let out = target(self.gpu, "scene shadow", width, height);
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        let pipeline = self.pipelines.get(&key)?;
        draw(
            &mut encoder,
            "scene shadow",
            &out.view,
            &pipeline.pipeline,
            &group,
            None,
            None,
        );
        self.gpu.queue().submit([encoder.finish()]);
        self.ensure_readback(width, height);
        Ok(Some(self.read_back(&out)?))
    }

    /// Renders `frame`.
    pub fn render(&mut self, frame: &Frame) -> Result<Image, RuntimeError> {
        self.render_with_progress(frame, &mut |_, _| {})
    }

    /// Bytes of one row of a `width`-texel target, padded as buffer copies require.
    fn row_bytes(width: u32, format: wgpu::TextureFormat) -> u32 {
        (width * texel_bytes(format)).div_ceil(256) * 256
    }

    /// A readback buffer large enough for a `width`×`height` target of the widest format,
    /// kept while it is.
    fn ensure_readback(&mut self, width: u32, height: u32) {
        let widest = wgpu::TextureFormat::Rgba32Float;
        let size = u64::from(Self::row_bytes(width, widest)) * u64::from(height);
        if self.readback.as_ref().is_some_and(|b| b.size() >= size) {
            return;
        }
        self.readback = Some(readback_buffer(self.gpu, size));
    }

    fn read_back(&self, target: &Target) -> Result<Image, RuntimeError> {
        let (width, height) = (target.width, target.height);
        let row_bytes = Self::row_bytes(width, target.format);
        let size = u64::from(row_bytes) * u64::from(height);
        let owned;
        let readback = match &self.readback {
            Some(b) if b.size() >= size => b,
            _ => {
                owned = readback_buffer(self.gpu, size);
                &owned
            }
        };
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            target.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.gpu.queue().submit([encoder.finish()]);
        let data = self.gpu.map_read_prefix(readback, size)?;
        let mut pixels = Vec::with_capacity((width * height) as usize);
        let texel = texel_bytes(target.format) as usize;
        for y in 0..height as usize {
            let row = &data[y * row_bytes as usize..][..width as usize * texel];
            if texel == 16 {
                let floats: &[f32] = bytemuck::cast_slice(row);
                pixels.extend(floats.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]));
            } else {
                let halves: &[u16] = bytemuck::cast_slice(row);
                pixels.extend(
                    halves
                        .chunks_exact(4)
                        .map(|px| px_f32([px[0], px[1], px[2], px[3]])),
                );
            }
        }
        Ok(Image {
            width,
            height,
            pixels,
        })
    }
}

/// Bytes per texel of the render targets' formats (RGBA16F or RGBA32F).
fn texel_bytes(format: wgpu::TextureFormat) -> u32 {
    if format == wgpu::TextureFormat::Rgba32Float {
        16
    } else {
        8
    }
}

/// One RGBA16F texel as f32 (IEEE half floats, by `half`).
fn px_f32(texel: [u16; 4]) -> [f32; 4] {
    texel.map(|b| f16::from_bits(b).to_f32())
}

fn missing() -> RuntimeError {
    RuntimeError::Kernel("a pass's resources are missing after creation".into())
}

/// One full-screen draw into `view`: the whole target, cleared first, or (`region`: x, y,
/// width, height) within the region alone, the rest of the target kept.
fn draw(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    region: Option<[u32; 4]>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        timestamp_writes,
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: match region {
                    Some(_) => wgpu::LoadOp::Load,
                    None => wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                },
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    if let Some([x, y, w, h]) = region {
        pass.set_scissor_rect(x, y, w, h);
    }
    pass.draw(0..3, 0..1);
}

/// Copies `region` (x, y, width, height in texels) of `from` to the same place in `to`: a tile
/// or table drawn in bands into a back target reaching the one the passes read.
fn copy_region(encoder: &mut wgpu::CommandEncoder, from: &Target, to: &Target, region: [u32; 4]) {
    let [x, y, width, height] = region;
    let origin = wgpu::Origin3d { x, y, z: 0 };
    encoder.copy_texture_to_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &from.texture,
            mip_level: 0,
            origin,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyTextureInfo {
            texture: &to.texture,
            mip_level: 0,
            origin,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
}
