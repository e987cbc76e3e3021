//! The `nimbus` command as a user runs it.

use std::process::Command;

fn nimbus(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_nimbus"))
        .args(args)
        .output()
        .expect("run nimbus")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn emit_writes_every_target_and_a_manifest() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let o = nimbus(&["emit", "preview/hg", "-o", out.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for name in [
        "preview.hg.wgsl",
        "preview.hg.fs_main.es300.frag",
        "preview.hg.fs_main.es300.frag.json",
        "preview.hg.vs_main.450.vert",
        "preview.hg.fs_main.hlsl",
        "preview.hg.fs_main.metal",
        "preview.hg.fs_main.spv",
        "nimbus-manifest.txt",
    ] {
        assert!(
            out.join(name).is_file(),
            "{name} missing; stdout:\n{}",
            text(&o.stdout)
        );
    }
}

#[test]
fn an_unknown_target_fails_cleanly_and_writes_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let o = nimbus(&["emit", "-t", "wgsl,dx9", "-o", out.to_str().expect("utf8")]);
    assert!(!o.status.success());
    let err = text(&o.stderr);
    assert!(err.contains("unknown target `dx9`"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "nothing may be written on error");
}

#[test]
fn an_unknown_variant_fails_cleanly_and_writes_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let o = nimbus(&["emit", "cumulus/ultra", "-o", out.to_str().expect("utf8")]);
    assert!(!o.status.success());
    let err = text(&o.stderr);
    assert!(
        err.contains("`cumulus/ultra`") && err.contains("preview/hg"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn list_and_check_describe_and_validate_everything() {
    let o = nimbus(&["list"]);
    assert!(o.status.success());
    let s = text(&o.stdout);
    for want in [
        "preview/hg",
        "preview/dual_lobe",
        "glsl-es300",
        "spirv",
        "msl",
        "hlsl",
    ] {
        assert!(s.contains(want), "{want} missing from:\n{s}");
    }
    let o = nimbus(&["check", "--no-external"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("0 failure(s)"));
}
