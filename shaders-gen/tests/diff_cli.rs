//! `nimbus diff` names exactly the keys a one-line model edit changes.
//!
//! The edit: the clamp of the sun's optical-air-mass exponent in `sun_attenuation` (one literal,
//! `.min(20.0)` → `.min(25.0)`), applied to the recorded IR of every shader before generation,
//! as if that line of dsl/clouds/src/model/march.rs had been changed and re-emitted. Only
//! shaders whose key has `accurate-sun-sky-light` call that function, so exactly those must be
//! reported, and every other shader must be reported unchanged.

mod common;

use common::{nimbus, text};
use nimbus_clouds::catalog::{ShaderKey, catalog, cloud_catalog};
use nimbus_clouds::{CloudLibrary, Toggle};
use nimbus_codegen::{EmitExtras, Target, emit, generate};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::ir::{ExprKind, Literal, Module};
use nimbus_output::Overwrite;

/// The one-line edit, on a recorded module; returns whether the module had the line.
fn edit_sun_attenuation(m: &mut Module) -> bool {
    let mut hit = false;
    for f in m
        .functions
        .iter_mut()
        .filter(|f| f.name == "sun_attenuation")
    {
        for e in &mut f.exprs {
            if e.kind == ExprKind::Literal(Literal::f32(20.0)) {
                e.kind = ExprKind::Literal(Literal::f32(25.0));
                hit = true;
            }
        }
    }
    hit
}

#[test]
fn diff_names_exactly_the_keys_a_one_line_model_edit_changes() {
    let lib = CloudLibrary::load(std::path::Path::new(&common::examples(""))).expect("library");
    let mut entries = catalog();
    entries.extend(cloud_catalog(&lib));
    let (mut before, mut after) = (Vec::new(), Vec::new());
    let mut expected = Vec::new();
    for e in &entries {
        let module = e.record().expect("record");
        before.push(generate(module.clone(), &e.variant(), &[Target::Wgsl]).expect("old"));
        let mut edited = module;
        if edit_sun_attenuation(&mut edited) {
            expected.push(e.id());
        }
        after.push(generate(edited, &e.variant(), &[Target::Wgsl]).expect("new"));
    }
    // What the key says, independently of the IR: the cloud keys with accurate sun/sky light.
    let mut by_key: Vec<String> = entries
        .iter()
        .filter(|e| matches!(e.key, ShaderKey::Clouds(k) if Toggle::AccurateSunSkyLight.get(&k.features)))
        .map(|e| e.id())
        .collect();
    by_key.sort();
    expected.sort();
    assert_eq!(
        expected, by_key,
        "the edited function is reached by exactly these keys"
    );
    assert!(!expected.is_empty() && expected.len() < entries.len());

    let dir = tempfile::tempdir().expect("tmp");
    let (old, new) = (dir.path().join("old"), dir.path().join("new"));
    emit(&before, &EmitExtras::default(), &old, Overwrite::OwnOnly).expect("emit old");
    emit(&after, &EmitExtras::default(), &new, Overwrite::OwnOnly).expect("emit new");
    let out = nimbus(&[
        "diff",
        &old.display().to_string(),
        &new.display().to_string(),
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut reported: Vec<String> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("changed  "))
        .map(|l| l.split_whitespace().next().unwrap_or("").to_string())
        .collect();
    reported.sort();
    assert_eq!(reported, expected, "{stdout}");
    assert!(
        stdout.contains(&format!(
            "{} shader(s) compared: {} changed, 0 added, 0 removed",
            entries.len(),
            expected.len()
        )),
        "{stdout}"
    );
    // The WGSL diff shows the edited line on both sides.
    assert!(
        stdout.contains("-    return exp(min(") && stdout.contains("25.0"),
        "{stdout}"
    );

    // The same folder against itself: nothing changed.
    let same = nimbus(&[
        "diff",
        "-q",
        &old.display().to_string(),
        &old.display().to_string(),
    ]);
    assert!(text(&same.stdout).contains("0 changed, 0 added, 0 removed"));
}

#[test]
fn diff_refuses_a_folder_nimbus_did_not_write() {
    let dir = tempfile::tempdir().expect("tmp");
    let plain = dir.path().join("plain");
    std::fs::create_dir(&plain).expect("dir");
    let out = nimbus(&[
        "diff",
        &plain.display().to_string(),
        &plain.display().to_string(),
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("not a folder written by `nimbus emit`"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn diff_of_revisions_outside_a_checkout_says_what_it_needs() {
    let dir = tempfile::tempdir().expect("tmp");
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_nimbus"));
    c.args(["diff", "-q", "HEAD~1", "HEAD"])
        .current_dir(dir.path())
        // Stops git's search at the temporary folder, should the system's temporary folder
        // itself lie inside a repository.
        .env(
            "GIT_CEILING_DIRECTORIES",
            dir.path().parent().unwrap_or(dir.path()),
        );
    let out = c.output().expect("run nimbus");
    let stderr = text(&out.stderr);
    // The folder as the binary sees it, links resolved.
    let here = dir.path().canonicalize().expect("tmp path");
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Without git on PATH the same sentence says what is needed; with it, where none was found.
    assert!(
        stderr.contains(
            "comparing git revisions needs a Nimbus git checkout as the current directory"
        ) && stderr.contains("or compare two folders written by `nimbus emit`"),
        "{stderr}"
    );
    assert!(
        stderr.contains("git is not on PATH")
            || stderr.contains(&format!("no git checkout at or above {}", here.display())),
        "{stderr}"
    );
}

#[test]
fn diff_of_revisions_outside_nimbus_says_what_it_needs() {
    let dir = tempfile::tempdir().expect("tmp");
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .current_dir(dir.path())
            .output()
    };
    // Only where git is installed: the test above covers a machine without it.
    let Ok(init) = git(&["init", "-q"]) else {
        return;
    };
    assert!(init.status.success(), "{}", text(&init.stderr));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nimbus"))
        .args(["diff", "-q", "HEAD~1", "HEAD"])
        .current_dir(dir.path())
        .output()
        .expect("run nimbus");
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("is not Nimbus's (no shaders-gen/Cargo.toml)")
            && stderr.contains("or compare two folders written by `nimbus emit`"),
        "{stderr}"
    );
}
