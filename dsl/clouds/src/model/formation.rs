//! Cloud formation and dissipation: the cellular automaton of Dobashi et al. 2000 ("A Simple,
//! Efficient Method for Realistic Animation of Clouds"), on a 2D grid that tiles the weather
//! texture, as compute kernels recorded from the `#[shader_fn]`s below (whose CPU twins run the
//! same grid in [`FormationGrid`]).
//!
//! Each cell holds three bits: vapour (`hum`), a phase transition under way (`act`) and cloud
//! (`cld`). Per step, an activated cell turns its vapour into cloud, activation spreads to humid
//! neighbours (so cloud grows through moist air as a front), cloud dissipates with probability
//! `extinction`, vapour returns with probability `humidity`, and activation starts by itself
//! with probability `activation`. Where clouds form is thus a forest-fire process: clusters of
//! every size, growing and dying away.
//!
//! The bits become a continuous field the renderer can use: the share of cloudy cells around a
//! cell (5×5), relaxed over time (`relax` per step), interpolated between steps and across cells.
//! That field gates the weather texture's low and mid cloud signals, so the clouds the genus
//! draws appear, grow and dissolve where the automaton says. (Through the coverage remap, the
//! weather decides where clouds are only while the coverage is below the layer's filter width's
//! complement, about 0.4 for cumulus: a denser sky is cloud wherever the shape noise allows.)
//!
//! Randomness is an integer hash of (cell, step, seed) compared against integer thresholds, so
//! the CPU and GPU automata agree bit for bit; only the relaxed density is a float.

use nimbus_dsl::ir::Module;
use nimbus_dsl::prelude::*;
use nimbus_dsl::shader::{self, F32, U32};
use nimbus_dsl::{DslError, ModuleBuilder, loc};

use super::noise::hash3;

/// Bit of a cell's state: vapour.
pub const HUM: u32 = 1;
/// Bit of a cell's state: a phase transition under way.
pub const ACT: u32 = 2;
/// Bit of a cell's state: cloud.
pub const CLD: u32 = 4;

/// The cells whose activation spreads to a cell: Dobashi's neighbourhood (the four adjacent
/// cells and the two beyond along each axis, so fronts grow faster along the grid than across),
/// in two dimensions.
pub const NEIGHBOURS: [(i32, i32); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (2, 0),
    (-2, 0),
    (0, 2),
    (0, -2),
];

/// The cells whose cloud is averaged into a cell's density: the 5×5 block around it (a cell's
/// own cloud flickers as each cell dissipates at random; the block's share is what a cloud is).
pub const SMOOTHING: [(i32, i32); 25] = [
    (-2, -2),
    (-1, -2),
    (0, -2),
    (1, -2),
    (2, -2),
    (-2, -1),
    (-1, -1),
    (0, -1),
    (1, -1),
    (2, -1),
    (-2, 0),
    (-1, 0),
    (0, 0),
    (1, 0),
    (2, 0),
    (-2, 1),
    (-1, 1),
    (0, 1),
    (1, 1),
    (2, 1),
    (-2, 2),
    (-1, 2),
    (0, 2),
    (1, 2),
    (2, 2),
];

/// Salts of the three random draws per cell and step.
const SALT_EXTINCTION: u32 = 0x9E37_79B9;
const SALT_HUMIDITY: u32 = 0x7F4A_7C15;
const SALT_ACTIVATION: u32 = 0x2545_F491;

/// The automaton's inputs for one step.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct FormationParams {
    /// The step being computed (from 0): salts the random draws.
    pub step: u32,
    pub seed: u32,
    /// Probabilities per step, as thresholds on a 32-bit hash (`p × 2³²`): activation starts by
    /// itself, cloud dissipates. (Vapour's return is per cell: [`FormationGrid::supply`].)
    pub activation: u32,
    pub extinction: u32,
    /// How far a cell's density moves towards its neighbourhood's cloud share per step (0–1].
    pub relax: f32,
    /// Densities mapped to no cloud and to full weather by the gate ([`formation_gate`]).
    pub gate_low: f32,
    pub gate_high: f32,
    /// Fraction of the way from the state of step `step` to the next, for the weather kernel.
    pub blend: f32,
}

/// A probability as the threshold a 32-bit hash falls under with that probability.
pub fn threshold(p: f32) -> u32 {
    (f64::from(p.clamp(0.0, 1.0)) * 4_294_967_295.0).round() as u32
}

/// 1 when `bits` has `bit` set, else 0.
#[shader_fn]
pub fn has(bits: u32, bit: u32) -> u32 {
    select(0u32, 1u32, (bits & bit) != 0u32)
}

/// 1 when the hash of (`cell`, `step`, `seed ^ salt`) falls under `threshold`.
#[shader_fn]
pub fn chance(cell: u32, step: u32, seed: u32, threshold: u32) -> u32 {
    select(0u32, 1u32, hash3(cell, step, seed) < threshold)
}

/// One cell's next state: `state` its own, `neighbours` the OR of its [`NEIGHBOURS`]' states,
/// `cell` its index (for the random draws), `humidity` the threshold of its vapour supply (the
/// scene's humidity where the weather map is moist, less where it is dry: Dobashi's way of
/// saying where clouds may form).
#[shader_fn]
pub fn formation_cell(
    state: u32,
    neighbours: u32,
    cell: u32,
    humidity: u32,
    params: FormationParams,
) -> u32 {
    let hum = has(state, HUM);
    let act = has(state, ACT);
    let cld = has(state, CLD);
    let spread = has(neighbours, ACT);
    // Random draws: cloud dissipates, vapour returns, activation starts on its own.
    let keep = 1u32
        - chance(
            cell,
            params.step,
            params.seed ^ SALT_EXTINCTION,
            params.extinction,
        );
    let supplied = chance(cell, params.step, params.seed ^ SALT_HUMIDITY, humidity);
    let started = chance(
        cell,
        params.step,
        params.seed ^ SALT_ACTIVATION,
        params.activation,
    );
    // Growth (Dobashi's transition rules): activation consumes the vapour and leaves cloud; it
    // spreads to humid neighbours of an activated cell. Then extinction and supply.
    let next_hum = (hum & (1u32 - act)) | supplied;
    let next_cld = (cld | act) & keep;
    let next_act = ((1u32 - act) & hum & spread) | (next_hum & started);
    next_hum * HUM + next_act * ACT + next_cld * CLD
}

/// A cell's next density from its own and the number of cloudy cells among its [`SMOOTHING`]
/// block (25 cells): a convex step towards the block's cloud share, so it stays within [0, 1].
#[shader_fn]
pub fn formation_density(previous: f32, cloudy: u32, params: FormationParams) -> f32 {
    let share = (cloudy as f32) * (1.0 / 25.0);
    previous + (share - previous) * params.relax
}

/// How much of the weather the density lets through: none below `gate_low`, all above
/// `gate_high`, smooth between (a cloud's edge grows and shrinks rather than switching).
#[shader_fn]
pub fn formation_gate(density: f32, params: FormationParams) -> f32 {
    smoothstep(params.gate_low, params.gate_high, density)
}

/// The density at a point between four cells and two steps: `now` and `next` hold the four
/// cells' densities (x: the cell, y: +x, z: +y, w: +x+y) at step `step` and the next, `f` the
/// point's position between them.
#[shader_fn]
pub fn formation_sample(now: Vec4, next: Vec4, f: Vec2, params: FormationParams) -> f32 {
    let corners = now + (next - now) * params.blend;
    let bottom = corners.x + (corners.y - corners.x) * f.x;
    let top = corners.z + (corners.w - corners.z) * f.x;
    bottom + (top - bottom) * f.y
}

/// The weather texel `base` (RGBA8, as the weather kernel packs it) gated by the density: its
/// low (r) and mid (g) cloud signals, where convective clouds form; the high (b) and extra (a)
/// signals, which carry cirrus and the planet-scale weather, pass unchanged.
#[shader_fn]
pub fn formation_weather(base: u32, density: f32, params: FormationParams) -> u32 {
    let unpacked = vec4(
        (base & 255u32) as f32,
        ((base >> 8u32) & 255u32) as f32,
        ((base >> 16u32) & 255u32) as f32,
        (base >> 24u32) as f32,
    ) * (1.0 / 255.0);
    let gate = formation_gate(density, params);
    let gated = unpacked * vec4(gate, gate, 1.0, 1.0);
    pack4x8unorm(gated)
}

/// Index of the cell `offset` away from (`x`, `y`) on a `cells`-wide grid that wraps.
fn wrapped(x: u32, y: u32, offset: (i32, i32), cells: u32) -> u32 {
    let c = cells as i64;
    let nx = (i64::from(x) + i64::from(offset.0)).rem_euclid(c);
    let ny = (i64::from(y) + i64::from(offset.1)).rem_euclid(c);
    (nx + ny * c) as u32
}

/// Storage bindings of the step kernel (group 0).
pub mod slots {
    pub const PARAMS: u32 = 0;
    pub const STATES_IN: u32 = 1;
    pub const DENSITY_IN: u32 = 2;
    pub const STATES_OUT: u32 = 3;
    pub const DENSITY_OUT: u32 = 4;
    /// Each cell's vapour supply threshold ([`super::FormationGrid::supply`]).
    pub const SUPPLY: u32 = 5;
    /// The weather kernel: the two steps' densities, the base texels, the gated texels.
    pub const NOW: u32 = 1;
    pub const NEXT: u32 = 2;
    pub const BASE: u32 = 3;
    pub const TEXELS: u32 = 4;
}

/// Invocations per workgroup of both kernels.
pub const WORKGROUP: u32 = 64;

/// Cells per side of a grid: at least 4 (the neighbourhood reaches 2 cells), at most 1024.
pub const CELLS: std::ops::RangeInclusive<u32> = 4..=1024;

/// A compute entry point with one item per invocation: `body` runs for the items below `count`
/// (the dispatch rounds up to whole workgroups of [`WORKGROUP`]).
fn per_item(m: &mut ModuleBuilder, entry: &str, doc: &str, count: u32, body: impl FnOnce(U32)) {
    m.compute(entry, doc, loc!(), [WORKGROUP, 1, 1], |gid| {
        let index = nimbus_dsl::control::bind("index", loc!(), gid.x);
        nimbus_dsl::control::branch(
            loc!(),
            nimbus_dsl::ops::lt(index, count),
            || body(index),
            || {},
        );
    });
}

/// The step kernel for a `cells`-wide grid: one cell per invocation, reading step k's states and
/// densities and writing step k + 1's.
pub fn formation_step_module(cells: u32) -> Result<Module, DslError> {
    ModuleBuilder::build(
        "formation_step",
        "One step of the cloud-formation automaton (Dobashi et al. 2000): one cell per invocation.",
        loc!(),
        |m| {
            let params = m.uniform::<FormationParams>("params", 0, slots::PARAMS, "This step.");
            let states_in = m.storage::<U32>("states_in", 0, slots::STATES_IN, false, "Step k.");
            let density_in = m.storage::<F32>("density_in", 0, slots::DENSITY_IN, false, "Step k.");
            let states_out =
                m.storage::<U32>("states_out", 0, slots::STATES_OUT, true, "Step k + 1.");
            let density_out =
                m.storage::<F32>("density_out", 0, slots::DENSITY_OUT, true, "Step k + 1.");
            let supply = m.storage::<U32>("supply", 0, slots::SUPPLY, false, "Vapour supply.");
            per_item(
                m,
                "cs_formation_step",
                "One cell per invocation; the grid wraps.",
                cells * cells,
                |index| {
                    let x = index % cells;
                    let y = index / cells;
                    let states = states_in.array();
                    let at = |offset: (i32, i32)| {
                        // (x + cells + dx) % cells, the offset folded in at generation time.
                        let nx = (x + (cells as i32 + offset.0) as u32) % cells;
                        let ny = (y + (cells as i32 + offset.1) as u32) % cells;
                        nx + ny * cells
                    };
                    let neighbours = NEIGHBOURS
                        .iter()
                        .fold(U32::lit(0), |acc, o| acc | states.get(at(*o)));
                    let cloudy = SMOOTHING.iter().fold(U32::lit(0), |acc, o| {
                        acc + has::shader(states.get(at(*o)), CLD)
                    });
                    let p = params.get();
                    let next = formation_cell::shader(
                        states.get(index),
                        neighbours,
                        index,
                        supply.array().get(index),
                        p,
                    );
                    states_out.array().set(index, next);
                    let d = formation_density::shader(density_in.array().get(index), cloudy, p);
                    density_out.array().set(index, d);
                },
            );
        },
    )
}

/// The weather kernel: gates each texel of a `size`-texel weather texture (rows padded to
/// `row` texels) by the density of a `cells`-wide grid, between two steps.
pub fn formation_weather_module(cells: u32, size: u32, row: u32) -> Result<Module, DslError> {
    ModuleBuilder::build(
        "formation_weather",
        "The weather texture gated by the formation automaton's density: one texel per \
         invocation.",
        loc!(),
        |m| {
            let params = m.uniform::<FormationParams>("params", 0, slots::PARAMS, "Blend.");
            let now = m.storage::<F32>("now", 0, slots::NOW, false, "Densities at step k.");
            let next = m.storage::<F32>("next", 0, slots::NEXT, false, "At step k + 1.");
            let base = m.storage::<U32>("base", 0, slots::BASE, false, "Weather texels.");
            let texels = m.storage::<U32>("texels", 0, slots::TEXELS, true, "Gated texels.");
            per_item(
                m,
                "cs_formation_weather",
                "One texel per invocation.",
                size * size,
                |index| {
                    let tx = index % size;
                    let ty = index / size;
                    // Cell centres sit at (i + 0.5) / cells of the tile, as texel centres do.
                    let scale = cells as f32 / size as f32;
                    let gx =
                        (nimbus_dsl::ops::cast::<F32, _>(tx) + 0.5) * scale + (cells as f32 - 0.5);
                    let gy =
                        (nimbus_dsl::ops::cast::<F32, _>(ty) + 0.5) * scale + (cells as f32 - 0.5);
                    // Shifted by a whole grid so the floor is of a positive number.
                    let cx = nimbus_dsl::ops::cast::<U32, _>(gx.floor());
                    let cy = nimbus_dsl::ops::cast::<U32, _>(gy.floor());
                    let f = shader::vec2(gx.fract(), gy.fract());
                    let cell = |dx: u32, dy: u32| ((cx + dx) % cells) + ((cy + dy) % cells) * cells;
                    let corners = |a: nimbus_dsl::value::StorageArray<F32>| {
                        shader::vec4(
                            a.get(cell(0, 0)),
                            a.get(cell(1, 0)),
                            a.get(cell(0, 1)),
                            a.get(cell(1, 1)),
                        )
                    };
                    let p = params.get();
                    let d =
                        formation_sample::shader(corners(now.array()), corners(next.array()), f, p);
                    let target = tx + ty * row;
                    let gated = formation_weather::shader(base.array().get(target), d, p);
                    texels.array().set(target, gated);
                },
            );
        },
    )
}

/// The automaton on the CPU: the same cell rules (the `#[shader_fn]`s' CPU twins) over the same
/// wrapped neighbourhoods, for tests and for checking the GPU's grid.
#[derive(Clone, Debug, PartialEq)]
pub struct FormationGrid {
    pub cells: u32,
    /// Steps taken.
    pub step: u32,
    pub states: Vec<u32>,
    pub density: Vec<f32>,
    /// Each cell's vapour supply, as a threshold ([`threshold`]): the scene's humidity times
    /// the moisture of the weather map at the cell.
    pub supply: Vec<u32>,
}

/// Moisture of the weather map's low-cloud signal `w` (0–1): dry below 0.2, saturated above
/// 0.5, so clouds form in the weather's moist areas and rarely between them.
#[shader_fn]
pub fn moisture(w: f32) -> f32 {
    smoothstep(0.2, 0.5, w)
}

impl FormationGrid {
    /// A clear sky (no vapour, no cloud) over the procedural weather map: `humidity` is the
    /// probability per step that vapour returns to a cell where the map is moist.
    pub fn new(cells: u32, humidity: f32) -> FormationGrid {
        let n = (cells * cells) as usize;
        let weather_cells = super::noise::WEATHER_CELLS;
        let supply = (0..n as u32)
            .map(|i| {
                let uv = glam::Vec2::new(
                    ((i % cells) as f32 + 0.5) / cells as f32,
                    ((i / cells) as f32 + 0.5) / cells as f32,
                );
                let w = super::noise::weather_noise(uv, weather_cells).x;
                threshold(humidity * moisture(w))
            })
            .collect();
        FormationGrid {
            cells,
            step: 0,
            states: vec![0; n],
            density: vec![0.0; n],
            supply,
        }
    }

    /// One step; `params.step` is taken from the grid.
    pub fn advance(&mut self, params: FormationParams) {
        let params = FormationParams {
            step: self.step,
            ..params
        };
        let c = self.cells;
        let mut states = vec![0; self.states.len()];
        let mut density = vec![0.0; self.density.len()];
        for y in 0..c {
            for x in 0..c {
                let i = (x + y * c) as usize;
                let neighbours = NEIGHBOURS
                    .iter()
                    .fold(0, |acc, o| acc | self.states[wrapped(x, y, *o, c) as usize]);
                let cloudy = SMOOTHING
                    .iter()
                    .map(|o| has(self.states[wrapped(x, y, *o, c) as usize], CLD))
                    .sum();
                states[i] =
                    formation_cell(self.states[i], neighbours, i as u32, self.supply[i], params);
                density[i] = formation_density(self.density[i], cloudy, params);
            }
        }
        self.states = states;
        self.density = density;
        self.step += 1;
    }

    /// Share of cells holding cloud.
    pub fn cloud_fraction(&self) -> f32 {
        let cloudy = self.states.iter().filter(|s| *s & CLD != 0).count();
        cloudy as f32 / self.states.len().max(1) as f32
    }
}
