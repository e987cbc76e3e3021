//! The crate graph keeps its one-way arrows and the language knows nothing of clouds:
//! `nimbus-dsl` (and its macros) depend on no other Nimbus crate and name no cloud concept;
//! codegen depends on no cloud crate and no GPU API; the runtime pulls in no test kit; and the
//! runtime never names a WGSL binding (it binds by the typed binding enums and by slot).

use std::path::{Path, PathBuf};

use nimbus_clouds::catalog::{ShaderKey, cloud_catalog};
use nimbus_clouds::{CloudLibrary, Features, Quality};
use nimbus_codegen::{Target, generate_variant};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `[dependencies]` table of a crate's manifest, as text.
fn dependencies(krate: &str) -> String {
    let text = std::fs::read_to_string(root().join(krate).join("Cargo.toml")).expect("manifest");
    let start = text.find("[dependencies]").map_or(text.len(), |i| i);
    let rest = &text[start..];
    let end = rest[1..].find("\n[").map_or(rest.len(), |i| i + 1);
    rest[..end].to_string()
}

fn sources(dir: &Path) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("dir").flatten() {
        let p = entry.path();
        if p.is_dir() {
            out.extend(sources(&p));
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push((p.clone(), std::fs::read_to_string(&p).expect("read")));
        }
    }
    out
}

#[test]
fn dependencies_point_one_way() {
    for (krate, forbidden) in [
        (
            "dsl",
            &[
                "nimbus-clouds",
                "nimbus-codegen",
                "nimbus-runtime",
                "nimbus-testkit",
                "naga",
                "wgpu",
            ][..],
        ),
        (
            "dsl/macros",
            &["nimbus-clouds", "nimbus-codegen", "nimbus-runtime"][..],
        ),
        (
            "codegen",
            &["nimbus-clouds", "nimbus-runtime", "nimbus-testkit", "wgpu"][..],
        ),
        (
            "dsl/clouds",
            &[
                "nimbus-codegen",
                "nimbus-runtime",
                "nimbus-testkit",
                "naga",
                "wgpu",
            ][..],
        ),
        ("runtime", &["nimbus-testkit", "image-compare", "rayon"][..]),
    ] {
        let deps = dependencies(krate);
        for f in forbidden {
            assert!(
                !deps.lines().any(|l| l.trim_start().starts_with(f)),
                "{krate} depends on {f}:\n{deps}"
            );
        }
    }
}

#[test]
fn the_language_names_no_cloud_concept() {
    let words = [
        "cloud", "genus", "cumulus", "cirrus", "stratus", "weather", "scatter", "march", "phase",
        "sun", "haze", "density",
    ];
    let mut checked = 0;
    for dir in ["dsl/src", "dsl/macros/src"] {
        for (path, text) in sources(&root().join(dir)) {
            checked += 1;
            let lower = text.to_lowercase();
            for w in words {
                // Whole words (and their plurals), so `sunk` or `summary` do not count.
                let hit = lower.match_indices(w).any(|(i, _)| {
                    let before = lower[..i]
                        .chars()
                        .last()
                        .is_none_or(|c| !c.is_alphanumeric());
                    let after: String = lower[i + w.len()..].chars().take(2).collect();
                    let after_ok = after.chars().next().is_none_or(|c| !c.is_alphanumeric())
                        || after.starts_with('s')
                            && after.chars().nth(1).is_none_or(|c| !c.is_alphanumeric());
                    before && after_ok
                });
                assert!(!hit, "{} names `{w}`", path.display());
            }
        }
    }
    assert!(checked > 20, "only {checked} files read");
}

#[test]
fn the_runtime_names_no_wgsl_binding() {
    let lib = CloudLibrary::load(&root().join("examples")).expect("data");
    let mut all = Features::default();
    for &t in nimbus_clouds::Toggle::ALL {
        t.set(&mut all, true);
    }
    let genus = lib.genus("cumulus").expect("cumulus");
    let key = nimbus_clouds::catalog::assign(genus, Quality::High, all).clouds;
    let mut shaders = vec![ShaderKey::Clouds(key), ShaderKey::Resolve];
    shaders.extend(key.shadow_key().map(ShaderKey::Shadow));
    let mut names = Vec::new();
    for s in &shaders {
        let g = generate_variant(s, &[Target::Wgsl]).expect("generate");
        names.extend(g.bindings.iter().map(|b| b.name.clone()));
    }
    assert!(names.len() >= 10, "{names:?}");
    assert!(!cloud_catalog(&lib).is_empty());
    // A name string in a comparison, a match arm or a lookup is a binding chosen by name
    // (pass labels such as "clouds" may share a name and are not).
    for (path, text) in sources(&root().join("runtime/src")) {
        for n in &names {
            let quoted = format!("\"{n}\"");
            for (i, _) in text.match_indices(&quoted) {
                let before = text[..i].trim_end();
                let after = text[i + quoted.len()..].trim_start();
                let chosen = before.ends_with("==")
                    || before.ends_with('(')
                        && !before.ends_with("push(")
                        && !before.ends_with("Some(")
                    || after.starts_with("=>")
                    || after.starts_with("==")
                    || after.starts_with('|');
                assert!(
                    !chosen,
                    "{} chooses a binding by its WGSL name `{n}`: …{}…",
                    path.display(),
                    &text[i.saturating_sub(30)..(i + quoted.len() + 10).min(text.len())]
                );
            }
        }
    }
}
