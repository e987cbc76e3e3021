//! `nimbus emit`: the selected shaders (one per key), or those a scene derives, with the genus ×
//! preset → key table in the manifest.

use std::path::Path;

use nimbus_codegen::{EmitExtras, Target, emit, generate_variant};

use crate::data::{Resolved, Selection, load, resolve, table_text};

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    scene: Option<&Path>,
    targets: &str,
    out: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let targets = Target::parse_list(targets)?;
    let Resolved { entries, table } = match scene {
        Some(file) => crate::explain::resolved(data, file)?,
        None => resolve(sel, &load(data)?)?,
    };
    let mut generated = Vec::new();
    for s in &entries {
        generated.push(generate_variant(s, &targets)?);
    }
    let extras = EmitExtras {
        manifest_appendix: table_text(&table),
        files: Vec::new(),
    };
    let report = emit(&generated, &extras, out)?;
    for g in &generated {
        println!("{}", g.stats.manifest_line(&g.id()));
    }
    println!(
        "wrote {} files for {} shader(s) ({} genus × preset pair(s)) to {}",
        report.files.len(),
        generated.len(),
        table.len(),
        report.dir.display()
    );
    Ok(())
}
