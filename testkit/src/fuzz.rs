//! What the fuzz targets (`fuzz/`, cargo-fuzz on nightly) run, as plain functions, so the
//! default test run can call the same bodies over a seed corpus and a bounded number of
//! mutations (`tests/fuzz_smoke.rs`) without nightly.
//!
//! Each body panics only on a Nimbus bug: parsing may refuse any input (with a typed error),
//! but must not panic; and a genus or scene that is accepted must yield shader modules that
//! naga validates for every target.

use std::path::Path;

use std::collections::HashSet;
use std::sync::Mutex;

use nimbus_clouds::catalog::{Assignment, ShaderKey, assign};
use nimbus_clouds::{Genus, Quality, ScenePreset, analyse, parse_genus, parse_scene};
use nimbus_codegen::{Target, generate, validate};
use nimbus_dsl::ShaderVariant as _;

/// The name every fuzzed file goes by (a genus or scene must be named after its file).
pub const FUZZ_NAME: &str = "fuzzed";

/// Parses `data` as a genus file: accepted or refused, never a panic.
pub fn genus_parser(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = parse_genus(Path::new("genera/fuzzed.toml"), &text);
}

/// Parses `data` as a scene file: accepted or refused, never a panic.
pub fn scene_parser(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = parse_scene(Path::new("scenes/fuzzed.toml"), &text);
}

/// What an accepted input became, for the smoke test's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    pub accepted: bool,
    pub modules: usize,
}

/// Parses `data` as a genus; if accepted, every quality preset's cloud and shadow keys are
/// generated for `targets` and validated by naga (and translated by each backend). A key that
/// fails is a bug: this panics with the input and the error.
pub fn genus_codegen(data: &[u8], targets: &[Target]) -> Outcome {
    let text = String::from_utf8_lossy(data);
    let Ok(genus) = parse_genus(Path::new("genera/fuzzed.toml"), &text) else {
        return Outcome::default();
    };
    let modules = Quality::ALL
        .iter()
        .map(|&q| check_assignment(&assign(&genus, q, q.features()), targets, &text))
        .sum();
    Outcome {
        accepted: true,
        modules,
    }
}

/// Parses `data` as a scene over `genus_text` (a genus file's text); if both are accepted, the
/// scene's derived keys are generated and validated as in [`genus_codegen`].
pub fn scene_codegen(data: &[u8], genus_text: &str, targets: &[Target]) -> Outcome {
    let text = String::from_utf8_lossy(data);
    let Ok(scene) = parse_scene(Path::new("scenes/fuzzed.toml"), &text) else {
        return Outcome::default();
    };
    let Ok(genus) = parse_genus(Path::new("genera/fuzzed.toml"), genus_text) else {
        return Outcome::default();
    };
    Outcome {
        accepted: true,
        modules: check_scene_keys(&genus, &scene, targets),
    }
}

/// Generates and validates every key of one genus × preset assignment; returns their count.
fn check_assignment(a: &Assignment, targets: &[Target], input: &str) -> usize {
    let keys = a.keys();
    for key in &keys {
        check_key(*key, targets, input);
    }
    keys.len()
}

/// Keys already generated and validated in this process. Generation is deterministic, so a
/// key checked once is checked for every input that reaches it; the fuzzer's time then goes
/// to finding new keys and new parser paths.
static CHECKED: Mutex<Option<HashSet<ShaderKey>>> = Mutex::new(None);

/// Generates and validates (for `targets`) the keys `scene` derives for `genus`, as `render`
/// would pick them; returns how many keys that is. Both must be valid already.
pub fn check_scene_keys(genus: &Genus, scene: &ScenePreset, targets: &[Target]) -> usize {
    let mut genus = genus.clone();
    if let Some(c) = scene.coverage {
        genus.coverage = c;
    }
    let features = analyse(scene, &genus).features;
    let a = assign(&genus, scene.quality, features);
    check_assignment(&a, targets, &format!("{genus:?}\n{scene:?}"))
}

fn check_key(key: ShaderKey, targets: &[Target], input: &str) {
    {
        let mut done = CHECKED
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if !done.get_or_insert_with(HashSet::new).insert(key) {
            return;
        }
    }
    let module = key
        .record()
        .unwrap_or_else(|e| panic!("{} does not record: {e}\ninput:\n{input}", key.id()));
    let g = generate(module, &key.variant(), targets)
        .unwrap_or_else(|e| panic!("{} fails codegen: {e}\ninput:\n{input}", key.id()));
    // Generation validates the lowered module; the WGSL printed from the same IR is what WebGPU
    // hosts load, so it must parse and validate too.
    if targets.contains(&Target::Wgsl)
        && let Err(e) = validate(&g.wgsl, &g.spans, &g.module_name, &g.variant)
    {
        panic!("{}: the printed WGSL: {e}\ninput:\n{input}", key.id());
    }
}
