//! `nimbus emit`: the selected variants, or the one a scene derives.

use std::path::Path;

use nimbus_codegen::{Target, emit, generate_variant};

use crate::data::{Selection, load, resolve};

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    scene: Option<&Path>,
    targets: &str,
    out: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let targets = Target::parse_list(targets)?;
    let sources = match scene {
        Some(file) => crate::explain::variant_source(data, file)?,
        None => resolve(sel, &load(data)?)?,
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
