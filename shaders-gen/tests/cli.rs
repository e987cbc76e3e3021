//! The `nimbus` command as a user runs it.

mod common;

use common::{nimbus, text};

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

#[test]
fn a_bad_genus_file_names_file_field_and_reason_and_nothing_is_emitted() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let data = tmp.path().join("data");
    std::fs::create_dir_all(data.join("genera")).expect("mkdir");
    std::fs::write(
        data.join("genera/bad.toml"),
        "name = \"bad\"\ndescription = \"x\"\n[[layers]]\naltitude = 100.0\nheight = -4.0\n",
    )
    .expect("write");
    let out = tmp.path().join("out");
    let o = nimbus(&[
        "emit",
        "--data",
        data.to_str().expect("utf8"),
        "--genus",
        "bad",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(!o.status.success());
    let err = text(&o.stderr);
    assert!(
        err.contains("bad.toml") && err.contains("layers[0].height") && err.contains("≥ 0"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn emit_genus_quality_and_toggles() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("clouds");
    let o = nimbus(&[
        "emit",
        "--genus",
        "cumulus",
        "--quality",
        "high",
        "--disable",
        "haze",
        "--target",
        "wgsl,glsl-es300",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let wgsl = std::fs::read_to_string(out.join("clouds.cumulus.high-haze.wgsl")).expect("wgsl");
    assert!(wgsl.contains("fn march_clouds") && !wgsl.contains("haze_opacity"));
    assert!(
        out.join("clouds.cumulus.high-haze.fs_main.es300.frag")
            .is_file()
    );
    let o = nimbus(&[
        "emit",
        "--genus",
        "cumulus",
        "--quality",
        "extreme",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("unknown quality preset `extreme`"));
}

fn example_scene(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../examples/scenes/{name}.toml"))
        .display()
        .to_string()
}

#[test]
fn explain_prints_each_effect_with_its_reason_and_the_variant() {
    let o = nimbus(&["explain", &example_scene("twilight-cirrus")]);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for line in [
        "haze                     out  haze density is 0",
        "shadows                  out  sun -4° (below the horizon): nothing to shadow",
        "shape-detail             out  every layer's shape-detail amount is 0",
        "turbulence               out  turbulent displacement is 0",
        "shadow-map-pass          out  nothing samples it: no pass, no texture",
        "powder                   in   on in the `high` preset (no scene rule)",
        "variant: cirrus.high-shape-detail-turbulence-light-shafts-haze-shadows",
    ] {
        assert!(out.contains(line), "missing `{line}` in\n{out}");
    }
}

#[test]
fn emit_and_explain_agree_on_the_scene_variant() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let o = nimbus(&[
        "emit",
        "--scene",
        &example_scene("above-the-deck"),
        "-t",
        "wgsl",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let name = "stratocumulus.high-light-shafts-ground-bounce";
    let clouds = std::fs::read_to_string(out.join(format!("clouds.{name}.wgsl"))).expect("clouds");
    assert!(out.join(format!("cloud_shadow.{name}.wgsl")).is_file());
    // Shafts and ground bounce are out: their code is not in the shader.
    assert!(!clouds.contains("fn shadow_length"));
    assert!(clouds.contains("fn shadow_texel"), "shadows stay in");
    let e = text(&nimbus(&["explain", &example_scene("above-the-deck")]).stdout);
    assert!(e.contains(&format!("variant: {name}")), "{e}");
}
