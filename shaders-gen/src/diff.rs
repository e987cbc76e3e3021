//! `nimbus diff OLD NEW`: which shaders (keys) and targets changed between two emitted folders,
//! or two git revisions of the project, with the WGSL diff of each changed key, so a reviewer
//! sees at a glance what a model edit touches.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use nimbus_codegen::MARKER_FILE;
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
        if name == MARKER_FILE || !entry.file_type()?.is_file() {
            continue;
        }
        out.insert(name, std::fs::read(entry.path())?);
    }
    Ok(out)
}

/// `clouds-detail-…-g1` and the target's part of a file name (`wgsl`, `fs_main.es300.frag`...).
fn split(name: &str) -> (String, String) {
    match name.split_once('.') {
        Some((id, rest)) => (id.to_string(), rest.to_string()),
        None => (name.to_string(), String::new()),
    }
}

/// Emits every shader of the project at git revision `rev` into a fresh folder, by running
/// this command's `emit` from a worktree of that revision (sharing this build's target
/// folder, so only what changed is rebuilt).
fn emit_revision(rev: &str, scratch: &Path) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let tree = scratch.join(format!("tree-{}", rev.replace('/', "_")));
    let out = scratch.join(format!("emit-{}", rev.replace('/', "_")));
    let status = Command::new("git")
        .args(["worktree", "add", "--detach", "--force"])
        .arg(&tree)
        .arg(rev)
        .status()?;
    if !status.success() {
        return Err(format!("`{rev}` is neither an emitted folder nor a git revision").into());
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    let status = Command::new("cargo")
        .current_dir(&tree)
        .env("CARGO_TARGET_DIR", target)
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "nimbus-cli",
            "--",
            "emit",
            "-t",
            "all",
            "-o",
        ])
        .arg(&out)
        .status();
    let _ = Command::new("git")
        .args(["worktree", "remove", "--force"])
        .arg(&tree)
        .status();
    if !status?.success() {
        return Err(format!("emitting revision `{rev}` failed").into());
    }
    Ok(out)
}

pub(crate) fn run(old: &Path, new: &Path, quiet: bool) -> Result<(), Box<dyn std::error::Error>> {
    let scratch = tempfile::tempdir()?;
    let folder = |p: &Path| -> Result<PathBuf, Box<dyn std::error::Error>> {
        if p.is_dir() {
            Ok(p.to_path_buf())
        } else {
            emit_revision(&p.to_string_lossy(), scratch.path())
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
    println!(
        "{} shader(s) compared: {} changed, {} added, {} removed",
        ids.len(),
        changed.len(),
        added.len(),
        removed.len()
    );
    for id in &added {
        println!("added    {id}");
    }
    for id in &removed {
        println!("removed  {id}");
    }
    for (id, targets, _, _) in &changed {
        println!("changed  {id}  [{}]", targets.join(", "));
    }
    if !quiet {
        for (id, _, x, y) in &changed {
            let (Some(x), Some(y)) = (x, y) else { continue };
            let (x, y) = (String::from_utf8_lossy(x), String::from_utf8_lossy(y));
            println!();
            print!(
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
