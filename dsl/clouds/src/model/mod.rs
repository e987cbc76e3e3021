//! The cloud model, written once as `#[shader_fn]` functions: each runs on the CPU (tests,
//! reference renders) and is recorded into shader modules for every target.

pub mod air_shadow;
pub mod air_table;
pub mod bake;
pub mod bindings;
pub mod blob2d;
pub mod choices;
pub mod clouds;
pub mod density;
pub mod diffusion;
pub mod display;
pub mod flat_layer;
pub mod formation;
pub mod genus_fns;
pub mod impostor;
pub mod layers;
pub mod march;
pub mod mesh;
pub mod noise;
pub mod orthographic;
pub mod phase;
pub mod preview;
pub mod profile;
pub mod resolve;
pub mod resource;
pub mod scene_depth;
pub mod scene_shadow;
pub mod shadow;
pub mod shell;
pub mod sky;
pub mod slices;
pub mod sun;
pub mod tile_bands;
pub mod tonemap;
pub mod transmission;
pub mod untiled_weather;
