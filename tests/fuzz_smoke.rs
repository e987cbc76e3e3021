//! A short run of the fuzz targets' bodies (`nimbus_testkit::fuzz`, which `fuzz/` runs under
//! libFuzzer on nightly): the example genera and scenes, then deterministic mutations of them
//! (bytes flipped, tokens of the files' dictionary spliced in, lines dropped or repeated,
//! numbers replaced by edge values). No input may panic; every accepted genus or scene must
//! generate shaders naga validates. The long runs are `fuzz/run.sh`; see the README.

use std::path::Path;

use nimbus_codegen::Target;
use nimbus_testkit::fuzz::{genus_codegen, genus_parser, scene_codegen, scene_parser};
use nimbus_testkit::mutation::mutate;

/// Example files, renamed to the name the fuzz targets parse them under.
fn seeds(dir: &str, rename_genus: bool) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(dir);
    let mut files: Vec<_> = std::fs::read_dir(&root)
        .expect("examples")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|f| {
            let stem = f.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
            let text = std::fs::read_to_string(f).expect("read");
            let text = text.replace(&format!("name = \"{stem}\""), "name = \"fuzzed\"");
            if rename_genus {
                text.lines()
                    .map(|l| {
                        if l.starts_with("genus = ") {
                            "genus = \"fuzzed\"".to_string()
                        } else {
                            l.to_string()
                        }
                    })
                    .collect::<Vec<_>>()
                    .join("\n")
            } else {
                text
            }
        })
        .collect()
}

#[test]
fn fuzz_targets_survive_the_seed_corpus_and_its_mutations() {
    let genera = seeds("genera", false);
    let scenes = seeds("scenes", true);
    let (mut parsed, mut accepted_genera, mut accepted_scenes, mut modules) = (0u64, 0, 0, 0);
    for (i, g) in genera.iter().enumerate() {
        for n in 0..400u64 {
            let input = if n == 0 {
                g.as_bytes().to_vec()
            } else {
                mutate(g, n * 7919 + i as u64)
            };
            genus_parser(&input);
            parsed += 1;
            // Codegen (WGSL through naga, every backend) for a share of the inputs; each
            // distinct key is generated once.
            if n % 8 == 0 {
                let o = genus_codegen(&input, &Target::ALL);
                accepted_genera += usize::from(o.accepted);
                modules += o.modules;
            }
        }
    }
    let cumulus = genera
        .iter()
        .find(|g| g.contains("cumulus") && !g.contains("nimbus"))
        .cloned()
        .unwrap_or_else(|| genera[0].clone());
    for (i, s) in scenes.iter().enumerate() {
        for n in 0..400u64 {
            let input = if n == 0 {
                s.as_bytes().to_vec()
            } else {
                mutate(s, n * 104_729 + i as u64)
            };
            scene_parser(&input);
            parsed += 1;
            if n % 8 == 0 {
                let o = scene_codegen(&input, &cumulus, &Target::ALL);
                accepted_scenes += usize::from(o.accepted);
                modules += o.modules;
            }
        }
    }
    println!(
        "fuzz smoke: {parsed} inputs parsed; {accepted_genera} genera and {accepted_scenes} \
         scenes accepted, {modules} shader keys reached, every one validated"
    );
    assert!(
        accepted_genera >= genera.len(),
        "the seed genera are accepted"
    );
    assert!(
        accepted_scenes >= scenes.len(),
        "the seed scenes are accepted"
    );
}
