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

use std::collections::BTreeMap;

use glam::{Mat4, Vec2, Vec3};
use nimbus_dsl::cloud::{Features, Genus, Quality, ScenePreset, analyse};
use nimbus_dsl::layout::UniformBytes;
use nimbus_dsl::model::clouds::{CloudVariant, cloud_module, resolve_module, shadow_module};
use nimbus_dsl::model::march::CloudUniforms;
use nimbus_dsl::model::resolve::{BAYER_OFFSETS, ResolveParams, reprojection};

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::pipelines::{CachedPipeline, HDR_FORMAT, Pass, PipelineCache, PipelineKey};
use crate::textures::{GpuTexture, NoiseKind};

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
            detail: 32,
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

/// What to render.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub genus: Genus,
    pub quality: Quality,
    pub features: Features,
    /// Sun elevation above the horizon and azimuth (degrees).
    pub sun_elevation_deg: f32,
    pub sun_azimuth_deg: f32,
    pub camera_altitude: f32,
    /// Camera pitch above the horizon, yaw, and vertical field of view (degrees).
    pub camera_pitch_deg: f32,
    pub camera_yaw_deg: f32,
    pub fov_deg: f32,
    /// Frames of temporal accumulation (at least 1). Upscaled, 16 frames shade every pixel
    /// once.
    pub frames: u32,
    /// Shade one pixel in sixteen per frame and reconstruct the rest from the history.
    pub upscale: bool,
    /// Keep the history of the previous `render` call (same size and mode) and reproject it,
    /// as a game loop does; otherwise each call starts afresh.
    pub continue_history: bool,
    /// Seed of the per-frame jitter sequence: same seed and frame, same pixels.
    pub seed: u32,
    /// Offset of the weather texture in tiles (wind drift).
    pub weather_offset: Vec2,
    /// Haze density at sea level (1/m).
    pub haze_density: f32,
    /// Turbulent displacement of cloud bases (m).
    pub turbulence_displacement: f32,
    /// Render the instrumented variant: alpha holds each pixel's density samples (use one
    /// full-resolution frame, so no resolve averages them).
    pub count_samples: bool,
}

impl Frame {
    /// A frame of `genus` at `quality` with the preset's toggles, from 2 m above the ground
    /// looking 12° up, sun 35° high.
    pub fn new(genus: Genus, quality: Quality, width: u32, height: u32) -> Frame {
        Frame {
            width,
            height,
            genus,
            quality,
            features: quality.features(),
            sun_elevation_deg: 35.0,
            sun_azimuth_deg: 150.0,
            camera_altitude: 2.0,
            camera_pitch_deg: 12.0,
            camera_yaw_deg: 0.0,
            fov_deg: 60.0,
            frames: 1,
            upscale: false,
            continue_history: false,
            seed: 0,
            weather_offset: Vec2::ZERO,
            haze_density: 3e-5,
            turbulence_displacement: 350.0,
            count_samples: false,
        }
    }

    /// The frame a scene describes, with the variant the scene derives (see
    /// [`nimbus_dsl::cloud::analyse`]): only the effects it can show.
    pub fn from_scene(scene: &ScenePreset, genus: &Genus, width: u32, height: u32) -> Frame {
        let mut genus = genus.clone();
        if let Some(c) = scene.coverage {
            genus.coverage = c;
        }
        let features = analyse(scene, &genus).features;
        let mut f = Frame::new(genus, scene.quality, width, height);
        f.features = features;
        f.sun_elevation_deg = scene.sun_elevation_deg;
        f.sun_azimuth_deg = scene.sun_azimuth_deg;
        f.camera_altitude = scene.camera_altitude;
        f.camera_pitch_deg = scene.camera_pitch_deg;
        f.camera_yaw_deg = scene.camera_yaw_deg;
        f.fov_deg = scene.fov_deg;
        f.weather_offset = Vec2::from_array(scene.weather_offset);
        f.haze_density = scene.haze_density;
        f.turbulence_displacement = scene.turbulence_displacement;
        f
    }

    /// The cloud variant this frame renders.
    pub fn variant(&self) -> CloudVariant {
        let mut v = CloudVariant::new(&self.genus, self.quality, self.features);
        v.key.count_samples = self.count_samples;
        v
    }

    fn sun_direction(&self) -> Vec3 {
        let (el, az) = (
            self.sun_elevation_deg.to_radians(),
            self.sun_azimuth_deg.to_radians(),
        );
        Vec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos())
    }

    /// View-projection without translation (the camera is the origin of the local frame).
    fn view_projection(&self) -> Mat4 {
        let (pitch, yaw) = (
            self.camera_pitch_deg.to_radians(),
            self.camera_yaw_deg.to_radians(),
        );
        let forward = Vec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            -pitch.cos() * yaw.cos(),
        );
        let view = Mat4::look_to_rh(Vec3::ZERO, forward, Vec3::Y);
        let aspect = self.width as f32 / self.height as f32;
        Mat4::perspective_rh(self.fov_deg.to_radians(), aspect, 1.0, 1e6) * view
    }
}

/// Linear HDR pixels, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
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

/// Where a cloud texture comes from.
pub enum TextureSource {
    /// Generated on the GPU by the noise kernels.
    Procedural,
    /// Supplied by the user (see [`crate::user_textures`]).
    User(GpuTexture),
}

/// A render target that is also sampled (cloud output, history).
struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    width: u32,
    height: u32,
}

/// History kept between frames: two targets the resolve ping-pongs between.
struct History {
    targets: [Target; 2],
    /// Index of the target holding the latest resolved frame.
    latest: usize,
    upscale: bool,
    view_projection: Mat4,
    frames: u32,
}

/// A renderer over one GPU: textures made on first use, pipelines cached by variant key.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    sizes: TextureSizes,
    textures: BTreeMap<&'static str, GpuTexture>,
    user: BTreeMap<&'static str, GpuTexture>,
    shadow_atlas: Option<(u32, u32, Target)>,
    /// What the atlas was last rendered from (variant key and uniform bytes): the atlas is
    /// redrawn only when the sun, the layers, the weather or the variant change.
    shadow_inputs: Option<(PipelineKey, Vec<u8>)>,
    pipelines: PipelineCache,
    history: Option<History>,
    samplers: Samplers,
    passes: Vec<&'static str>,
    /// GPU time of the passes of the last `render` call, where the adapter has timestamps.
    gpu_time_ms: Option<f64>,
}

/// Timestamp queries around every pass of one `render` call.
struct PassTimer {
    queries: wgpu::QuerySet,
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

struct Samplers {
    repeat: wgpu::Sampler,
    nearest: wgpu::Sampler,
    clamp: wgpu::Sampler,
}

fn texture_role(kind: NoiseKind) -> &'static str {
    match kind {
        NoiseKind::Weather => "weather_texture",
        NoiseKind::Shape => "shape_texture",
        NoiseKind::Detail => "detail_texture",
        NoiseKind::Turbulence => "turbulence_texture",
    }
}

fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((h >> 10) & 0x1f);
    let mant = f32::from(h & 0x3ff);
    match exp {
        0 => sign * mant * 2f32.powi(-24),
        31 => {
            if mant == 0.0 {
                sign * f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => sign * (1.0 + mant / 1024.0) * 2f32.powi(exp - 15),
    }
}

impl<'g> Renderer<'g> {
    pub fn new(gpu: &'g Gpu, sizes: TextureSizes) -> Self {
        let sampler = |label, address, filter| gpu.sampler(label, address, filter);
        let samplers = Samplers {
            repeat: sampler(
                "linear repeat",
                wgpu::AddressMode::Repeat,
                wgpu::FilterMode::Linear,
            ),
            nearest: sampler(
                "nearest clamp",
                wgpu::AddressMode::ClampToEdge,
                wgpu::FilterMode::Nearest,
            ),
            clamp: sampler(
                "linear clamp",
                wgpu::AddressMode::ClampToEdge,
                wgpu::FilterMode::Linear,
            ),
        };
        Renderer {
            gpu,
            sizes,
            textures: BTreeMap::new(),
            user: BTreeMap::new(),
            shadow_atlas: None,
            shadow_inputs: None,
            pipelines: PipelineCache::default(),
            history: None,
            samplers,
            passes: Vec::new(),
            gpu_time_ms: None,
        }
    }

    /// Uses a user texture for `kind` instead of the procedural one.
    pub fn set_texture(&mut self, kind: NoiseKind, source: TextureSource) {
        let role = texture_role(kind);
        self.textures.remove(role);
        match source {
            TextureSource::Procedural => {
                self.user.remove(role);
            }
            TextureSource::User(t) => {
                self.user.insert(role, t);
            }
        }
    }

    /// Pipelines built so far (one per pass and variant key).
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.built().len()
    }

    pub fn stats(&self) -> RenderStats {
        let mut textures: Vec<String> = self.textures.keys().map(|k| k.to_string()).collect();
        textures.extend(self.user.keys().map(|k| format!("{k} (user)")));
        if let Some((w, h, _)) = &self.shadow_atlas {
            textures.push(format!("shadow_map ({w}x{h})"));
        }
        if let Some(h) = &self.history {
            textures.push(format!(
                "history ({}x{}, 2 targets)",
                h.targets[0].width, h.targets[0].height
            ));
        }
        RenderStats {
            pipelines: self
                .pipelines
                .built()
                .iter()
                .map(|k| k.to_string())
                .collect(),
            textures,
            passes: self.passes.clone(),
        }
    }

    fn noise(&mut self, kind: NoiseKind) -> Result<(), RuntimeError> {
        let role = texture_role(kind);
        if !self.user.contains_key(role) && !self.textures.contains_key(role) {
            let t = self.gpu.noise_texture(kind, self.sizes.of(kind))?;
            self.textures.insert(role, t);
        }
        Ok(())
    }

    fn target(&self, label: &str, width: u32, height: u32) -> Target {
        let texture = self.gpu.device().create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HDR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        Target {
            texture,
            view,
            width,
            height,
        }
    }

    fn check_size(&self, what: &str, width: u32, height: u32) -> Result<(), RuntimeError> {
        let max = self.gpu.device().limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RuntimeError::Limit(format!(
                "{what} of {width}x{height} is outside 1..={max} texels per side on {}",
                self.gpu.info()
            )));
        }
        Ok(())
    }

    fn pipeline(
        &mut self,
        pass: Pass,
        variant: &CloudVariant,
    ) -> Result<&CachedPipeline, RuntimeError> {
        self.pipelines
            .get_or_build(self.gpu, pipeline_key(pass, variant), || match pass {
                Pass::Shadow => shadow_module(variant),
                Pass::Clouds => cloud_module(variant),
                Pass::Resolve => resolve_module(),
            })
    }

    /// A pipeline already built by [`Self::pipeline`].
    fn built(&self, pass: Pass, variant: &CloudVariant) -> Result<&CachedPipeline, RuntimeError> {
        self.pipelines.get(&pipeline_key(pass, variant))
    }

    /// Binds a pass's declared bindings from what the renderer holds.
    fn bind_group(
        &self,
        pipeline: &CachedPipeline,
        uniform: &wgpu::Buffer,
        extra: &[(&str, &wgpu::TextureView)],
    ) -> Result<wgpu::BindGroup, RuntimeError> {
        let mut entries = Vec::new();
        for (name, binding) in &pipeline.bindings {
            let texture = |role: &str| {
                self.user
                    .get(role)
                    .or_else(|| self.textures.get(role))
                    .map(|t| wgpu::BindingResource::TextureView(&t.view))
            };
            let resource = match name.as_str() {
                "clouds" | "resolve" => Some(uniform.as_entire_binding()),
                "linear_sampler" if pipeline.binds("history_texture") => {
                    Some(wgpu::BindingResource::Sampler(&self.samplers.clamp))
                }
                "linear_sampler" => Some(wgpu::BindingResource::Sampler(&self.samplers.repeat)),
                "nearest_sampler" => Some(wgpu::BindingResource::Sampler(&self.samplers.nearest)),
                "shadow_map" => self
                    .shadow_atlas
                    .as_ref()
                    .map(|(_, _, t)| wgpu::BindingResource::TextureView(&t.view)),
                other => extra
                    .iter()
                    .find(|(n, _)| *n == other)
                    .map(|(_, v)| wgpu::BindingResource::TextureView(v))
                    .or_else(|| texture(other)),
            };
            let resource = resource.ok_or_else(|| {
                RuntimeError::Kernel(format!("nothing to bind to `{name}` (binding {binding})"))
            })?;
            entries.push(wgpu::BindGroupEntry {
                binding: *binding,
                resource,
            });
        }
        Ok(self
            .gpu
            .device()
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.pipeline.get_bind_group_layout(0),
                entries: &entries,
            }))
    }

    fn uniform_buffer(&self, label: &str, bytes: &[u8]) -> wgpu::Buffer {
        let buffer = self.gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.len() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu.queue().write_buffer(&buffer, 0, bytes);
        buffer
    }

    /// The uniforms of `frame` at frame index 0.
    pub fn uniforms(frame: &Frame) -> CloudUniforms {
        let mut u = CloudUniforms::for_genus(
            &frame.genus,
            frame.quality,
            frame.sun_direction(),
            frame.camera_altitude,
        );
        u.inverse_view_projection = frame.view_projection().inverse();
        u.resolution = Vec2::new(frame.width as f32, frame.height as f32);
        u.media.weather_offset = frame.weather_offset;
        u.media.turbulence_displacement = frame.turbulence_displacement;
        u.haze.density = frame.haze_density;
        u
    }

    /// Renders `frame` (all its accumulation frames); `progress` hears of each frame done.
    pub fn render_with_progress(
        &mut self,
        frame: &Frame,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<Image, RuntimeError> {
        self.check_size("the image", frame.width, frame.height)?;
        let frames = frame.frames.max(1);
        let variant = frame.variant();
        self.passes.clear();
        self.gpu_time_ms = None;
        let device = self.gpu.device();
        let mut timer = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| {
                // Shadow, then clouds and resolve per frame: two timestamps each.
                let capacity = (2 * (1 + 2 * frames)).min(4096);
                PassTimer {
                    queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                        label: Some("pass timestamps"),
                        ty: wgpu::QueryType::Timestamp,
                        count: capacity,
                    }),
                    capacity,
                    used: 0,
                }
            });
        let mut u = Self::uniforms(frame);

        // Pipelines first: their bindings decide which textures exist.
        let clouds_bindings = self.pipeline(Pass::Clouds, &variant)?.bindings.clone();
        let mut needed: Vec<NoiseKind> = NoiseKind::ALL
            .into_iter()
            .filter(|k| clouds_bindings.iter().any(|(n, _)| n == texture_role(*k)))
            .collect();
        let shadowed = variant.key.uses_shadow_map();
        if shadowed {
            let b = self.pipeline(Pass::Shadow, &variant)?.bindings.clone();
            for k in NoiseKind::ALL {
                if b.iter().any(|(n, _)| n == texture_role(k)) && !needed.contains(&k) {
                    needed.push(k);
                }
            }
        }
        for k in needed {
            self.noise(k)?;
        }
        let resolve = frame.upscale || frames > 1;
        if resolve {
            self.pipeline(Pass::Resolve, &variant)?;
        }

        let uniform = self.uniform_buffer("cloud uniforms", &u.to_uniform_bytes());
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        if shadowed {
            let s = u.shadow;
            let (w, h) = (s.map_size as u32 * s.cascade_count, s.map_size as u32);
            self.check_size("the shadow atlas (cascades side by side)", w, h)?;
            if !matches!(&self.shadow_atlas, Some((aw, ah, _)) if (*aw, *ah) == (w, h)) {
                self.shadow_atlas = Some((w, h, self.target("shadow atlas", w, h)));
                self.shadow_inputs = None;
            }
            // The camera's orientation and the image size do not enter the atlas.
            let mut inputs = u;
            inputs.inverse_view_projection = Mat4::IDENTITY;
            inputs.resolution = Vec2::ZERO;
            let inputs = (
                pipeline_key(Pass::Shadow, &variant),
                inputs.to_uniform_bytes(),
            );
            if self.shadow_inputs.as_ref() != Some(&inputs) {
                let pipeline = self.built(Pass::Shadow, &variant)?;
                let group = self.bind_group(pipeline, &uniform, &[])?;
                let (_, _, atlas) = self.shadow_atlas.as_ref().ok_or_else(|| {
                    RuntimeError::Kernel("shadow atlas missing after creation".into())
                })?;
                draw(
                    &mut encoder,
                    "shadow",
                    &atlas.view,
                    &pipeline.pipeline,
                    &group,
                    PassTimer::next(&mut timer),
                );
                self.passes.push(Pass::Shadow.name());
                self.shadow_inputs = Some(inputs);
            }
        } else {
            // No shadows in this variant: the atlas of an earlier one is not kept.
            self.shadow_atlas = None;
            self.shadow_inputs = None;
        }
        self.gpu.queue().submit([encoder.finish()]);

        let scale = if frame.upscale { 4 } else { 1 };
        let (lw, lh) = (frame.width.div_ceil(scale), frame.height.div_ceil(scale));
        let current = self.target("clouds", lw, lh);
        let view_projection = frame.view_projection();
        let keep = frame.continue_history
            && matches!(&self.history, Some(h) if h.upscale == frame.upscale
                && h.targets[0].width == frame.width && h.targets[0].height == frame.height);
        if resolve && !keep {
            self.history = Some(History {
                targets: [
                    self.target("history A", frame.width, frame.height),
                    self.target("history B", frame.width, frame.height),
                ],
                latest: 0,
                upscale: frame.upscale,
                view_projection,
                frames: 0,
            });
        } else if !resolve {
            self.history = None;
        }
        for f in 0..frames {
            let previous_frames = self.history.as_ref().map_or(0, |h| h.frames);
            let index = previous_frames + f;
            let offset = if frame.upscale {
                BAYER_OFFSETS[(index % 16) as usize]
            } else {
                [0, 0]
            };
            u.frame = frame.seed.wrapping_mul(7919).wrapping_add(index);
            // Golden-ratio sequence: successive frames spread their first samples evenly.
            u.jitter = (index as f32 * 0.618_034 + frame.seed as f32 * 0.754_877_7).fract();
            u.pixel_scale = scale as f32;
            u.pixel_offset = Vec2::new(offset[0] as f32, offset[1] as f32);
            self.gpu
                .queue()
                .write_buffer(&uniform, 0, &u.to_uniform_bytes());
            let mut encoder = self
                .gpu
                .device()
                .create_command_encoder(&Default::default());
            let pipeline = self.built(Pass::Clouds, &variant)?;
            let group = self.bind_group(pipeline, &uniform, &[])?;
            draw(
                &mut encoder,
                "clouds",
                &current.view,
                &pipeline.pipeline,
                &group,
                PassTimer::next(&mut timer),
            );
            self.passes.push(Pass::Clouds.name());
            if let Some(h) = &self.history {
                // Upscaled, a pixel is refreshed once per 16 frames: average those visits.
                let visits = if frame.upscale { index / 16 } else { index };
                let params = ResolveParams {
                    reprojection: reprojection(h.view_projection, view_projection.inverse()),
                    resolution: u.resolution,
                    low_resolution: Vec2::new(lw as f32, lh as f32),
                    pixel_offset: u.pixel_offset,
                    pixel_scale: scale as f32,
                    current_weight: 1.0 / (visits as f32 + 1.0),
                    variance_gamma: if frame.upscale { 2.0 } else { 4.0 },
                    history_valid: if index == 0 { 0.0 } else { 1.0 },
                };
                let (read, write) = (h.latest, 1 - h.latest);
                let resolve_uniform =
                    self.uniform_buffer("resolve uniforms", &params.to_uniform_bytes());
                let pipeline = self.built(Pass::Resolve, &variant)?;
                let group = self.bind_group(
                    pipeline,
                    &resolve_uniform,
                    &[
                        ("current_texture", &current.view),
                        ("history_texture", &h.targets[read].view),
                    ],
                )?;
                draw(
                    &mut encoder,
                    "resolve",
                    &h.targets[write].view,
                    &pipeline.pipeline,
                    &group,
                    PassTimer::next(&mut timer),
                );
                self.passes.push(Pass::Resolve.name());
            }
            self.gpu.queue().submit([encoder.finish()]);
            if let Some(h) = &mut self.history {
                h.latest = 1 - h.latest;
                h.view_projection = view_projection;
            }
            progress(f + 1, frames);
        }
        if let Some(h) = &mut self.history {
            h.frames += frames;
        }
        if let Some(t) = &timer {
            self.gpu_time_ms = Some(self.read_timestamps(t)?);
        }
        let out = match &self.history {
            Some(h) => &h.targets[h.latest],
            None => &current,
        };
        self.read_back(out)
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
        let device = self.gpu.device();
        let size = u64::from(timer.used) * 8;
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.resolve_query_set(&timer.queries, 0..timer.used, &resolve, 0);
        encoder.copy_buffer_to_buffer(&resolve, 0, &readback, 0, size);
        self.gpu.queue().submit([encoder.finish()]);
        let bytes = self.gpu.map_read(&readback)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let period_ns = f64::from(self.gpu.queue().get_timestamp_period());
        let total: u64 = ticks
            .chunks_exact(2)
            .map(|p| p[1].saturating_sub(p[0]))
            .sum();
        Ok(total as f64 * period_ns * 1e-6)
    }

    /// The shadow atlas of the last frame (front depth, mean extinction, max optical depth,
    /// tail per texel), if the last variant had one.
    pub fn shadow_atlas(&self) -> Result<Option<Image>, RuntimeError> {
        match &self.shadow_atlas {
            Some((_, _, t)) => Ok(Some(self.read_back(t)?)),
            None => Ok(None),
        }
    }

    /// Renders `frame`.
    pub fn render(&mut self, frame: &Frame) -> Result<Image, RuntimeError> {
        self.render_with_progress(frame, &mut |_, _| {})
    }

    fn read_back(&self, target: &Target) -> Result<Image, RuntimeError> {
        let (width, height) = (target.width, target.height);
        let row_bytes = (width * 8).div_ceil(256) * 256;
        let device = self.gpu.device();
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame readback"),
            size: u64::from(row_bytes) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            target.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
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
        let data = self.gpu.map_read(&readback)?;
        let mut pixels = Vec::with_capacity((width * height) as usize);
        for y in 0..height as usize {
            let row = &data[y * row_bytes as usize..];
            let halves: &[u16] = bytemuck::cast_slice(&row[..width as usize * 8]);
            for px in halves.chunks_exact(4) {
                pixels.push([
                    f16_to_f32(px[0]),
                    f16_to_f32(px[1]),
                    f16_to_f32(px[2]),
                    f16_to_f32(px[3]),
                ]);
            }
        }
        Ok(Image {
            width,
            height,
            pixels,
        })
    }
}

fn pipeline_key(pass: Pass, variant: &CloudVariant) -> PipelineKey {
    // The shadow pass depends on the density alone: variants that differ in lighting (or in
    // the sample counter) share its pipeline and atlas.
    let key = match pass {
        Pass::Shadow => variant.key.shadow_key(),
        _ => variant.key,
    };
    PipelineKey {
        pass,
        key: (pass != Pass::Resolve).then_some(key),
    }
}

/// One full-screen draw into `view`, cleared first.
fn draw(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        timestamp_writes,
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.draw(0..3, 0..1);
}
