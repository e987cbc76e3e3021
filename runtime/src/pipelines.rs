//! The pipeline cache: one render pipeline per pass and variant key, created from codegen's
//! WGSL the first time it is needed and reused after. The key holds what changes the code
//! (toggles, octaves, phase kind, layer groups), not the numbers: two genera or two presets
//! with the same key share a pipeline, since their differences are uniforms.

use std::collections::HashMap;

use nimbus_codegen::{Target, generate};
use nimbus_dsl::DslError;
use nimbus_dsl::ir::Module;
use nimbus_dsl::model::march::MarchKey;

use crate::error::RuntimeError;
use crate::gpu::Gpu;

/// The passes a frame can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Pass {
    /// Beer shadow map atlas.
    Shadow,
    /// The cloud march, composited over sky and ground.
    Clouds,
    /// Temporal upscaling / accumulation.
    Resolve,
}

impl Pass {
    pub fn name(self) -> &'static str {
        match self {
            Pass::Shadow => "shadow",
            Pass::Clouds => "clouds",
            Pass::Resolve => "resolve",
        }
    }

    fn entry(self) -> &'static str {
        match self {
            Pass::Shadow => "fs_shadow",
            Pass::Clouds => "fs_main",
            Pass::Resolve => "fs_resolve",
        }
    }
}

/// What a pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    pub pass: Pass,
    /// The march key (none for the resolve pass, which is the same for every variant).
    pub key: Option<MarchKey>,
}

impl std::fmt::Display for PipelineKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.key {
            None => write!(f, "{}", self.pass.name()),
            Some(k) => write!(
                f,
                "{}[{:?} {} groups, {:?}]",
                self.pass.name(),
                k.phase,
                k.groups,
                k.features
            ),
        }
    }
}

/// A pipeline and the bindings its shader declares (name, binding index).
pub struct CachedPipeline {
    pub pipeline: wgpu::RenderPipeline,
    pub bindings: Vec<(String, u32)>,
}

impl CachedPipeline {
    pub fn binds(&self, name: &str) -> bool {
        self.bindings.iter().any(|(n, _)| n == name)
    }
}

/// Pipelines by key, and the order they were built in.
#[derive(Default)]
pub struct PipelineCache {
    map: HashMap<PipelineKey, CachedPipeline>,
    built: Vec<PipelineKey>,
}

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

impl PipelineCache {
    /// Keys built so far, in order.
    pub fn built(&self) -> &[PipelineKey] {
        &self.built
    }

    /// A pipeline built earlier.
    pub fn get(&self, key: &PipelineKey) -> Result<&CachedPipeline, RuntimeError> {
        self.map
            .get(key)
            .ok_or_else(|| RuntimeError::Kernel(format!("pipeline `{key}` was not built")))
    }

    /// The pipeline for `key`, recording and compiling `module` on a miss.
    pub fn get_or_build(
        &mut self,
        gpu: &Gpu,
        key: PipelineKey,
        module: impl FnOnce() -> Result<Module, DslError>,
    ) -> Result<&CachedPipeline, RuntimeError> {
        if let std::collections::hash_map::Entry::Vacant(slot) = self.map.entry(key) {
            let label = key.to_string();
            let generated = generate(module()?, &label, &[Target::Wgsl])?;
            let bindings = generated
                .ir
                .globals
                .iter()
                .filter_map(|g| g.binding().map(|(_, b)| (g.name.clone(), b)))
                .collect();
            let device = gpu.device();
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&label),
                source: wgpu::ShaderSource::Wgsl(generated.wgsl.into()),
            });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&label),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(key.pass.entry()),
                    compilation_options: Default::default(),
                    targets: &[Some(HDR_FORMAT.into())],
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
            slot.insert(CachedPipeline { pipeline, bindings });
            self.built.push(key);
        }
        self.map
            .get(&key)
            .ok_or_else(|| RuntimeError::Kernel("pipeline missing from the cache".into()))
    }
}
