//! `nimbus emit`: the selected shaders (one per key), or those a scene derives, with the genus ×
//! preset → key table in the manifest.

use std::path::Path;

use rayon::prelude::*;

use nimbus_codegen::{EmitExtras, Target, emit, generate_variant};
use nimbus_output::{Overwrite, check_folder};

use crate::data::{Resolved, Selection, keys_json, load, resolve, table_text};

/// The genus × preset → key table with uniform values, beside the manifest.
pub(crate) const KEYS_FILE: &str = "nimbus-keys.json";

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    scene: Option<(&Path, f64)>,
    targets: &[Target],
    (out, overwrite): (&Path, Overwrite),
) -> Result<(), Box<dyn std::error::Error>> {
    check_folder(out, overwrite)?;
    let resolved = match scene {
        Some((file, seconds)) => crate::explain::resolved(data, file, sel, seconds)?,
        None => resolve(sel, &load(data)?)?,
    };
    let Resolved { entries, table, .. } = &resolved;
    // Every key on every core; the first failure in key order is the one reported.
    let generated = entries
        .par_iter()
        .map(|s| generate_variant(s, targets))
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let mut files = Vec::new();
    if !table.is_empty() {
        files.push((KEYS_FILE.to_string(), keys_json(&resolved)?.into_bytes()));
    }
    let extras = EmitExtras {
        manifest_appendix: table_text(table),
        files,
    };
    let report = emit(&generated, &extras, out, overwrite)?;
    for g in &generated {
        say!("{}", g.stats.manifest_line(&g.id()));
    }
    say!(
        "wrote {} files for {} shader(s) ({} genus × preset pair(s)) to {}",
        report.files.len(),
        generated.len(),
        table.len(),
        report.dir.display()
    );
    Ok(())
}
