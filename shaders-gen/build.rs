//! Embeds the example data (genera, scenes, views, gallery scenes) in the binary, so an installed `nimbus`
//! (`cargo install --path shaders-gen`) has its genera and scenes with no source tree beside
//! it. Each file becomes `(relative path, contents)` in `$OUT_DIR/examples.rs`.

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let mut entries = String::new();
    for sub in ["genera", "scenes", "views", "gallery"] {
        let dir = root.join(sub);
        println!("cargo::rerun-if-changed={}", dir.display());
        let Ok(read) = std::fs::read_dir(&dir) else {
            println!(
                "cargo::warning=no {} to embed: the built nimbus will have no built-in {sub}",
                dir.display()
            );
            continue;
        };
        let mut files: Vec<_> = read
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        files.sort();
        for f in files {
            println!("cargo::rerun-if-changed={}", f.display());
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            let (Some(name), Ok(abs)) = (name, f.canonicalize()) else {
                continue;
            };
            let _ = writeln!(
                entries,
                "    ({:?}, include_str!({:?})),",
                format!("{sub}/{name}"),
                abs.display().to_string()
            );
        }
    }
    let code = format!(
        "/// The example data folder's files: (path relative to it, contents).\n\
         pub(crate) const EXAMPLES: &[(&str, &str)] = &[\n{entries}];\n"
    );
    let out =
        Path::new(&std::env::var("OUT_DIR").unwrap_or_else(|_| ".".into())).join("examples.rs");
    if let Err(e) = std::fs::write(&out, code) {
        println!("cargo::error=cannot write {}: {e}", out.display());
    }
}
