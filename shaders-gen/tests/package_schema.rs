//! The package description is typed: every engine's `nimbus-package.json` and uniform files
//! validate against the JSON Schemas shipped in the same package (checked by Ajv, a validator
//! independent of the Rust types the schemas are derived from), every binding names a resource
//! the description's `resources` table lists, and the controls (a misspelt resource id, a
//! missing member, a member the schema does not know, a negative offset) are each refused.
//!
//! Needs node and `browser/node_modules` (`npm ci` in browser/).

mod common;

use std::path::Path;
use std::process::Command;

use common::{browser_dir, emit_package, text};
use nimbus_testkit::skip::{browser_tools_present, node_missing};
use serde_json::Value;

/// Ajv's verdict on the package in `dir`: whether every file is valid, and its report.
fn validate(dir: &Path) -> (bool, String) {
    let out = Command::new("node")
        .arg(browser_dir().join("validate-package.mjs"))
        .arg(dir)
        .output()
        .expect("runs node");
    (
        out.status.success(),
        format!("{}{}", text(&out.stdout), text(&out.stderr)),
    )
}

/// A change to one JSON file of a package.
type Mutation = Box<dyn FnOnce(&mut Value)>;

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).expect("reads the file")).expect("JSON")
}

/// A copy of the package's JSON files in `to`, with `change` applied to the file `which`.
fn mutated(from: &Path, to: &Path, which: &str, change: impl FnOnce(&mut Value)) {
    std::fs::create_dir_all(to.join("uniforms")).expect("makes the copy's folders");
    for entry in std::fs::read_dir(from.join("uniforms")).expect("lists uniforms") {
        let entry = entry.expect("an entry");
        std::fs::copy(entry.path(), to.join("uniforms").join(entry.file_name()))
            .expect("copies a uniform file");
    }
    for f in [
        "nimbus-package.json",
        "nimbus-package.schema.json",
        "nimbus-uniforms.schema.json",
    ] {
        std::fs::copy(from.join(f), to.join(f)).expect("copies a file");
    }
    let mut v = read_json(&to.join(which));
    change(&mut v);
    std::fs::write(to.join(which), serde_json::to_vec_pretty(&v).expect("JSON"))
        .expect("writes the mutated file");
}

#[test]
fn every_engine_package_validates_against_its_shipped_schema() {
    let ajv = browser_dir().join("node_modules/ajv/package.json");
    if !browser_tools_present(
        "the package schema test",
        node_missing().or_else(|| {
            (!ajv.is_file())
                .then(|| "browser/node_modules is missing: run `npm ci` in browser/".into())
        }),
    ) {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let cases: [(&str, &[&str]); 6] = [
        ("three", &["scene-depth"]),
        ("webgpu", &[]),
        ("wgpu", &[]),
        ("vulkan", &[]),
        ("unity", &[]),
        ("metal", &[]),
    ];
    for (engine, toggles) in cases {
        let package = dir.path().join(engine);
        emit_package(engine, "cumulus", "low", toggles, &package);
        let (ok, log) = validate(&package);
        assert!(
            ok,
            "{engine}: the package does not match its schema:\n{log}"
        );
        assert!(
            log.matches("\"valid\":true").count() >= 4,
            "{engine}: {log}"
        );

        // Every binding names a resource the table lists, and every listed one is bound.
        let description = read_json(&package.join("nimbus-package.json"));
        let listed: Vec<&str> = description["resources"]
            .as_array()
            .expect("a resources table")
            .iter()
            .filter_map(|r| r["id"].as_str())
            .collect();
        let mut bound = std::collections::BTreeSet::new();
        for pass in description["pairs"]
            .as_array()
            .expect("pairs")
            .iter()
            .flat_map(|p| p["passes"].as_array().expect("passes"))
        {
            for b in pass["bindings"].as_array().expect("bindings") {
                let id = b["holds"]["id"].as_str().expect("a resource id");
                assert!(listed.contains(&id), "{engine}: {id} is not in resources");
                bound.insert(id);
            }
        }
        assert_eq!(
            bound.len(),
            listed.len(),
            "{engine}: {listed:?} vs {bound:?}"
        );
        if engine == "three" {
            assert!(bound.contains("scene_depth"), "{bound:?}");
        }
    }

    // The controls: each mistake alone is refused.
    let package = dir.path().join("webgpu");
    let controls: [(&str, &str, Mutation); 4] = [
        (
            "a misspelt resource id",
            "nimbus-package.json",
            Box::new(|v| {
                v["pairs"][0]["passes"][0]["bindings"][1]["holds"]["id"] = "wether".into()
            }),
        ),
        (
            "a missing member",
            "nimbus-package.json",
            Box::new(|v| {
                v.as_object_mut().expect("an object").remove("targets");
            }),
        ),
        (
            "a member the schema does not know",
            "nimbus-package.json",
            Box::new(|v| v["pairs"][0]["passes"][1]["colour"] = "red".into()),
        ),
        (
            "a negative offset",
            "uniforms/cumulus.low.json",
            Box::new(|v| v["members"][0]["offset"] = (-4).into()),
        ),
    ];
    for (i, (what, file, change)) in controls.into_iter().enumerate() {
        let copy = dir.path().join(format!("control-{i}"));
        mutated(&package, &copy, file, change);
        let (ok, log) = validate(&copy);
        let first: String = log.chars().take(240).collect();
        println!("control ({what}): {first}");
        assert!(!ok, "the schema accepted {what}:\n{log}");
    }
}
