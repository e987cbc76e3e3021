//! Where the genus and scene files come from, and how command-line flags pick a variant.

use nimbus_clouds::view_defaults::VIEW_DEFAULTS;
use std::path::{Path, PathBuf};

use crate::data_folder::DataFolder;
use crate::error::CliError;
use nimbus_clouds::catalog::{
    Assignment, CatalogEntry, ShaderKey, assign, catalog, distinct, select,
};
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::{CloudLibrary, Genus, Quality, Toggle};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::layout::{LayoutError, UniformBytes, read_members};
use nimbus_runtime::render::{Frame, Renderer};

/// The data folder (see [`DataFolder`]).
pub(crate) fn data_dir(flag: Option<&Path>) -> Result<PathBuf, CliError> {
    Ok(DataFolder::find(flag)?.dir)
}

/// The library of the data folder. Files that failed to load are reported on stderr and left
/// out; a command that names one gets its error.
pub(crate) fn load(flag: Option<&Path>) -> Result<CloudLibrary, CliError> {
    let folder = DataFolder::find(flag)?;
    load_dir(&folder.dir)
}

/// The library of `dir`, reporting the files that failed to load.
pub(crate) fn load_dir(dir: &Path) -> Result<CloudLibrary, CliError> {
    let lib = CloudLibrary::load(dir)?;
    for p in &lib.problems {
        say_err!("warning: skipped: {p}");
    }
    Ok(lib)
}

/// What the user asked to emit or check.
pub(crate) struct Selection<'a> {
    pub name: Option<&'a str>,
    pub genus: Option<&'a str>,
    pub quality: Option<Quality>,
    pub enable: &'a [Toggle],
    pub disable: &'a [Toggle],
    pub octaves: Option<u32>,
    pub path: Option<nimbus_clouds::Path>,
}

/// The shaders a selection names, and the genus × preset pairs it covers (the table that
/// says which key each pair runs), each with its uniform values.
pub(crate) struct Resolved {
    pub entries: Vec<CatalogEntry>,
    pub table: Vec<Assignment>,
    pub uniforms: Vec<CloudUniforms>,
}

/// The uniform values of `genus` at `quality`, lit and seen as the view defaults say
/// (`VIEW_DEFAULTS`, as `Frame::new` sets them up).
pub(crate) fn pair_uniforms(genus: &Genus, quality: Quality) -> CloudUniforms {
    let d = VIEW_DEFAULTS;
    Renderer::uniforms(&Frame::new(genus.clone(), quality, d.width, d.height))
}

/// The uniform values of every row of `table` whose genus is in `lib`.
fn uniforms_of(lib: &CloudLibrary, table: &[Assignment]) -> Vec<CloudUniforms> {
    table
        .iter()
        .filter_map(|a| lib.genus(&a.genus).map(|g| pair_uniforms(g, a.quality)))
        .collect()
}

/// `nimbus-keys.json`: every pair's keys and uniform values, member by member in layout order,
/// so an engine loads a handful of shaders and switches genus and preset by uniforms alone.
pub(crate) fn keys_json(r: &Resolved) -> Result<String, LayoutError> {
    let pairs = r
        .table
        .iter()
        .zip(&r.uniforms)
        .map(|(a, u)| {
            let members: Vec<serde_json::Value> =
                read_members(CloudUniforms::shader_type(), &u.to_uniform_bytes()?)
                    .into_iter()
                    .map(|(member, value)| serde_json::json!({ "member": member, "value": value }))
                    .collect();
            Ok(serde_json::json!({
                "pair": a.name(),
                "genus": a.genus,
                "quality": a.quality.name(),
                "clouds": ShaderKey::Clouds(a.clouds).id(),
                "shadow": a.shadow.map(|k| ShaderKey::Shadow(k).id()),
                "functions": a.clouds.functions.slots().map(|(slot, name, path, _)| {
                    serde_json::json!({ "slot": slot, "name": name, "path": path })
                }),
                "uniforms": { "block": "clouds", "members": members },
            }))
        })
        .collect::<Result<Vec<_>, LayoutError>>()?;
    let doc = serde_json::json!({
        "about": format!("Each genus × quality preset: the shaders (by key) it runs and the values of the `clouds` uniform block, member by member in layout order. Sun, camera and image members hold the view defaults ({}): a host sets those per frame.", VIEW_DEFAULTS.describe()),
        "pairs": pairs,
    });
    let mut s = serde_json::to_string_pretty(&doc).unwrap_or_default();
    s.push('\n');
    Ok(s)
}

pub(crate) fn resolve(sel: &Selection<'_>, lib: &CloudLibrary) -> Result<Resolved, CliError> {
    let quality = sel.quality;
    let (enable, disable) = (sel.enable, sel.disable);
    if let Some(o) = sel.octaves
        && !(1..=12).contains(&o)
    {
        return Err(CliError::Unknown {
            kind: "octave count",
            given: o.to_string(),
            known: "1..=12".into(),
        });
    }
    if let Some(genus) = sel.genus {
        let g = match (lib.genus(genus), lib.problem_of(genus)) {
            (Some(g), _) => g,
            (None, Some(problem)) => return Err(problem.clone().into()),
            (None, None) => {
                return Err(CliError::Unknown {
                    kind: "genus",
                    given: genus.to_string(),
                    known: lib.genera.keys().cloned().collect::<Vec<_>>().join(", "),
                });
            }
        };
        let qualities = quality.map_or_else(|| Quality::ALL.to_vec(), |q| vec![q]);
        let table: Vec<Assignment> = qualities
            .into_iter()
            .map(|q| {
                let mut f = q.features();
                for t in enable {
                    t.set(&mut f, true);
                }
                for t in disable {
                    t.set(&mut f, false);
                }
                if let Some(o) = sel.octaves {
                    f.octaves = o;
                }
                if let Some(p) = sel.path {
                    f.path = p;
                }
                assign(g, q, f)
            })
            .collect();
        let uniforms = table.iter().map(|a| pair_uniforms(g, a.quality)).collect();
        return Ok(Resolved {
            entries: distinct(&table),
            table,
            uniforms,
        });
    }
    if !enable.is_empty()
        || !disable.is_empty()
        || quality.is_some()
        || sel.octaves.is_some()
        || sel.path.is_some()
    {
        return Err(CliError::Unknown {
            kind: "combination",
            given: "--quality/--enable/--disable/--octaves/--path without --genus".into(),
            known: "pass --genus NAME with them".into(),
        });
    }
    let table = nimbus_clouds::catalog::assignments(lib);
    let entries = match sel.name {
        Some(n) => {
            let found = select(n, Some(lib));
            if found.is_empty() {
                let mut known: Vec<String> = catalog().iter().map(|e| e.id()).collect();
                known.extend(["clouds".into(), "shadow".into(), "preview".into()]);
                known.push("clouds-<key> (see `nimbus list`)".into());
                return Err(CliError::Unknown {
                    kind: "shader",
                    given: n.to_string(),
                    known: known.join(", "),
                });
            }
            found
        }
        None => {
            let mut all = catalog();
            all.extend(distinct(&table));
            all
        }
    };
    // The table rows whose keys were selected.
    let ids: Vec<String> = entries.iter().map(|e| e.id()).collect();
    let table: Vec<Assignment> = table
        .into_iter()
        .filter(|a| a.keys().iter().any(|k| ids.contains(&k.id())))
        .collect();
    let uniforms = uniforms_of(lib, &table);
    Ok(Resolved {
        entries,
        table,
        uniforms,
    })
}

/// The genus × preset → key table, as manifest text: one line per pair.
pub(crate) fn table_text(table: &[Assignment]) -> String {
    let mut s = String::new();
    if table.is_empty() {
        return s;
    }
    s.push_str("\n# Genus × quality preset → shaders (the rest is uniform values):\n");
    for a in table {
        s.push_str(&format!("{:<28} {}", a.name(), a.keys()[0].id()));
        if let Some(k) = a.shadow {
            s.push_str(&format!(" {}", ShaderKey::Shadow(k).id()));
        }
        s.push('\n');
    }
    s
}

/// Distinct shaders per module, each with the pairs that share it, for `list` and `check`.
pub(crate) fn print_sharing(entries: &[CatalogEntry]) {
    let mut modules: Vec<&str> = entries.iter().map(|e| e.module()).collect();
    modules.dedup();
    for m in modules {
        let of: Vec<&CatalogEntry> = entries.iter().filter(|e| e.module() == m).collect();
        say!("  {m}: {} distinct shader(s)", of.len());
        for e in of {
            if e.users.is_empty() {
                say!("    {}", e.id());
            } else {
                say!(
                    "    {} ← {} pair(s): {}",
                    e.id(),
                    e.users.len(),
                    e.users.join(", ")
                );
            }
        }
    }
}
