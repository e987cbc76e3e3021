//! `nimbus emit`.

use std::path::Path;

use nimbus_codegen::{CodegenError, Target, emit, generate_variant};

use crate::data::{Selection, load, resolve};

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    targets: &str,
    out: &Path,
) -> Result<(), CodegenError> {
    let targets = Target::parse_list(targets)?;
    let lib = load(data)?;
    let sources = resolve(sel, &lib)?;
    let mut generated = Vec::new();
    for s in &sources {
        generated.push(generate_variant(s, &targets)?);
    }
    let report = emit(&generated, out)?;
    for g in &generated {
        println!("{}", g.stats.manifest_line(&g.key()));
    }
    println!(
        "wrote {} files for {} variant(s) to {}",
        report.files.len(),
        generated.len(),
        report.dir.display()
    );
    Ok(())
}
