//! The cloud textures, generated on the GPU by compute shaders recorded from the noise
//! `#[shader_fn]`s (whose CPU twins test them). Each kernel writes RGBA8 texels into a buffer
//! with rows padded to 256 bytes, from which the texture is made in half floats.

use nimbus_clouds::model::noise::{curl_noise, detail_noise, shape_noise, weather_noise};
use nimbus_codegen::{Generated, Target, generate};
use nimbus_dsl::shader::{self, F32, I32, U32};
use nimbus_dsl::{ModuleBuilder, loc};
use wgpu::util::DeviceExt;

use crate::error::RuntimeError;
use crate::gpu::Gpu;

/// Which noise a texture holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum NoiseKind {
    /// 2D RGBA coverage (low, mid, high, extra).
    Weather,
    /// 3D Perlin–Worley.
    Shape,
    /// 3D Worley.
    Detail,
    /// 2D curl noise.
    Turbulence,
}

impl NoiseKind {
    /// The procedural texture `resource` is, if it is one.
    pub fn of(resource: nimbus_clouds::model::resource::Resource) -> Option<NoiseKind> {
        Self::ALL.into_iter().find(|k| k.resource() == resource)
    }

    fn is_3d(self) -> bool {
        matches!(self, NoiseKind::Shape | NoiseKind::Detail)
    }

    /// The channels the cloud passes read, and so the channels its texture holds: the two 3D
    /// noises only their red (the density's erosion reads `.x` of each; `tests/clouds.rs`
    /// checks every catalogued shader), the 2D maps all four. One half float a texel in place
    /// of four took 7 % off `low`'s frame in SwiftShader, with the same values sampled.
    pub fn channels(self) -> u32 {
        if self.is_3d() { 1 } else { 4 }
    }

    /// Lattice cells per side: the noise's base frequency within one tile.
    fn cells(self) -> i32 {
        match self {
            NoiseKind::Weather => nimbus_clouds::model::noise::WEATHER_CELLS,
            NoiseKind::Shape => 4,
            NoiseKind::Detail => 4,
            NoiseKind::Turbulence => 8,
        }
    }

    /// The resource it is in the passes' bindings.
    pub fn resource(self) -> nimbus_clouds::model::resource::Resource {
        use nimbus_clouds::model::resource::Resource;
        match self {
            NoiseKind::Weather => Resource::Weather,
            NoiseKind::Shape => Resource::Shape,
            NoiseKind::Detail => Resource::Detail,
            NoiseKind::Turbulence => Resource::Turbulence,
        }
    }

    /// `weather`, `shape`, `detail`, `turbulence`: its resource's id.
    pub fn name(self) -> &'static str {
        self.resource().id()
    }
}

/// The value of a packed RGBA8 texel as the textures hold it: each channel `k/255` rounded to
/// the nearest half float, on the GPU ([`Gpu::texture_from_texels`]) and in the CPU twins alike.
pub fn texel_value(word: u32) -> glam::Vec4 {
    glam::Vec4::from_array(std::array::from_fn(|c| {
        half::f16::from_bits(texel_half_bits((word >> (8 * c)) as u8)).to_f32()
    }))
}

/// The half float (IEEE 754 binary16 bits) an 8-bit texel channel `k` stands for: `k/255`
/// rounded to the nearest half float, as [`texel_value`] reads it. Engine packages print this
/// table so their hosts widen the texture files' bytes exactly as the runtime does.
pub fn texel_half_bits(k: u8) -> u16 {
    half::f16::from_f32(f32::from(k) / 255.0).to_bits()
}

/// Texels per row in the buffer: rows padded to 256 bytes.
pub fn padded_row(size: u32) -> u32 {
    (size * 4).div_ceil(256) * 256 / 4
}

/// The kernel that fills a `size`-texel (per side) texture of `kind`, generated.
fn noise_kernel(kind: NoiseKind, size: u32) -> Result<Generated, RuntimeError> {
    let row = padded_row(size);
    let module = ModuleBuilder::build(
        &format!("{}_texture", kind.name()),
        "Fills one procedural cloud texture, one texel per invocation.",
        loc!(),
        |m| {
            let out = m.storage::<U32>(
                "texels",
                0,
                0,
                true,
                "RGBA8 texels, rows padded to 256 bytes.",
            );
            m.compute(
                "fill",
                "One texel per invocation.",
                loc!(),
                [64, 1, 1],
                |gid| {
                    let index = gid.x;
                    let x = index % size;
                    let y = (index / size) % size;
                    let z = index / (size * size);
                    let inv = 1.0 / size as f32;
                    let u = (nimbus_dsl::ops::cast::<F32, _>(x) + 0.5) * inv;
                    let v = (nimbus_dsl::ops::cast::<F32, _>(y) + 0.5) * inv;
                    let w = (nimbus_dsl::ops::cast::<F32, _>(z) + 0.5) * inv;
                    let cells = I32::lit(kind.cells());
                    let texel = match kind {
                        NoiseKind::Shape => {
                            let s = shape_noise::shader(shader::vec3(u, v, w), cells);
                            shader::vec4(s, s, s, 1.0)
                        }
                        NoiseKind::Detail => {
                            let d = detail_noise::shader(shader::vec3(u, v, w), cells);
                            shader::vec4(d, d, d, 1.0)
                        }
                        NoiseKind::Weather => weather_noise::shader(shader::vec2(u, v), cells),
                        NoiseKind::Turbulence => curl_noise::shader(shader::vec2(u, v), cells),
                    };
                    let target = x + y * row + z * row * size;
                    out.array()
                        .set(target, nimbus_dsl::builtins::pack4x8unorm(texel));
                },
            );
        },
    )?;
    Ok(generate(module, "default", &[Target::Wgsl])?)
}

/// A generated texture and its view.
pub struct GpuTexture {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub size: u32,
    /// Means of the red channel and of its sixth power, where known: the detail noise's level
    /// of detail erodes with them where the noise is finer than a sample
    /// (`MediaParams::with_detail_lod`).
    pub red_moments: Option<glam::Vec2>,
}

impl Gpu {
    /// Generates a procedural texture of `kind` with `size` texels per side on the GPU.
    pub fn noise_texture(&self, kind: NoiseKind, size: u32) -> Result<GpuTexture, RuntimeError> {
        let buffer = self.noise_buffer(kind, size)?;
        self.texture_from_texels(kind, &buffer, size)
    }

    /// The texels of a procedural texture, RGBA8 in a storage buffer with rows padded to
    /// [`padded_row`] (what the formation kernel gates, and what textures are copied from).
    pub(crate) fn noise_buffer(
        &self,
        kind: NoiseKind,
        size: u32,
    ) -> Result<wgpu::Buffer, RuntimeError> {
        let depth = if kind.is_3d() { size } else { 1 };
        let count = size * size * depth;
        let row = padded_row(size);
        let words = (row * size * depth) as usize;
        let kernel = noise_kernel(kind, size)?;
        let groups = count.div_ceil(64);
        self.compute_to_buffer(&kernel, "fill", words, groups)
    }

    /// A texture of `kind` holding the padded RGBA8 texels of `buffer` ([`Self::noise_buffer`]),
    /// widened to half floats ([`texel_value`], what the CPU twins read too).
    ///
    /// Not RGBA8 itself: lavapipe filters an 8-bit texture in 8-bit arithmetic, so a filtered
    /// value lands on a coarse lattice around the exact one. That rounding is zero on average,
    /// but the coverage threshold clamps it at zero and keeps only its positive half, so it put
    /// cloud where the model has none: a one-pixel halo of faint opacity around every cloud,
    /// pixels of opacity under 1 % 1.7 times as opaque as the CPU twin's, and the thin edges
    /// 8 % too bright against it (and 3.5 % against Mitsuba). Half floats filter in float:
    /// 1.07 times, and the halo gone (the agreement suite's thin edges).
    pub(crate) fn texture_from_texels(
        &self,
        kind: NoiseKind,
        buffer: &wgpu::Buffer,
        size: u32,
    ) -> Result<GpuTexture, RuntimeError> {
        let depth = if kind.is_3d() { size } else { 1 };
        let row = padded_row(size);
        let padded = self.read_buffer(buffer, (row * size * depth) as usize)?;
        let channels = kind.channels() as usize;
        let mut halves: Vec<u16> = Vec::with_capacity((size * size * depth) as usize * channels);
        for z in 0..depth {
            for y in 0..size {
                let start = ((z * size + y) * row) as usize;
                for word in &padded[start..start + size as usize] {
                    let texel = texel_value(*word).to_array().map(crate::gpu::f16_bits);
                    halves.extend(&texel[..channels]);
                }
            }
        }
        let dimension = if kind.is_3d() {
            wgpu::TextureDimension::D3
        } else {
            wgpu::TextureDimension::D2
        };
        let (texture, view) = self.half_float_texture(
            kind.name(),
            [size, size, depth],
            dimension,
            kind.channels(),
            &halves,
        );
        Ok(GpuTexture {
            texture,
            view,
            size,
            red_moments: (kind == NoiseKind::Detail)
                .then_some(nimbus_clouds::model::noise::DETAIL_MOMENTS),
        })
    }

    /// A sampled half-float texture of `size` (width, height, depth) holding `halves` (f16
    /// bits, `channels` per texel, x fastest: `R16Float` for one, `Rgba16Float` for four), and
    /// its view: every texture the cloud passes read.
    pub(crate) fn half_float_texture(
        &self,
        label: &str,
        size: [u32; 3],
        dimension: wgpu::TextureDimension,
        channels: u32,
        halves: &[u16],
    ) -> (wgpu::Texture, wgpu::TextureView) {
        let format = if channels == 1 {
            wgpu::TextureFormat::R16Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        };
        let texture = self.device().create_texture_with_data(
            self.queue(),
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size[0],
                    height: size[1],
                    depth_or_array_layers: size[2],
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(halves),
        );
        let view = texture.create_view(&Default::default());
        (texture, view)
    }

    /// A 1×1 texture holding `texel` (e.g. an empty shadow map).
    pub fn constant_texture(&self, texel: [f32; 4]) -> GpuTexture {
        let data: Vec<u16> = texel.iter().map(|v| crate::gpu::f16_bits(*v)).collect();
        let (texture, view) =
            self.half_float_texture("constant", [1, 1, 1], wgpu::TextureDimension::D2, 4, &data);
        GpuTexture {
            texture,
            view,
            size: 1,
            red_moments: Some(glam::Vec2::new(texel[0], texel[0].powi(6))),
        }
    }

    /// Runs a compute kernel whose only binding is a read-write `array<u32>` of `words` words
    /// at binding 0, and returns the buffer (for copies).
    pub(crate) fn compute_to_buffer(
        &self,
        kernel: &Generated,
        entry: &str,
        words: usize,
        groups: u32,
    ) -> Result<wgpu::Buffer, RuntimeError> {
        let max_groups = self.device().limits().max_compute_workgroups_per_dimension;
        if groups > max_groups {
            return Err(RuntimeError::Kernel(format!(
                "texture kernel `{entry}` needs {groups} workgroups; this adapter allows {max_groups} (use a smaller texture)"
            )));
        }
        let device = self.device();
        let (pipeline, layout) = self.compute_pipeline(kernel, entry)?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("texels"),
            contents: &vec![0u8; words.max(1) * 4],
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
        self.queue().submit([encoder.finish()]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: format!("texture kernel `{entry}`"),
                reason: e.to_string(),
            });
        }
        Ok(buffer)
    }
}

impl Gpu {
    /// Reads `words` words back from a buffer with `COPY_SRC` usage.
    pub fn read_buffer(
        &self,
        buffer: &wgpu::Buffer,
        words: usize,
    ) -> Result<Vec<u32>, RuntimeError> {
        let size = (words.max(1) * 4) as u64;
        let readback = self.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device().create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &readback, 0, size);
        self.queue().submit([encoder.finish()]);
        let data = self.map_read(&readback)?;
        let out = bytemuck::cast_slice::<u8, u32>(&data)[..words].to_vec();
        Ok(out)
    }

    /// The texels a noise kernel writes, unpadded, for tests against the CPU twins.
    pub fn noise_texels(&self, kind: NoiseKind, size: u32) -> Result<Vec<u32>, RuntimeError> {
        let depth = if kind.is_3d() { size } else { 1 };
        let row = padded_row(size);
        let words = (row * size * depth) as usize;
        let buffer = self.compute_to_buffer(
            &noise_kernel(kind, size)?,
            "fill",
            words,
            (size * size * depth).div_ceil(64),
        )?;
        let padded = self.read_buffer(&buffer, words)?;
        let mut out = Vec::with_capacity((size * size * depth) as usize);
        for z in 0..depth {
            for y in 0..size {
                let start = ((z * size + y) * row) as usize;
                out.extend_from_slice(&padded[start..start + size as usize]);
            }
        }
        Ok(out)
    }
}

impl NoiseKind {
    /// The texel the CPU twin computes for texel (x, y, z) of a `size` texture.
    pub fn cpu_texel(self, size: u32, x: u32, y: u32, z: u32) -> u32 {
        use nimbus_dsl::builtins::pack4x8unorm;
        let inv = 1.0 / size as f32;
        let (u, v, w) = (
            (x as f32 + 0.5) * inv,
            (y as f32 + 0.5) * inv,
            (z as f32 + 0.5) * inv,
        );
        let cells = self.cells();
        let texel = match self {
            NoiseKind::Shape => {
                let s = shape_noise(glam::vec3(u, v, w), cells);
                glam::vec4(s, s, s, 1.0)
            }
            NoiseKind::Detail => {
                let d = detail_noise(glam::vec3(u, v, w), cells);
                glam::vec4(d, d, d, 1.0)
            }
            NoiseKind::Weather => weather_noise(glam::vec2(u, v), cells),
            NoiseKind::Turbulence => curl_noise(glam::vec2(u, v), cells),
        };
        pack4x8unorm(texel)
    }

    pub const ALL: [NoiseKind; 4] = [
        NoiseKind::Weather,
        NoiseKind::Shape,
        NoiseKind::Detail,
        NoiseKind::Turbulence,
    ];
}
