//! The formation automaton on the GPU ([`nimbus_clouds::model::formation`]): the grid in two
//! ping-pong pairs of storage buffers, advanced one dispatch per step, and the weather texture
//! it gates at any time between steps.

use nimbus_clouds::formation::Formation;
use nimbus_clouds::model::formation::{
    FormationGrid, FormationParams, WORKGROUP, formation_step_module, formation_weather_module,
    slots,
};
use nimbus_codegen::{Generated, Target, generate};
use nimbus_dsl::layout::UniformBytes;
use wgpu::util::DeviceExt;

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::render::{Renderer, TextureSource};
use crate::textures::{GpuTexture, NoiseKind, padded_row};

/// The most steps one `weather_at` may have to compute: the time limit over the shortest step,
/// and the step after it (the weather between two steps reads both).
pub const MAX_STEPS: u32 = 100_001;

/// A compute kernel and its bind group layout.
struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl Kernel {
    fn new(gpu: &Gpu, generated: &Generated, entry: &str) -> Result<Kernel, RuntimeError> {
        let (pipeline, layout) = gpu.compute_pipeline(generated, entry)?;
        Ok(Kernel { pipeline, layout })
    }
}

/// The automaton of one scene, on the GPU.
pub struct FormationSim<'g> {
    gpu: &'g Gpu,
    settings: Formation,
    cells: u32,
    weather_size: u32,
    /// Steps taken: `states[latest]` holds this step, `states[1 - latest]` the one before.
    step: u32,
    latest: usize,
    states: [wgpu::Buffer; 2],
    density: [wgpu::Buffer; 2],
    supply: wgpu::Buffer,
    params: wgpu::Buffer,
    base: wgpu::Buffer,
    texels: wgpu::Buffer,
    step_kernel: Kernel,
    weather_kernel: Kernel,
    /// The bind groups of a step from pair `i` to pair `1 - i`.
    step_groups: [wgpu::BindGroup; 2],
}

fn storage(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
        })
}

impl<'g> FormationSim<'g> {
    /// A clear sky over the procedural weather map of `weather_size` texels per side (the
    /// renderer's [`crate::render::TextureSizes::weather`]), at step 0.
    pub fn new(
        gpu: &'g Gpu,
        settings: Formation,
        weather_size: u32,
    ) -> Result<FormationSim<'g>, RuntimeError> {
        let cells = settings.cells;
        if !cells.is_multiple_of(8) || !nimbus_clouds::model::formation::CELLS.contains(&cells) {
            return Err(RuntimeError::Limit(format!(
                "formation.cells = {cells}: a multiple of 8 from 8 to 1024"
            )));
        }
        let grid = FormationGrid::new(cells, settings.humidity);
        let zeros = vec![0u8; grid.states.len() * 4];
        let states = [
            storage(gpu, "states 0", &zeros),
            storage(gpu, "states 1", &zeros),
        ];
        let density = [
            storage(gpu, "density 0", &zeros),
            storage(gpu, "density 1", &zeros),
        ];
        let supply = storage(gpu, "supply", bytemuck::cast_slice(&grid.supply));
        let params_bytes = settings.params().to_uniform_bytes()?;
        let params = gpu
            .device()
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("formation params"),
                contents: &params_bytes,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
        let base = gpu.noise_buffer(NoiseKind::Weather, weather_size)?;
        let row = padded_row(weather_size);
        let texels = storage(
            gpu,
            "formation texels",
            &vec![0u8; (row * weather_size * 4) as usize],
        );
        let step_kernel = Kernel::new(
            gpu,
            &generate(formation_step_module(cells)?, "default", &[Target::Wgsl])?,
            "cs_formation_step",
        )?;
        let weather_kernel = Kernel::new(
            gpu,
            &generate(
                formation_weather_module(cells, weather_size, row)?,
                "default",
                &[Target::Wgsl],
            )?,
            "cs_formation_weather",
        )?;
        let step_group = |from: usize| {
            let to = 1 - from;
            gpu.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("formation step"),
                layout: &step_kernel.layout,
                entries: &[
                    entry(slots::PARAMS, &params),
                    entry(slots::STATES_IN, &states[from]),
                    entry(slots::DENSITY_IN, &density[from]),
                    entry(slots::STATES_OUT, &states[to]),
                    entry(slots::DENSITY_OUT, &density[to]),
                    entry(slots::SUPPLY, &supply),
                ],
            })
        };
        let step_groups = [step_group(0), step_group(1)];
        Ok(FormationSim {
            gpu,
            settings,
            cells,
            weather_size,
            step: 0,
            latest: 0,
            states,
            density,
            supply,
            params,
            base,
            texels,
            step_kernel,
            weather_kernel,
            step_groups,
        })
    }

    /// Steps taken.
    pub fn step(&self) -> u32 {
        self.step
    }

    /// Back to the clear sky of step 0.
    pub fn reset(&mut self) {
        let zeros = vec![0u8; (self.cells * self.cells * 4) as usize];
        for b in self.states.iter().chain(&self.density) {
            self.gpu.queue().write_buffer(b, 0, &zeros);
        }
        self.step = 0;
        self.latest = 0;
    }

    /// Advances the grid to step `target` (from step 0 again when it is behind).
    pub fn advance_to(&mut self, target: u32) -> Result<(), RuntimeError> {
        if target > MAX_STEPS {
            return Err(RuntimeError::Limit(format!(
                "the formation automaton would need {target} steps (at most {MAX_STEPS}): \
                 lengthen formation.step_seconds"
            )));
        }
        if target < self.step {
            self.reset();
        }
        let groups = (self.cells * self.cells).div_ceil(WORKGROUP);
        let scope = self
            .gpu
            .device()
            .push_error_scope(wgpu::ErrorFilter::Validation);
        while self.step < target {
            // The step index salts the random draws: one submit per step, after its write.
            let params = FormationParams {
                step: self.step,
                ..self.settings.params()
            };
            self.gpu
                .queue()
                .write_buffer(&self.params, 0, &params.to_uniform_bytes()?);
            let mut encoder = self
                .gpu
                .device()
                .create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.step_kernel.pipeline);
                pass.set_bind_group(0, &self.step_groups[self.latest], &[]);
                pass.dispatch_workgroups(groups, 1, 1);
            }
            self.gpu.queue().submit([encoder.finish()]);
            self.latest = 1 - self.latest;
            self.step += 1;
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: "the formation step kernel".into(),
                reason: e.to_string(),
            });
        }
        Ok(())
    }

    /// The grid's states and densities now, read back (for tests against [`FormationGrid`]).
    pub fn read(&self) -> Result<FormationGrid, RuntimeError> {
        let n = (self.cells * self.cells) as usize;
        let states = self.gpu.read_buffer(&self.states[self.latest], n)?;
        let density = self
            .gpu
            .read_buffer(&self.density[self.latest], n)?
            .into_iter()
            .map(f32::from_bits)
            .collect();
        let supply = self.gpu.read_buffer(&self.supply, n)?;
        Ok(FormationGrid {
            cells: self.cells,
            step: self.step,
            states,
            density,
            supply,
        })
    }

    /// The weather texture at `seconds` into the timeline: the procedural weather gated by the
    /// automaton's density, interpolated between the steps either side of that time.
    pub fn weather_at(&mut self, seconds: f64) -> Result<GpuTexture, RuntimeError> {
        let (step, blend) = self.settings.step_at(seconds);
        // Pair `1 - latest` must hold `step`, pair `latest` the step after.
        self.advance_to(step.saturating_add(1))?;
        let params = FormationParams {
            step,
            blend,
            ..self.settings.params()
        };
        self.gpu
            .queue()
            .write_buffer(&self.params, 0, &params.to_uniform_bytes()?);
        let group = self.gpu.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("formation weather"),
            layout: &self.weather_kernel.layout,
            entries: &[
                entry(slots::PARAMS, &self.params),
                entry(slots::NOW, &self.density[1 - self.latest]),
                entry(slots::NEXT, &self.density[self.latest]),
                entry(slots::BASE, &self.base),
                entry(slots::TEXELS, &self.texels),
            ],
        });
        let scope = self
            .gpu
            .device()
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.weather_kernel.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(
                (self.weather_size * self.weather_size).div_ceil(WORKGROUP),
                1,
                1,
            );
        }
        self.gpu.queue().submit([encoder.finish()]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RuntimeError::Pipeline {
                what: "the formation weather kernel".into(),
                reason: e.to_string(),
            });
        }
        self.gpu
            .texture_from_texels(NoiseKind::Weather, &self.texels, self.weather_size)
    }
}

impl FormationSim<'_> {
    /// Gives `renderer` the weather of `seconds` into the timeline (the shadow atlas is
    /// redrawn through it on the next frame).
    pub fn apply(&mut self, renderer: &mut Renderer<'_>, seconds: f64) -> Result<(), RuntimeError> {
        let texture = self.weather_at(seconds)?;
        renderer.set_texture(NoiseKind::Weather, TextureSource::User(texture));
        Ok(())
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
