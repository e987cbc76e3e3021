//! A short run of the command line's fuzz bodies (`nimbus_cli::fuzz`, which `fuzz/` runs under
//! libFuzzer on nightly): timelines through the scene loader every command uses, `animate`'s
//! arguments through its own parser and planner, and engine packages built from scenes. The
//! seeds are the example scenes and argument lists; then deterministic mutations of them. No
//! input may panic; the seeds must be accepted.

use std::path::Path;

use nimbus_cli::fuzz::{animate_args, engine_package, timeline};
use nimbus_testkit::mutation::mutate;

/// The example scenes with a timeline ([clock], [wind] or [[weather]]), named as fuzzed files.
fn timeline_scenes() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut files: Vec<_> = std::fs::read_dir(&root)
        .expect("examples")
        .flatten()
        .map(|e| e.path())
        .collect();
    files.sort();
    files
        .iter()
        .filter_map(|f| {
            let stem = f.file_stem()?.to_str()?;
            let text = std::fs::read_to_string(f).ok()?;
            let timed = ["[clock]", "[wind]", "[[weather]]"]
                .iter()
                .any(|t| text.contains(t));
            timed.then(|| text.replace(&format!("name = \"{stem}\""), "name = \"fuzzed\""))
        })
        .collect()
}

/// `animate` argument lists (one per line, the scene file first).
const ANIMATE_SEEDS: &[&str] = &[
    "day-with-wind.toml\n--to\n7200\n--speed\n1800\n--fps\n1",
    "day-with-wind.toml\n--from\n6000\n--to\n10800\n--speed\n600\n-r\n64x36",
    "clouds-forming.toml\n--to\n600\n--speed\n300\n--fps\n1\n--frames\n2",
    "sunset.toml\n--to\n0",
];

#[test]
fn the_command_lines_fuzz_bodies_survive_their_seeds_and_mutations() {
    let scenes = timeline_scenes();
    assert!(scenes.len() >= 2, "example scenes with a timeline");
    let (mut timelines, mut states) = (0, 0);
    for (i, s) in scenes.iter().enumerate() {
        for n in 0..120u64 {
            let mut input = vec![(n * 37 + i as u64) as u8];
            if n == 0 {
                input.extend_from_slice(s.as_bytes());
            } else {
                input.extend(mutate(s, n * 6007 + i as u64));
            }
            let o = timeline(&input);
            assert!(n != 0 || o.accepted, "seed scene {i} refused");
            timelines += usize::from(o.accepted);
            states += o.made;
        }
    }
    let (mut plans, mut pictures) = (0, 0);
    for (i, seed) in ANIMATE_SEEDS.iter().enumerate() {
        for n in 0..40u64 {
            let input = if n == 0 {
                seed.as_bytes().to_vec()
            } else {
                mutate(seed, n * 7919 + i as u64)
            };
            let o = animate_args(&input);
            assert!(n != 0 || o.accepted, "seed arguments {seed:?} refused");
            plans += usize::from(o.accepted);
            pictures += o.made;
        }
    }
    // Packages: the seeds for every engine, and a few mutations each (a package generates and
    // validates every pass, so fewer runs).
    let (mut packages, mut files) = (0, 0);
    for (i, s) in scenes.iter().enumerate() {
        for n in 0..8u64 {
            let mut input = vec![(n * 5 + i as u64) as u8];
            if n < 6 {
                input.extend_from_slice(s.as_bytes());
            } else {
                input.extend(mutate(s, n * 104_729 + i as u64));
            }
            let o = engine_package(&input);
            assert!(
                n >= 6 || o.accepted,
                "seed scene {i}, engine pick {}",
                input[0]
            );
            packages += usize::from(o.accepted);
            files += o.made;
        }
    }
    println!(
        "fuzz smoke (command line): {timelines} timelines accepted ({states} states checked), \
         {plans} animate argument lists planned ({pictures} pictures), {packages} packages \
         built ({files} files)"
    );
}
