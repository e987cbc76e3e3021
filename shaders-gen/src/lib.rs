//! `nimbus`: emit, check, list and benchmark the generated shaders, and render scenes. The
//! binary is [`main`]; the library exists so the fuzz targets (`fuzz/`) and the smoke tests
//! can run the command line's own code paths ([`fuzz`]) without a process per input.

// First, so that every module below can print through its macros.
#[macro_use]
mod stdout;

mod animate;
mod bench;
mod bench_frames;
mod check;
mod cli;
mod data;
mod data_folder;
mod diff;
mod diff_revision;
mod emit;
mod engine;
mod error;
mod explain;
mod export_density;
mod formation_progress;
mod gallery;
mod list;
mod package;
mod package_description;
mod package_textures;
mod plot;
mod render;
mod scene_input;
mod session;
mod tradeoff;
mod unity_shaderlab;

pub mod fuzz;

pub(crate) use cli::ToggleArgs;
pub use cli::main;
