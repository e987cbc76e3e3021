//! `nimbus check`: every selected shader generated and validated for every target, the number of
//! distinct shaders per module and the genus × preset pairs that share each. Two keys that
//! print the same text would mean a key holds a setting that changes no code: that fails too.

use std::collections::BTreeMap;
use std::path::Path;

use nimbus_codegen::external::{ExternalCheck, check_files};
use nimbus_codegen::{Target, generate_variant, validate};
use nimbus_dsl::ShaderVariant;

use crate::data::{Selection, load, print_sharing, resolve};

#[derive(Debug, thiserror::Error)]
#[error("{failures} check(s) failed")]
pub(crate) struct CheckFailed {
    failures: usize,
}

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    external: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let lib = load(data)?;
    let resolved = resolve(sel, &lib)?;
    let sources = &resolved.entries;
    let mut failures = 0usize;
    let mut files = 0usize;
    let mut missing = std::collections::BTreeSet::new();
    let mut external_passed = 0usize;
    // WGSL text without its comments → the first shader that printed it, per module.
    let mut texts: BTreeMap<(String, String), String> = BTreeMap::new();
    for source in sources {
        match generate_variant(source, &Target::ALL) {
            Err(e) => {
                failures += 1;
                say_err!("FAIL {}: {e}", source.id());
            }
            Ok(g) => {
                files += g.files.len();
                // Generation validated the lowered module; the printed WGSL (what WebGPU hosts
                // load) is parsed and validated here as well.
                if let Err(e) = validate(&g.wgsl, &g.spans, &g.module_name, &g.variant) {
                    failures += 1;
                    say_err!("FAIL {}: the printed WGSL: {e}", g.id());
                }
                let code: String = g
                    .wgsl
                    .lines()
                    .filter(|l| !l.trim_start().starts_with("//"))
                    .collect::<Vec<_>>()
                    .join("\n");
                if let Some(first) = texts.insert((g.module_name.clone(), code), g.id()) {
                    failures += 1;
                    say_err!(
                        "FAIL {} prints the same code as {first}: its key holds a setting that changes nothing",
                        g.id()
                    );
                }
                if external {
                    let files: Vec<_> = g.files.iter().collect();
                    for (f, check) in files.iter().zip(check_files(&files)) {
                        match check {
                            ExternalCheck::Passed { .. } => external_passed += 1,
                            ExternalCheck::Failed { tool, output } => {
                                failures += 1;
                                say_err!("FAIL {} ({tool}): {output}", f.file_name);
                            }
                            ExternalCheck::ToolMissing { tool } => {
                                missing.insert(tool);
                            }
                            ExternalCheck::NotApplicable => {}
                        }
                    }
                }
                say!("ok   {}", g.stats.manifest_line(&g.id()));
            }
        }
    }
    for tool in &missing {
        say!("skipped external validation with {tool}: not installed");
    }
    say!();
    say!(
        "distinct shaders ({} genus × preset pair(s)):",
        resolved.table.len()
    );
    print_sharing(sources);
    say!();
    say!(
        "{} shader(s), {files} file(s) validated by naga, {external_passed} also by external tools; {failures} failure(s)",
        sources.len()
    );
    if failures > 0 {
        return Err(Box::new(CheckFailed { failures }));
    }
    Ok(())
}
