//! Rendering a cloud variant: a full-screen pass of the generated cloud shader over the
//! procedural textures, with pipelines cached by variant so switching presets reuses what was
//! built. The runtime creates pipelines only from codegen's WGSL.

use std::collections::HashMap;

use glam::{Mat4, Vec3};
use nimbus_codegen::{Target, generate};
use nimbus_dsl::cloud::{Features, Genus, Quality};
use nimbus_dsl::layout::UniformBytes;
use nimbus_dsl::model::clouds::{CloudVariant, cloud_module};
use nimbus_dsl::model::march::CloudUniforms;
use wgpu::util::DeviceExt;

use crate::error::RuntimeError;
use crate::gpu::Gpu;
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
    /// Jitter of the first march sample, in [0, 1).
    pub jitter: f32,
}

/// Linear HDR pixels, row-major, top row first.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

/// Textures, shared by every pipeline.
struct Textures {
    weather: GpuTexture,
    shape: GpuTexture,
    detail: GpuTexture,
    turbulence: GpuTexture,
    shadow: GpuTexture,
    sampler: wgpu::Sampler,
}

/// A renderer over one GPU: textures made once, pipelines cached by variant.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    sizes: TextureSizes,
    textures: Option<Textures>,
    pipelines: HashMap<String, wgpu::RenderPipeline>,
}

const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

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
        Renderer {
            gpu,
            sizes,
            textures: None,
            pipelines: HashMap::new(),
        }
    }

    /// Pipelines built so far (one per variant rendered).
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.len()
    }

    fn textures(&mut self) -> Result<&Textures, RuntimeError> {
        if self.textures.is_none() {
            let g = self.gpu;
            let s = self.sizes;
            let sampler = g.device().create_sampler(&wgpu::SamplerDescriptor {
                label: Some("linear repeat"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                address_mode_w: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            });
            self.textures = Some(Textures {
                weather: g.noise_texture(NoiseKind::Weather, s.weather)?,
                shape: g.noise_texture(NoiseKind::Shape, s.shape)?,
                detail: g.noise_texture(NoiseKind::Detail, s.detail)?,
                turbulence: g.noise_texture(NoiseKind::Turbulence, s.turbulence)?,
                // No beer shadow map pass yet: an empty map (no optical depth) keeps the
                // shadow lookup valid.
                shadow: g.constant_texture([0.0; 4]),
                sampler,
            });
        }
        self.textures
            .as_ref()
            .ok_or_else(|| RuntimeError::Kernel("textures missing".into()))
    }

    fn pipeline(&mut self, variant: &CloudVariant) -> Result<&wgpu::RenderPipeline, RuntimeError> {
        let key = variant.name();
        if !self.pipelines.contains_key(&key) {
            let module = cloud_module(variant)?;
            let wgsl = generate(module, &key, &[Target::Wgsl])?.wgsl;
            let device = self.gpu.device();
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&key),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&key),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(TARGET_FORMAT.into())],
                }),
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                multiview_mask: None,
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(RuntimeError::Pipeline {
                    what: format!("render pipeline `{key}`"),
                    reason: e.to_string(),
                });
            }
            self.pipelines.insert(key.clone(), pipeline);
        }
        self.pipelines
            .get(&key)
            .ok_or_else(|| RuntimeError::Kernel("pipeline missing".into()))
    }

    /// Renders one frame.
    pub fn render(&mut self, frame: &Frame) -> Result<Image, RuntimeError> {
        let max = self.gpu.device().limits().max_texture_dimension_2d;
        if frame.width == 0 || frame.height == 0 || frame.width > max || frame.height > max {
            return Err(RuntimeError::Kernel(format!(
                "resolution {}x{} is outside 1..={max} on this adapter",
                frame.width, frame.height
            )));
        }
        let variant = CloudVariant::new(&frame.genus, frame.quality, frame.features);
        let (el, az) = (
            frame.sun_elevation_deg.to_radians(),
            frame.sun_azimuth_deg.to_radians(),
        );
        let sun = Vec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos());
        let mut u =
            CloudUniforms::for_genus(&frame.genus, frame.quality, sun, frame.camera_altitude);
        let (pitch, yaw) = (
            frame.camera_pitch_deg.to_radians(),
            frame.camera_yaw_deg.to_radians(),
        );
        let forward = Vec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            -pitch.cos() * yaw.cos(),
        );
        let view = Mat4::look_to_rh(Vec3::ZERO, forward, Vec3::Y);
        let aspect = frame.width as f32 / frame.height as f32;
        let proj = Mat4::perspective_rh(frame.fov_deg.to_radians(), aspect, 1.0, 1e6);
        u.inverse_view_projection = (proj * view).inverse();
        u.resolution = glam::vec2(frame.width as f32, frame.height as f32);
        u.jitter = frame.jitter;
        let uniform_bytes = u.to_uniform_bytes();

        self.textures()?;
        self.pipeline(&variant)?;
        let (Some(t), Some(pipeline)) =
            (self.textures.as_ref(), self.pipelines.get(&variant.name()))
        else {
            return Err(RuntimeError::Kernel("renderer state missing".into()));
        };
        let device = self.gpu.device();
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("cloud uniforms"),
            contents: &uniform_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Bind only what the variant's shader declares: a toggle that is off has no binding.
        let layout = pipeline.get_bind_group_layout(0);
        let wgsl_bindings = generate(cloud_module(&variant)?, "bindings", &[Target::Wgsl])?
            .ir
            .globals;
        let mut entries = Vec::new();
        for g in &wgsl_bindings {
            let Some((_, binding)) = g.binding() else {
                continue;
            };
            let resource = match g.name.as_str() {
                "clouds" => uniform.as_entire_binding(),
                "weather_texture" => wgpu::BindingResource::TextureView(&t.weather.view),
                "shape_texture" => wgpu::BindingResource::TextureView(&t.shape.view),
                "detail_texture" => wgpu::BindingResource::TextureView(&t.detail.view),
                "turbulence_texture" => wgpu::BindingResource::TextureView(&t.turbulence.view),
                "shadow_map" => wgpu::BindingResource::TextureView(&t.shadow.view),
                "linear_sampler" => wgpu::BindingResource::Sampler(&t.sampler),
                other => {
                    return Err(RuntimeError::Kernel(format!(
                        "unexpected binding `{other}`"
                    )));
                }
            };
            entries.push(wgpu::BindGroupEntry { binding, resource });
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("clouds"),
            layout: &layout,
            entries: &entries,
        });
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("clouds target"),
            size: wgpu::Extent3d {
                width: frame.width,
                height: frame.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: TARGET_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = target.create_view(&Default::default());
        let row_bytes = (frame.width * 8).div_ceil(256) * 256;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame readback"),
            size: u64::from(row_bytes) * u64::from(frame.height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("clouds"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
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
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        encoder.copy_texture_to_buffer(
            target.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row_bytes),
                    rows_per_image: Some(frame.height),
                },
            },
            wgpu::Extent3d {
                width: frame.width,
                height: frame.height,
                depth_or_array_layers: 1,
            },
        );
        self.gpu.queue().submit([encoder.finish()]);
        let data = self.gpu.map_read(&readback)?;
        let mut pixels = Vec::with_capacity((frame.width * frame.height) as usize);
        for y in 0..frame.height as usize {
            let row = &data[y * row_bytes as usize..];
            let halves: &[u16] = bytemuck::cast_slice(&row[..frame.width as usize * 8]);
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
            width: frame.width,
            height: frame.height,
            pixels,
        })
    }
}
