//! The `nimbus` command as a user runs it.

mod common;

use common::{nimbus, text};

#[test]
fn emit_writes_every_target_and_a_manifest() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let o = nimbus(&["emit", "preview-hg", "-o", out.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for name in [
        "preview-hg.wgsl",
        "preview-hg.fs_main.es300.frag",
        "preview-hg.fs_main.es300.frag.json",
        "preview-hg.vs_main.450.vert",
        "preview-hg.hlsl",
        "preview-hg.hlsl.json",
        "preview-hg.fs_main.metal",
        "preview-hg.fs_main.spv",
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
    assert!(
        err.contains("invalid value 'dx9'")
            && err.contains("--targets")
            && err.contains("glsl-es300"),
        "{err}"
    );
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
        err.contains("unknown shader `cumulus/ultra`") && err.contains("preview-hg"),
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
        "preview-hg",
        "preview-dual_lobe",
        "clouds: 32 distinct shader(s)",
        "shadow: 21 distinct shader(s)",
        "clouds-detail-turb-shafts-haze-shadows-bounce-diffuse-powder-o1-dual-g1 ← 2 pair(s): cumulus.high, takram-default.high",
        "clouds-detail-turb-shafts-haze-shadows-bounce-diffuse-powder-o1-mie-g1-weather_exponent ← 3 pair(s): altostratus.high, nimbostratus.high, stratus.high",
        "clouds-detail-turb-shafts-haze-shadows-bounce-diffuse-powder-o1-dual-g1-sparse_weather-anvil_shape ← 1 pair(s): cumulonimbus.high",
        "glsl-es300",
        "spirv",
        "msl",
        "hlsl",
    ] {
        assert!(s.contains(want), "{want} missing from:\n{s}");
    }
    let o = nimbus(&["check", "--no-external"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    // 2 previews + resolve + display + sun light + scene shadow + 32 cloud keys + 21 shadow
    // keys + the air table, for 11 genera × 4 presets (genera with their own weather or shape
    // functions, or their own phase function kind, have their own).
    assert!(
        s.contains("60 shader(s),") && s.contains("0 failure(s)"),
        "{s}"
    );
    assert!(
        s.contains("distinct shaders (44 genus × preset pair(s))"),
        "{s}"
    );
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
    // Without haze the shafts have nothing to light: the key drops both.
    let id = "clouds-detail-turb-shadows-bounce-diffuse-powder-o1-dual-g1";
    let wgsl = std::fs::read_to_string(out.join(format!("{id}.wgsl"))).expect("wgsl");
    assert!(wgsl.contains("fn march_clouds") && !wgsl.contains("haze_opacity"));
    assert!(out.join(format!("{id}.fs_main.es300.frag")).is_file());
    assert!(out.join("shadow-detail-turb-g1.wgsl").is_file());
    let manifest = std::fs::read_to_string(out.join("nimbus-manifest.txt")).expect("manifest");
    assert!(
        manifest.contains(&format!(
            "cumulus.high                 {id} shadow-detail-turb-g1"
        )),
        "{manifest}"
    );
    // The pair's uniform values, member by member: the genus' coverage is among them.
    let keys: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("nimbus-keys.json")).expect("keys file"),
    )
    .expect("json");
    let pair = &keys["pairs"][0];
    assert_eq!(pair["pair"], "cumulus.high");
    assert_eq!(pair["clouds"], id);
    let coverage = pair["uniforms"]["members"]
        .as_array()
        .and_then(|m| m.iter().find(|m| m["member"] == "media.coverage"))
        .map(|m| m["value"][0].as_f64().unwrap_or(-1.0));
    let genus = std::fs::read_to_string(common::examples("genera/cumulus.toml")).expect("genus");
    let want: f64 = genus
        .lines()
        .find_map(|l| l.strip_prefix("coverage = "))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .expect("cumulus.toml sets coverage");
    assert!(
        coverage.is_some_and(|c| (c - want).abs() < 1e-6),
        "{coverage:?} vs {want}: {pair}"
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
    let err = text(&o.stderr);
    assert!(
        err.contains("invalid value 'extreme'")
            && err.contains("--quality")
            && err.contains("ultra"),
        "{err}"
    );
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
        "shadows                  out  no layer casts shadows",
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
    // 6.5 km above the deck the view holds three weather tiles: the analysis untiles them.
    let name = "stratocumulus.high-light-shafts-ground-bounce+untiled-weather";
    let id = "clouds-detail-turb-haze-shadows-diffuse-powder-untile-o1-dual-g1-cellular_weather-weather_exponent";
    let clouds = std::fs::read_to_string(out.join(format!("{id}.wgsl"))).expect("clouds");
    assert!(
        out.join("shadow-detail-turb-untile-g1-cellular_weather-weather_exponent.wgsl")
            .is_file()
    );
    // Shafts and ground bounce are out: their code is not in the shader.
    assert!(!clouds.contains("fn shadow_length"));
    assert!(clouds.contains("fn shadow_texel"), "shadows stay in");
    let e = text(&nimbus(&["explain", &example_scene("above-the-deck")]).stdout);
    assert!(e.contains(&format!("variant: {name}")), "{e}");
    assert!(e.contains(&format!("shader: {id}")), "{e}");
    // The genus' weather function is its own choice, reported with the built-in defaults.
    assert!(
        e.contains("weather-function         own  cellular_weather"),
        "{e}"
    );
    assert!(
        e.contains("profile-function         std  linear_profile"),
        "{e}"
    );
}
