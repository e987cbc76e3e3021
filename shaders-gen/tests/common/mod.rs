//! Helpers shared by the command-line tests: run the `nimbus` binary, read its output, find the
//! example data, and decide whether GPU work can run here.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `nimbus` with `args` and extra environment variables.
pub fn nimbus_env(args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_nimbus"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run nimbus")
}

/// Runs `nimbus` with `args`.
pub fn nimbus(args: &[&str]) -> std::process::Output {
    nimbus_env(args, &[])
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A path under the repository's examples/.
pub fn examples(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(rel)
        .display()
        .to_string()
}

/// Whether an adapter exists; without one, GPU tests print why they skip (and fail under
/// NIMBUS_REQUIRE_GPU=1, which CI sets).
pub fn have_gpu() -> bool {
    let ok = nimbus_runtime::Gpu::new().is_ok();
    if !ok {
        assert!(
            !std::env::var("NIMBUS_REQUIRE_GPU").is_ok_and(|v| v == "1"),
            "NIMBUS_REQUIRE_GPU=1 but no adapter"
        );
        eprintln!("SKIPPED: no GPU adapter, so no GPU work to check");
    }
    ok
}

/// Runs `nimbus` with `args` and a folder the user made (holding a file of theirs, under
/// `parent`) as the last argument: the command must fail and leave the folder as it was.
pub fn refuses_a_foreign_folder(args: &[&str], parent: &Path) {
    let mine = parent.join("mine");
    std::fs::create_dir(&mine).expect("mkdir");
    std::fs::write(mine.join("notes.txt"), "mine").expect("write");
    let before = tree(&mine);
    let o = nimbus(&[args, &[mine.to_str().expect("utf8")]].concat());
    assert!(!o.status.success(), "replaced a foreign folder");
    assert_eq!(tree(&mine), before, "the user's folder changed");
}

/// Every file under `dir` with its bytes, and every folder (as `name/`), by relative path:
/// what a test compares to show a folder unchanged, or equal to another.
pub fn tree(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read dir").flatten() {
            let p = e.path();
            let rel = p.strip_prefix(dir).expect("prefix").display().to_string();
            if p.is_dir() {
                out.insert(format!("{rel}/"), Vec::new());
                stack.push(p);
            } else {
                out.insert(rel, std::fs::read(&p).expect("read file"));
            }
        }
    }
    out
}

/// Whether python3 runs `check` (imports of the packages `.ci/install-deps` installs from
/// tools/requirements.txt); without them a test prints why it skips (`what` is missing), and
/// fails under NIMBUS_REQUIRE_TOOLS=1, which CI sets.
pub fn have_python(check: &str, what: &str) -> bool {
    let ok = Command::new("python3")
        .args(["-c", check])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            !std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1"),
            "NIMBUS_REQUIRE_TOOLS=1 but python3 with {what} is missing (pip install -r tools/requirements.txt)"
        );
        eprintln!("SKIPPED: python3 with {what} is missing");
    }
    ok
}

/// The browser tests' folder (page, driver scripts, node_modules).
pub fn browser_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../browser")
}

fn chromium() -> PathBuf {
    std::env::var_os("CHROMIUM").map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from)
}

/// Why the browser tests cannot run here, if they cannot.
pub fn missing_browser() -> Option<String> {
    if Command::new("node").arg("--version").output().is_err() {
        return Some("node is not installed".into());
    }
    if !browser_dir().join("node_modules/playwright-core").is_dir()
        || !browser_dir().join("node_modules/three").is_dir()
    {
        return Some("browser/node_modules is missing: run `npm ci` in browser/".into());
    }
    if !chromium().is_file() {
        return Some(format!(
            "{} is missing: apt-get install chromium",
            chromium().display()
        ));
    }
    None
}

/// An image file as 8-bit RGB.
pub fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// Mean absolute difference of two images' channels (of 255).
pub fn mean_difference(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    let sum: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    sum as f64 / a.as_raw().len() as f64
}

/// Emits the `engine` package of `genus` at `quality` with `toggles` enabled into `out`,
/// asserting that `nimbus emit` succeeds.
pub fn emit_package(engine: &str, genus: &str, quality: &str, toggles: &[&str], out: &Path) {
    let mut args = vec![
        "emit",
        "--engine",
        engine,
        "--genus",
        genus,
        "--quality",
        quality,
    ];
    for t in toggles {
        args.extend(["--enable", t]);
    }
    args.extend(["-o", out.to_str().expect("utf-8 path")]);
    let o = nimbus(&args);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
}

/// Renders `package` in Chromium through `browser/render.mjs` with the page's `args`
/// (`key=value`) into `png`, asserting the page ran and logged nothing; returns the page's log
/// (`<png>.log.json`: renderer, problems and any published values).
pub fn render_page(package: &Path, png: &Path, args: &[String]) -> String {
    let o = Command::new("node")
        .current_dir(browser_dir())
        .arg("render.mjs")
        .arg(package)
        .arg(png)
        .args(args)
        .output()
        .expect("runs node");
    let log = std::fs::read_to_string(format!("{}.log.json", png.display())).unwrap_or_default();
    assert!(
        o.status.success(),
        "{}: the page failed or logged: {}{}\n{log}",
        png.display(),
        text(&o.stdout),
        text(&o.stderr)
    );
    println!("{}: {}", png.display(), text(&o.stdout).trim());
    log
}

/// Emits `engine`'s package for `scene_file` into `package`, failing the test with nimbus's
/// message when it cannot.
pub fn emit_scene(engine: &str, scene_file: &Path, package: &Path) {
    let o = nimbus(&[
        "emit",
        "--engine",
        engine,
        "--scene",
        scene_file.to_str().expect("utf8"),
        "-o",
        package.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "emit {engine}: {}", text(&o.stderr));
}
