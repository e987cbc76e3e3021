//! `nimbus diff OLD NEW`: which shaders (keys) and targets changed between two emitted folders,
//! or two git revisions of the Nimbus checkout the command runs in, with the WGSL diff of each changed key, so a reviewer
//! sees at a glance what a model edit touches.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use nimbus_codegen::MARKER_FILE;

use crate::diff_revision::emit_revision;
use crate::emit::KEYS_FILE;
use similar::TextDiff;

/// The files of an emitted folder, by name.
fn files_of(dir: &Path) -> Result<BTreeMap<String, Vec<u8>>, Box<dyn std::error::Error>> {
    if !dir.join(MARKER_FILE).is_file() {
        return Err(format!(
            "`{}` is not a folder written by `nimbus emit` (no {MARKER_FILE})",
            dir.display()
        )
        .into());
    }
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with("nimbus-") || !entry.file_type()?.is_file() {
            // Nimbus's own files (the manifest, the key table, an ownership record), not shaders.
            continue;
        }
        out.insert(name, std::fs::read(entry.path())?);
    }
    Ok(out)
}

/// The shader's part of a file name and the target's (`wgsl`, `fs_main.es300.frag`,
/// `fs_main.hlsl.json`...), split from the right so that ids holding dots (older emits named
/// files `clouds.<variant>.fs_main.spv`) stay whole.
fn split(name: &str) -> (String, String) {
    let base = name.strip_suffix(".json").unwrap_or(name);
    let json = if base.len() < name.len() { ".json" } else { "" };
    if let Some(id) = base.strip_suffix(".wgsl") {
        return (id.to_string(), format!("wgsl{json}"));
    }
    // `<id>.<entry>.<ext>` or `<id>.<entry>.<version>.<stage>` (GLSL).
    let glsl = [".es300.", ".450."].iter().any(|v| base.contains(v));
    let parts = if glsl { 3 } else { 2 };
    let mut rest = base;
    for _ in 0..parts {
        match rest.rsplit_once('.') {
            Some((head, _)) => rest = head,
            None => return (name.to_string(), String::new()),
        }
    }
    (
        rest.to_string(),
        format!("{}{json}", &base[rest.len() + 1..]),
    )
}

pub(crate) fn run(old: &Path, new: &Path, quiet: bool) -> Result<(), Box<dyn std::error::Error>> {
    let scratch = tempfile::tempdir()?;
    let folder = |p: &Path| -> Result<PathBuf, Box<dyn std::error::Error>> {
        if p.is_dir() {
            Ok(p.to_path_buf())
        } else {
            // Only a revision needs git, a checkout and cargo: two folders compare without.
            Ok(emit_revision(&p.to_string_lossy(), scratch.path())?)
        }
    };
    let (old_dir, new_dir) = (folder(old)?, folder(new)?);
    let (a, b) = (files_of(&old_dir)?, files_of(&new_dir)?);
    let ids: BTreeSet<String> = a.keys().chain(b.keys()).map(|n| split(n).0).collect();
    let (mut changed, mut added, mut removed) = (Vec::new(), Vec::new(), Vec::new());
    for id in &ids {
        let of = |m: &BTreeMap<String, Vec<u8>>| -> BTreeMap<String, Vec<u8>> {
            m.iter()
                .filter(|(n, _)| &split(n).0 == id)
                .map(|(n, v)| (split(n).1, v.clone()))
                .collect()
        };
        let (x, y) = (of(&a), of(&b));
        if x.is_empty() {
            added.push(id.clone());
        } else if y.is_empty() {
            removed.push(id.clone());
        } else {
            let targets: Vec<String> = x
                .keys()
                .chain(y.keys())
                .collect::<BTreeSet<_>>()
                .into_iter()
                .filter(|t| x.get(*t) != y.get(*t))
                .cloned()
                .collect();
            if !targets.is_empty() {
                changed.push((
                    id.clone(),
                    targets,
                    x.get("wgsl").cloned(),
                    y.get("wgsl").cloned(),
                ));
            }
        }
    }
    say!(
        "{} shader(s) compared: {} changed, {} added, {} removed",
        ids.len(),
        changed.len(),
        added.len(),
        removed.len()
    );
    let table = |d: &Path| std::fs::read(d.join(KEYS_FILE)).ok();
    if table(&old_dir) != table(&new_dir) {
        say!("the genus × preset table ({KEYS_FILE}: keys and uniform values) changed");
    }
    for id in &added {
        say!("added    {id}");
    }
    for id in &removed {
        say!("removed  {id}");
    }
    for (id, targets, _, _) in &changed {
        say!("changed  {id}  [{}]", targets.join(", "));
    }
    if !quiet {
        for (id, _, x, y) in &changed {
            let (Some(x), Some(y)) = (x, y) else { continue };
            let (x, y) = (String::from_utf8_lossy(x), String::from_utf8_lossy(y));
            say!();
            say_part!(
                "{}",
                TextDiff::from_lines(x.as_ref(), y.as_ref())
                    .unified_diff()
                    .context_radius(3)
                    .header(&format!("{id}.wgsl (old)"), &format!("{id}.wgsl (new)"))
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::split;

    #[test]
    fn file_names_split_into_shader_and_target() {
        let id = "clouds-detail-turb-o8-dual-g1";
        for (file, target) in [
            (format!("{id}.wgsl"), "wgsl"),
            (format!("{id}.fs_main.es300.frag"), "fs_main.es300.frag"),
            (
                format!("{id}.fs_main.es300.frag.json"),
                "fs_main.es300.frag.json",
            ),
            (format!("{id}.vs_main.450.vert"), "vs_main.450.vert"),
            (format!("{id}.fs_main.hlsl"), "fs_main.hlsl"),
            (format!("{id}.fs_main.metal.json"), "fs_main.metal.json"),
            (format!("{id}.fs_main.spv"), "fs_main.spv"),
        ] {
            assert_eq!(split(&file), (id.to_string(), target.to_string()), "{file}");
        }
        // Older emits put dots in the id.
        assert_eq!(
            split("clouds.cumulus.high.fs_main.spv"),
            ("clouds.cumulus.high".to_string(), "fs_main.spv".to_string())
        );
    }
}
