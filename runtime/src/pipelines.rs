//! The pipeline cache: one render pipeline per shader key, created from codegen's naga module
//! the first time it is needed and reused after. The key holds what changes the code (toggles,
//! octaves, phase kind, layer groups), not the numbers: two genera or two presets with the same
//! key share a pipeline, since their differences are uniforms.
//!
//! Each pipeline has an explicit bind-group layout built from codegen's binding description
//! (slot, kind, texture dimension, sampler, visibility): nothing is inferred from the WGSL.

use std::collections::HashMap;

use nimbus_clouds::catalog::ShaderKey;
use nimbus_codegen::{
    BindingInfo, BindingKind, Target, TextureDimension, copy_uniforms_per_invocation,
    flatten_uniform_blocks, generate,
};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::ir::Stage;

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::shader_input::ShaderInput;

/// A pipeline, its layout, and the bindings its shader keeps.
pub struct CachedPipeline {
    pub pipeline: wgpu::RenderPipeline,
    pub layout: wgpu::BindGroupLayout,
    pub bindings: Vec<BindingInfo>,
}

/// Pipelines by key, and the order they were built in.
#[derive(Default)]
pub struct PipelineCache {
    map: HashMap<ShaderKey, CachedPipeline>,
    built: Vec<ShaderKey>,
    /// Pipelines being built on threads of their own ([`Self::request`]).
    pending: HashMap<ShaderKey, std::thread::JoinHandle<Result<CachedPipeline, RuntimeError>>>,
    /// Bind uniform blocks as `vec4` word arrays, as engine packages for three.js do
    /// ([`flatten_uniform_blocks`]); the bytes written are the same.
    flat_uniforms: bool,
    /// What shader modules are created from.
    input: ShaderInput,
}

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

fn stages(b: &BindingInfo) -> wgpu::ShaderStages {
    let mut s = wgpu::ShaderStages::NONE;
    for stage in &b.visibility {
        s |= match stage {
            Stage::Vertex => wgpu::ShaderStages::VERTEX,
            Stage::Fragment => wgpu::ShaderStages::FRAGMENT,
            Stage::Compute => wgpu::ShaderStages::COMPUTE,
        };
    }
    s
}

/// The explicit bind-group layout of group 0 of a generated module, from codegen's binding
/// description.
pub(crate) fn bind_group_layout(
    device: &wgpu::Device,
    label: &str,
    bindings: &[BindingInfo],
) -> Result<wgpu::BindGroupLayout, RuntimeError> {
    if bindings.iter().any(|b| b.group != 0) {
        return Err(RuntimeError::Kernel(format!(
            "`{label}` uses a bind group other than 0; the runtime binds group 0 only"
        )));
    }
    let entries: Vec<_> = bindings.iter().map(layout_entry).collect();
    Ok(
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        }),
    )
}

/// The layout entry of one described binding.
fn layout_entry(b: &BindingInfo) -> wgpu::BindGroupLayoutEntry {
    let ty = match &b.kind {
        BindingKind::Uniform { size, .. } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(u64::from(*size)),
        },
        BindingKind::Storage { read_write } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage {
                read_only: !read_write,
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        BindingKind::Texture {
            dimension,
            filterable,
        } => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float {
                filterable: *filterable,
            },
            view_dimension: match dimension {
                TextureDimension::D2 => wgpu::TextureViewDimension::D2,
                TextureDimension::D3 => wgpu::TextureViewDimension::D3,
            },
            multisampled: false,
        },
        BindingKind::Sampler(_) => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
    };
    wgpu::BindGroupLayoutEntry {
        binding: b.binding,
        visibility: stages(b),
        ty,
        count: None,
    }
}

impl PipelineCache {
    /// Builds every later pipeline with flattened uniform blocks (or not); pipelines built the
    /// other way are dropped.
    pub fn set_flat_uniforms(&mut self, on: bool) {
        if self.flat_uniforms != on {
            self.flat_uniforms = on;
            self.map.clear();
            self.built.clear();
        }
    }

    /// Builds every later pipeline from `input`; pipelines built from the other are dropped.
    pub fn set_shader_input(&mut self, input: ShaderInput) {
        if self.input != input {
            self.input = input;
            self.map.clear();
            self.built.clear();
        }
    }

    /// Keys built so far, in order.
    pub fn built(&self) -> &[ShaderKey] {
        &self.built
    }

    /// A pipeline built earlier.
    pub fn get(&self, key: &ShaderKey) -> Result<&CachedPipeline, RuntimeError> {
        self.map
            .get(key)
            .ok_or_else(|| RuntimeError::Kernel(format!("pipeline `{}` was not built", key.id())))
    }

    /// The pipeline for `key`: built earlier, finished by a background build (waited for),
    /// or recorded and compiled now.
    pub fn get_or_build(
        &mut self,
        gpu: &Gpu,
        key: ShaderKey,
    ) -> Result<&CachedPipeline, RuntimeError> {
        if !self.map.contains_key(&key) {
            let built = match self.pending.remove(&key) {
                Some(handle) => handle.join().map_err(|_| {
                    RuntimeError::Kernel(format!("the background build of `{}` panicked", key.id()))
                })??,
                None => build(&BuildTarget::of(gpu, self.flat_uniforms, self.input), key)?,
            };
            self.map.insert(key, built);
            self.built.push(key);
        }
        self.get(&key)
    }

    /// Starts building `key`'s pipeline on a thread of its own, unless it is built or being
    /// built: recording, generating and the driver's compile all happen off the caller's
    /// thread, and [`Self::ready`] says when it can be drawn with.
    pub fn request(&mut self, gpu: &Gpu, key: ShaderKey) {
        if self.map.contains_key(&key) || self.pending.contains_key(&key) {
            return;
        }
        let target = BuildTarget::of(gpu, self.flat_uniforms, self.input);
        let handle = std::thread::spawn(move || build(&target, key));
        self.pending.insert(key, handle);
    }

    /// Whether `key`'s pipeline can be drawn with now: built, or its background build has
    /// finished (its result, or its error, is taken then). Never waits.
    pub fn ready(&mut self, gpu: &Gpu, key: ShaderKey) -> Result<bool, RuntimeError> {
        if self.map.contains_key(&key) {
            return Ok(true);
        }
        if self.pending.get(&key).is_some_and(|h| h.is_finished()) {
            self.get_or_build(gpu, key)?;
            return Ok(true);
        }
        Ok(false)
    }
}

/// What a pipeline build needs of the GPU, owned, so a build can run on another thread.
struct BuildTarget {
    device: wgpu::Device,
    cpu: bool,
    accumulation: wgpu::TextureFormat,
    flat_uniforms: bool,
    input: ShaderInput,
}

impl BuildTarget {
    fn of(gpu: &Gpu, flat_uniforms: bool, input: ShaderInput) -> Self {
        BuildTarget {
            device: gpu.device().clone(),
            cpu: gpu.info().cpu,
            accumulation: gpu.accumulation_format(),
            flat_uniforms,
            input,
        }
    }
}

/// Records `key`'s module, generates it and compiles its render pipeline.
fn build(target: &BuildTarget, key: ShaderKey) -> Result<CachedPipeline, RuntimeError> {
    let label = key.id();
    let mut module = key.record()?;
    if target.flat_uniforms {
        flatten_uniform_blocks(&mut module);
    }
    if target.cpu {
        // CPU drivers re-load uniforms at every read inside loops; a per-invocation copy
        // made the cloud pass 30 % faster on llvmpipe (see the pass's docs).
        copy_uniforms_per_invocation(&mut module);
    }
    let mut generated = generate(module, &key.variant(), &[Target::Wgsl])?;
    let entry_of = |stage: Stage| {
        generated
            .ir
            .entry_points
            .iter()
            .find(|e| e.stage == stage)
            .map(|e| e.function.clone())
            .ok_or_else(|| RuntimeError::Kernel(format!("`{label}` has no {stage:?} entry point")))
    };
    let (vs, fs) = (entry_of(Stage::Vertex)?, entry_of(Stage::Fragment)?);
    let device = &target.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let layout = bind_group_layout(device, &label, &generated.bindings)?;
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&label),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&label),
        source: target.input.source(&mut generated),
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(&label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &shader,
            entry_point: Some(&vs),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &shader,
            entry_point: Some(&fs),
            compilation_options: Default::default(),
            // The resolve writes the history, which keeps full precision where it can.
            targets: &[Some(
                match key {
                    ShaderKey::Resolve => target.accumulation,
                    _ => HDR_FORMAT,
                }
                .into(),
            )],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(RuntimeError::Pipeline {
            what: format!("render pipeline `{label}`"),
            reason: e.to_string(),
        });
    }
    Ok(CachedPipeline {
        pipeline,
        layout,
        bindings: generated.bindings,
    })
}
