//! `nimbus check`.

use std::path::Path;

use nimbus_codegen::external::{ExternalCheck, check_file};
use nimbus_codegen::{Target, generate_variant};

use crate::data::{Selection, load, resolve};

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
    let sources = resolve(sel, &lib)?;
    let mut failures = 0usize;
    let mut files = 0usize;
    let mut missing = std::collections::BTreeSet::new();
    let mut external_passed = 0usize;
    for source in &sources {
        match generate_variant(source, &Target::ALL) {
            Err(e) => {
                failures += 1;
                eprintln!("FAIL {}: {e}", source.key());
            }
            Ok(g) => {
                files += g.files.len();
                if external {
                    for f in &g.files {
                        match check_file(f) {
                            ExternalCheck::Passed { .. } => external_passed += 1,
                            ExternalCheck::Failed { tool, output } => {
                                failures += 1;
                                eprintln!("FAIL {} ({tool}): {output}", f.file_name);
                            }
                            ExternalCheck::ToolMissing { tool } => {
                                missing.insert(tool);
                            }
                            ExternalCheck::NotApplicable => {}
                        }
                    }
                }
                println!("ok   {}", g.stats.manifest_line(&g.key()));
            }
        }
    }
    for tool in &missing {
        println!("skipped external validation with {tool}: not installed");
    }
    println!(
        "{} variant(s), {files} file(s) validated by naga, {external_passed} also by external tools; {failures} failure(s)",
        sources.len()
    );
    if failures > 0 {
        return Err(Box::new(CheckFailed { failures }));
    }
    Ok(())
}
