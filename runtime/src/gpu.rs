//! Device setup and compute dispatch.

use std::sync::atomic::{AtomicU64, Ordering};

use wgpu::util::DeviceExt;

use nimbus_codegen::Generated;

use crate::error::RuntimeError;
use crate::pipelines::bind_group_layout;

/// What adapter ran the work, for the output of tests and benchmarks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuInfo {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    /// A CPU implementation (llvmpipe, lavapipe, WARP): pipelines get the tuning of
    /// [`nimbus_codegen::copy_uniforms_per_invocation`].
    pub cpu: bool,
}

impl std::fmt::Display for GpuInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ({}, {}, driver {})",
            self.name, self.backend, self.device_type, self.driver
        )
    }
}

/// How many buffers, textures and bind groups were created through a [`Gpu`]'s constructors
/// (the renderer creates all of its resources through them, so a steady-state frame that
/// allocates shows up here).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResourceCounts {
    pub buffers: u64,
    pub textures: u64,
    pub bind_groups: u64,
}

/// A hardware adapter of `instance` if there is one, else a software (fallback) one.
async fn any_adapter(instance: &wgpu::Instance) -> Option<wgpu::Adapter> {
    for (power_preference, force_fallback_adapter) in [
        (wgpu::PowerPreference::HighPerformance, false),
        (wgpu::PowerPreference::None, true),
    ] {
        let found = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference,
                force_fallback_adapter,
                compatible_surface: None,
                ..Default::default()
            })
            .await;
        if let Ok(a) = found {
            return Some(a);
        }
    }
    None
}

/// A device and queue.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: GpuInfo,
    created: [AtomicU64; 3],
}

impl Gpu {
    /// Opens any available adapter: a real GPU first, then software (lavapipe, llvmpipe).
    pub fn new() -> Result<Gpu, RuntimeError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Gpu, RuntimeError> {
        // Vulkan alone first, GL only where Vulkan has no adapter: GL's EGL probes the display
        // servers (Wayland, X11), which on a machine without a desktop session print errors of
        // their own ("XDG_RUNTIME_DIR is invalid") on every run.
        let choices = if std::env::var_os("WGPU_BACKEND").is_some() {
            vec![None]
        } else {
            vec![Some(wgpu::Backends::VULKAN), Some(wgpu::Backends::GL)]
        };
        let mut adapter = None;
        for backends in choices {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            if let Some(b) = backends {
                desc.backends = b;
            }
            adapter = any_adapter(&wgpu::Instance::new(desc)).await;
            if adapter.is_some() {
                break;
            }
        }
        let adapter = adapter.ok_or(RuntimeError::NoAdapter)?;
        let ai = adapter.get_info();
        let info = GpuInfo {
            name: ai.name.clone(),
            backend: format!("{:?}", ai.backend),
            device_type: format!("{:?}", ai.device_type),
            cpu: ai.device_type == wgpu::DeviceType::Cpu,
            driver: format!("{} {}", ai.driver, ai.driver_info)
                .trim()
                .to_string(),
        };
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("nimbus"),
                // Timestamps let benchmarks time the passes themselves where the adapter can;
                // filterable 32-bit float textures hold the temporal history exactly.
                required_features: adapter.features()
                    & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::FLOAT32_FILTERABLE),
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| RuntimeError::Device {
                adapter: info.to_string(),
                reason: e.to_string(),
            })?;
        Ok(Gpu {
            device,
            queue,
            info,
            created: Default::default(),
        })
    }

    /// Resources created so far through [`Self::create_buffer`], [`Self::create_texture`] and
    /// [`Self::create_bind_group`].
    pub fn resource_counts(&self) -> ResourceCounts {
        let n = |i: usize| self.created[i].load(Ordering::Relaxed);
        ResourceCounts {
            buffers: n(0),
            textures: n(1),
            bind_groups: n(2),
        }
    }

    /// `device.create_buffer`, counted.
    pub fn create_buffer(&self, desc: &wgpu::BufferDescriptor<'_>) -> wgpu::Buffer {
        self.created[0].fetch_add(1, Ordering::Relaxed);
        self.device.create_buffer(desc)
    }

    /// `device.create_texture`, counted.
    pub fn create_texture(&self, desc: &wgpu::TextureDescriptor<'_>) -> wgpu::Texture {
        self.created[1].fetch_add(1, Ordering::Relaxed);
        self.device.create_texture(desc)
    }

    /// `device.create_bind_group`, counted.
    pub fn create_bind_group(&self, desc: &wgpu::BindGroupDescriptor<'_>) -> wgpu::BindGroup {
        self.created[2].fetch_add(1, Ordering::Relaxed);
        self.device.create_bind_group(desc)
    }

    pub fn info(&self) -> &GpuInfo {
        &self.info
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The format of the temporal history: 32-bit float where the device can filter it, else
    /// the 16-bit HDR format. A running mean over many frames in half floats drifts (drivers may
    /// round towards zero when a shader writes them: 48 accumulated frames came out 0.8 % dark
    /// on lavapipe), so the history keeps full precision wherever it can.
    pub fn accumulation_format(&self) -> wgpu::TextureFormat {
        if self
            .device
            .features()
            .contains(wgpu::Features::FLOAT32_FILTERABLE)
        {
            wgpu::TextureFormat::Rgba32Float
        } else {
            crate::pipelines::HDR_FORMAT
        }
    }

    /// A compute pipeline for entry point `entry` of a generated module, with the explicit
    /// layout of codegen's binding description; wgpu's validation errors come back as
    /// [`RuntimeError::Pipeline`].
    pub(crate) fn compute_pipeline(
        &self,
        generated: &Generated,
        entry: &str,
    ) -> Result<(wgpu::ComputePipeline, wgpu::BindGroupLayout), RuntimeError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let layout = bind_group_layout(&self.device, entry, &generated.bindings)?;
        let pipeline_layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(generated.naga.clone())),
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: format!("compute pipeline `{entry}`"),
                reason: e.to_string(),
            });
        }
        Ok((pipeline, layout))
    }

    /// Maps a `MAP_READ` buffer (after the submitted work that fills it), copies its bytes out
    /// and unmaps it.
    pub fn map_read(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RuntimeError> {
        self.map_read_prefix(buffer, buffer.size())
    }

    /// [`Self::map_read`] of the first `len` bytes only (a buffer kept larger than this use).
    pub fn map_read_prefix(
        &self,
        buffer: &wgpu::Buffer,
        len: u64,
    ) -> Result<Vec<u8>, RuntimeError> {
        let len = len.min(buffer.size());
        let (tx, rx) = std::sync::mpsc::channel();
        buffer
            .slice(..len)
            .map_async(wgpu::MapMode::Read, move |r| {
                let _ = tx.send(r);
            });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RuntimeError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| RuntimeError::Readback(e.to_string()))?
            .map_err(|e| RuntimeError::Readback(e.to_string()))?;
        let data = buffer
            .slice(..len)
            .get_mapped_range()
            .map_err(|e| RuntimeError::Readback(e.to_string()))?;
        let bytes = data.to_vec();
        drop(data);
        buffer.unmap();
        Ok(bytes)
    }

    /// A sampler with one address mode on every axis and one filter for both magnification
    /// and minification (the textures have one mip level).
    pub fn sampler(
        &self,
        label: &str,
        address: wgpu::AddressMode,
        filter: wgpu::FilterMode,
    ) -> wgpu::Sampler {
        self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some(label),
            address_mode_u: address,
            address_mode_v: address,
            address_mode_w: address,
            mag_filter: filter,
            min_filter: filter,
            ..Default::default()
        })
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Runs compute entry point `entry` of `wgsl` over `input` (bound read-only at binding
    /// `input_binding` of group 0) and returns `output_words` words of the read-write buffer at
    /// the next binding. `groups` workgroups are dispatched. `resources` are bound at their
    /// binding numbers.
    #[expect(clippy::too_many_arguments, reason = "one dispatch, described in full")]
    pub fn run_compute(
        &self,
        generated: &Generated,
        entry: &str,
        input_binding: u32,
        input: &[u32],
        output_words: usize,
        groups: u32,
        resources: &[(u32, GpuResource)],
    ) -> Result<Vec<u32>, RuntimeError> {
        let device = &self.device;
        let (pipeline, layout) = self.compute_pipeline(generated, entry)?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        // Storage buffers cannot be empty.
        let input_bytes: &[u8] = if input.is_empty() {
            &[0; 4]
        } else {
            bytemuck::cast_slice(input)
        };
        let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parity input"),
            contents: input_bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (output_words.max(1) * 4) as u64;
        let output_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parity output"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let views: Vec<(u32, GpuBinding)> = resources
            .iter()
            .filter(|(b, _)| {
                generated
                    .bindings
                    .iter()
                    .any(|g| g.group == 0 && g.binding == *b)
            })
            .map(|(b, r)| (*b, self.upload(r)))
            .collect();
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: input_binding,
                resource: input_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: input_binding + 1,
                resource: output_buf.as_entire_binding(),
            },
        ];
        for (binding, v) in &views {
            entries.push(wgpu::BindGroupEntry {
                binding: *binding,
                resource: match v {
                    GpuBinding::View(view) => wgpu::BindingResource::TextureView(view),
                    GpuBinding::Sampler(s) => wgpu::BindingResource::Sampler(s),
                },
            });
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &entries,
        });
        let data = self.dispatch_and_read(&pipeline, &bind_group, groups, &output_buf)?;
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: format!("dispatch of `{entry}`"),
                reason: e.to_string(),
            });
        }
        let words: Vec<u32> = bytemuck::cast_slice(&data)[..output_words].to_vec();
        Ok(words)
    }
}

impl Gpu {
    /// Dispatches `groups` workgroups of `pipeline` with `bind_group` at group 0, waits, and
    /// returns the bytes of `output` (which needs `COPY_SRC`).
    fn dispatch_and_read(
        &self,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        groups: u32,
        output: &wgpu::Buffer,
    ) -> Result<Vec<u8>, RuntimeError> {
        let size = output.size();
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compute readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
        encoder.copy_buffer_to_buffer(output, 0, &readback, 0, size);
        self.queue.submit([encoder.finish()]);
        self.map_read(&readback)
    }

    /// Dispatches one workgroup of compute entry point `entry` that reads the uniform block
    /// `uniform` at binding `uniform_binding` of group 0 and writes the storage buffer at
    /// `output_binding` (`output_bytes` long, zeroed first); returns what it wrote. How an
    /// engine runs a kernel that completes a uniform block (the `sun_light` pass).
    pub fn run_uniform_kernel(
        &self,
        generated: &Generated,
        entry: &str,
        (uniform_binding, uniform): (u32, &[u8]),
        (output_binding, output_bytes): (u32, usize),
    ) -> Result<Vec<u8>, RuntimeError> {
        let device = &self.device;
        let (pipeline, layout) = self.compute_pipeline(generated, entry)?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let uniform_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("kernel uniform"),
            contents: uniform,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let size = output_bytes.max(4).next_multiple_of(4) as u64;
        let output_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel output"),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: uniform_binding,
                    resource: uniform_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: output_binding,
                    resource: output_buf.as_entire_binding(),
                },
            ],
        });
        let mut data = self.dispatch_and_read(&pipeline, &bind_group, 1, &output_buf)?;
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: format!("dispatch of `{entry}`"),
                reason: e.to_string(),
            });
        }
        data.truncate(output_bytes);
        Ok(data)
    }
}

/// A texture or sampler for a compute dispatch. Texel values travel as f16 (`Rgba16Float`, the
/// filterable float format every adapter has); callers choose values f16 represents exactly so
/// the CPU twin sees the same texels.
#[derive(Clone, Debug)]
pub enum GpuResource {
    Texture2d(nimbus_dsl::cpu::Texture2d),
    Texture3d(nimbus_dsl::cpu::Texture3d),
    Sampler(nimbus_dsl::cpu::Sampler),
}

enum GpuBinding {
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

/// f32 to f16 bits by IEEE rules (`half`): round to nearest even, −0 and NaN kept, overflow to
/// infinity, so a texel the GPU reads is the f16 nearest the CPU twin's value.
pub(crate) fn f16_bits(v: f32) -> u16 {
    half::f16::from_f32(v).to_bits()
}

impl Gpu {
    fn upload(&self, r: &GpuResource) -> GpuBinding {
        let (size, dimension, texels) = match r {
            GpuResource::Texture2d(t) => (
                wgpu::Extent3d {
                    width: t.size[0],
                    height: t.size[1],
                    depth_or_array_layers: 1,
                },
                wgpu::TextureDimension::D2,
                &t.texels,
            ),
            GpuResource::Texture3d(t) => (
                wgpu::Extent3d {
                    width: t.size[0],
                    height: t.size[1],
                    depth_or_array_layers: t.size[2],
                },
                wgpu::TextureDimension::D3,
                &t.texels,
            ),
            GpuResource::Sampler(s) => {
                let address = match s.address {
                    nimbus_dsl::cpu::AddressMode::Repeat => wgpu::AddressMode::Repeat,
                    nimbus_dsl::cpu::AddressMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
                };
                let filter = match s.filter {
                    nimbus_dsl::cpu::Filter::Linear => wgpu::FilterMode::Linear,
                    nimbus_dsl::cpu::Filter::Nearest => wgpu::FilterMode::Nearest,
                };
                return GpuBinding::Sampler(self.sampler("parity sampler", address, filter));
            }
        };
        let data: Vec<u16> = texels
            .iter()
            .flat_map(|t| t.to_array().map(f16_bits))
            .collect();
        let texture = self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: Some("parity texture"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&data),
        );
        GpuBinding::View(texture.create_view(&Default::default()))
    }
}

#[cfg(test)]
mod tests {
    use super::f16_bits;

    /// The IEEE cases a hand-written truncating conversion got wrong.
    #[test]
    fn f16_bits_follow_ieee_rounding() {
        assert_eq!(f16_bits(-0.0), 0x8000, "−0 stays −0");
        assert_eq!(f16_bits(0.0), 0x0000);
        let nan = f16_bits(f32::NAN);
        assert!(
            nan & 0x7c00 == 0x7c00 && nan & 0x03ff != 0,
            "NaN stays NaN, got {nan:#06x}"
        );
        // 65520 is halfway between f16::MAX (65504) and the next step (65536): ties to even
        // round up, out of range, so infinity.
        assert_eq!(f16_bits(65520.0), 0x7c00);
        assert_eq!(f16_bits(-65520.0), 0xfc00);
        assert_eq!(f16_bits(65504.0), 0x7bff, "f16::MAX is exact");
        // f16 has 10 mantissa bits: near 1.0 its step is 2^-10. 1 + 2^-11 is a tie between
        // 1.0 (even) and 1 + 2^-10, so 1.0; 1 + 3·2^-11 is a tie between 1 + 2^-10 (odd) and
        // 1 + 2^-9 (even), so 1 + 2^-9.
        let step = 2f32.powi(-11);
        assert_eq!(f16_bits(1.0 + step), 0x3c00);
        assert_eq!(f16_bits(1.0 + 3.0 * step), 0x3c02);
        // Just above half a step rounds up, where truncation would keep 1.0.
        assert_eq!(f16_bits(1.0 + step * 1.5), 0x3c01);
        assert_eq!(f16_bits(0.5), 0x3800, "representable values are exact");
    }
}
