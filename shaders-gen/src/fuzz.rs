//! What the fuzz targets (`fuzz/`, cargo-fuzz on nightly) run of the command line, as plain
//! functions that `tests/fuzz_smoke_cli.rs` also runs over a seed corpus without nightly. Each
//! may refuse its input with a typed error; a panic is a Nimbus bug.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use clap::Parser;
use nimbus_clouds::{CloudLibrary, parse_scene};

use crate::cli::{Cli, Command};
use crate::engine::Engine;
use crate::scene_input::SceneInput;

/// The built-in example library and its folder, loaded once per process.
fn library() -> Option<&'static (CloudLibrary, PathBuf)> {
    static LIB: OnceLock<Option<(CloudLibrary, PathBuf)>> = OnceLock::new();
    LIB.get_or_init(|| {
        Some((
            crate::data::load(None).ok()?,
            crate::data::data_dir(None).ok()?,
        ))
    })
    .as_ref()
}

/// What an input became, for the smoke test's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// The input was accepted (parsed, checked).
    pub accepted: bool,
    /// Pictures planned, or package files written in memory.
    pub made: usize,
}

/// `data` as `animate`'s arguments after the scene (one per line; the first line is the
/// scene: a file of the built-in examples' `scenes/`, e.g. `day-with-wind.toml`): parsed by
/// the command line's own parser and planned (every argument checked, every picture's frames
/// built), without a GPU or a write.
pub fn animate_args(data: &[u8]) -> Outcome {
    let text = String::from_utf8_lossy(data);
    let mut lines = text.lines();
    let (Some((_, dir)), Some(scene)) = (library(), lines.next()) else {
        return Outcome::default();
    };
    // Only a plain file name inside the examples: the fuzzer must not read the machine.
    if scene.is_empty() || scene.contains(['/', '\\']) || scene.starts_with('.') {
        return Outcome::default();
    }
    let scene = dir.join("scenes").join(scene);
    let args = [
        "nimbus".to_string(),
        "animate".into(),
        scene.display().to_string(),
    ]
    .into_iter()
    .chain(lines.map(str::to_string));
    let Ok(cli) = Cli::try_parse_from(args) else {
        return Outcome::default();
    };
    let Command::Animate(a) = cli.command else {
        return Outcome::default();
    };
    match crate::animate::plan(Some(dir), &a) {
        Ok(plan) => Outcome {
            accepted: true,
            made: plan.pictures.len(),
        },
        Err(_) => Outcome::default(),
    }
}

/// `data` as a byte that picks (a time, an engine) and a scene file: the byte, the scene's
/// text and the scene as every command loads it, or `None` when it is refused.
fn scene_input(data: &[u8]) -> Option<(u8, String, SceneInput)> {
    let (&pick, rest) = data.split_first()?;
    let (lib, _) = library()?;
    let text = String::from_utf8_lossy(rest).into_owned();
    let file = Path::new("scenes/fuzzed.toml");
    let scene = parse_scene(file, &text).ok()?;
    let input = SceneInput::from_scene(lib, file, scene, None).ok()?;
    Some((pick, text, input))
}

/// `data` as a scene file with a timeline (the first byte picks a second of it): if accepted,
/// the scene is taken at second 0, at that second and at the last second a timeline may
/// reach, through the loader every command uses. Each time gives one state or two whose
/// weights are finite, in 0..=1 and sum to 1, with a finite sun; each state's frame is accepted
/// or refused with a typed error. Anything else is a bug.
pub fn timeline(data: &[u8]) -> Outcome {
    let Some((pick, text, input)) = scene_input(data) else {
        return Outcome::default();
    };
    let last = nimbus_clouds::limits::TIME.max;
    let mut made = 0;
    for seconds in [0.0, f64::from(pick) * f64::from(pick) * 7.3, last] {
        let Ok(states) = input.at(seconds) else {
            continue;
        };
        assert!(
            matches!(states.len(), 1 | 2),
            "{} states at {seconds} s\n{text}",
            states.len()
        );
        let total: f32 = states.iter().map(|s| s.weight).sum();
        for s in &states {
            assert!(
                s.weight.is_finite() && (0.0..=1.0).contains(&s.weight),
                "weight {} at {seconds} s\n{text}",
                s.weight
            );
            assert!(
                s.scene.sun_elevation_deg.is_finite() && s.scene.sun_azimuth_deg.is_finite(),
                "sun at {seconds} s\n{text}"
            );
            assert!(
                s.drift.ground.is_finite() && s.drift.per_metre.is_finite(),
                "wind drift at {seconds} s\n{text}"
            );
            // A frame of the state is accepted or refused by its checks, never a panic.
            let _ = s.frame(64, 36).validate();
            made += 1;
        }
        assert!((total - 1.0).abs() < 1e-4, "weights sum to {total}\n{text}");
    }
    Outcome {
        accepted: true,
        made,
    }
}

/// `data` as a scene file (the first byte picks the engine and the timeline second); if
/// accepted, the engine package of its derived pairs is built in memory: every pass generated
/// and validated by naga, the description and uniform files serialised. A refusal must be a
/// typed error (an engine's limit); a panic or a failed validation is a bug.
pub fn engine_package(data: &[u8]) -> Outcome {
    let Some((pick, text, input)) = scene_input(data) else {
        return Outcome::default();
    };
    let engines = <Engine as clap::ValueEnum>::value_variants();
    let engine = engines[usize::from(pick) % engines.len()];
    let seconds = f64::from(pick / 8) * 900.0;
    let selection = crate::data::Selection {
        name: None,
        genus: None,
        quality: None,
        enable: &[],
        disable: &[],
        octaves: None,
        path: None,
    };
    let Ok(resolved) = crate::explain::resolved_from(&input, &selection, seconds) else {
        return Outcome::default();
    };
    match crate::package::build(&resolved, engine) {
        Ok(package) => Outcome {
            accepted: true,
            made: package.extras.files.len(),
        },
        Err(crate::error::CliError::EngineLimit { .. }) => Outcome::default(),
        Err(e) => panic!("{engine:?} package of an accepted scene failed: {e}\n{text}"),
    }
}
