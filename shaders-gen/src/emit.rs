//! `nimbus emit`.

use std::path::Path;

use nimbus_codegen::{CodegenError, Target, catalog, emit, generate_variant, select_variants};

pub(crate) fn run(name: Option<&str>, targets: &str, out: &Path) -> Result<(), CodegenError> {
    let targets = Target::parse_list(targets)?;
    let sources = match name {
        Some(n) => select_variants(n)?,
        None => catalog(),
    };
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
