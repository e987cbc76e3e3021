//! The numerical-stability catalogue: named hard cases for the cloud model, each a set of rays
//! (probes) with the invariants they must keep. The catalogue is data; the CPU twins run it in
//! `tests/stability.rs` and the generated shaders run the very same probes on the GPU in
//! `tests/stability_gpu.rs`, both judged by [`check_case`].
//!
//! Invariants, per probe: every output finite; transmittance in [0, 1]; radiance non-negative
//! and within the energy the medium can scatter, `S_max · albedo · (1 − T)`; a pixel no
//! brighter than the sun's disc plus everything that scatters sunlight; density samples within
//! the step limits. Per chain of probes that cut one ray shorter and shorter: transmittance
//! never increases with distance. Per pair of probes on either side of a threshold: outputs
//! close (continuity).

mod case;
mod catalogue;
mod invariants;
mod probe;

pub use case::{Case, CaseTextures, Pair, Probe};
pub use catalogue::{base_genus, catalogue, genus_case, single_ray_case};
pub use invariants::{Violation, check_case, fragment_bound, source_bound};
pub use probe::{RayOutcome, RayOutcomeShader, probe_ray, run_case_cpu};
