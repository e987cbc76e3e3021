//! Genus and scene files: the shipped ones load, and bad ones are refused with an error that
//! names the file, the field and the reason.

use std::path::{Path, PathBuf};

use nimbus_clouds::{CloudLibrary, DataError, MAX_LAYERS, parse_genus};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn the_shipped_library_loads() {
    let lib = CloudLibrary::load(&data_dir()).expect("shipped data is valid");
    for g in [
        "cumulus",
        "stratus",
        "stratocumulus",
        "cumulonimbus",
        "altocumulus",
        "altostratus",
        "nimbostratus",
        "cirrus",
        "cirrostratus",
        "cirrocumulus",
        "takram-default",
    ] {
        assert!(lib.genera.contains_key(g), "genus {g} missing");
    }
    for s in [
        "clear-day",
        "partly-cloudy",
        "overcast",
        "dramatic",
        "sunset",
        "high-cirrus",
        "mackerel-sky",
    ] {
        assert!(lib.scenes.contains_key(s), "scene {s} missing");
    }
    let default = lib.genus("takram-default").expect("default");
    assert_eq!(default.layers.len(), 4);
    assert_eq!(default.layers[2].density_scale, 0.003);
}

const GOOD: &str = r#"
name = "test"
description = "a test genus"
[[layers]]
altitude = 1000.0
height = 500.0
"#;

fn expect_invalid(text: &str, field: &str, reason_part: &str) {
    let file = Path::new("genera/test.toml");
    let err = parse_genus(file, text).expect_err("must be refused");
    let msg = err.to_string();
    match &err {
        DataError::Invalid {
            file: f,
            field: got,
            reason,
        } => {
            assert_eq!(f, file);
            assert_eq!(got, field, "{msg}");
            assert!(
                reason.contains(reason_part),
                "reason `{reason}` lacks `{reason_part}`"
            );
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
    assert!(msg.starts_with("genera/test.toml: "), "{msg}");
}

#[test]
fn a_minimal_genus_is_accepted_with_reference_defaults() {
    let g = parse_genus(Path::new("genera/test.toml"), GOOD).expect("valid");
    assert_eq!(g.layers[0].coverage_filter_width, 0.6);
    assert_eq!(g.layers[0].shape_altering_bias, 0.35);
    assert_eq!(g.coverage, 0.3);
}

#[test]
fn unknown_key() {
    expect_invalid(
        &format!("{GOOD}cloudiness = 3.0\n"),
        "layers[0].cloudiness",
        "unknown field",
    );
    expect_invalid(
        &GOOD.replace("name = \"test\"", "name = \"test\"\nflavour = 1"),
        "flavour",
        "unknown field",
    );
}

#[test]
fn wrong_type() {
    expect_invalid(
        &GOOD.replace("height = 500.0", "height = \"tall\""),
        "layers[0].height",
        "invalid type",
    );
}

#[test]
fn negative_height() {
    expect_invalid(
        &GOOD.replace("height = 500.0", "height = -5.0"),
        "layers[0].height",
        "≥ 0",
    );
}

#[test]
fn nan_value() {
    expect_invalid(
        &GOOD.replace("altitude = 1000.0", "altitude = nan"),
        "layers[0].altitude",
        "finite",
    );
}

#[test]
fn zero_coverage_filter_width() {
    expect_invalid(
        &format!("{GOOD}coverage_filter_width = 0.0\n"),
        "layers[0].coverage_filter_width",
        "divide",
    );
}

#[test]
fn too_many_layers() {
    let mut text = GOOD.to_string();
    for _ in 0..MAX_LAYERS {
        text.push_str("[[layers]]\naltitude = 100.0\nheight = 100.0\n");
    }
    expect_invalid(&text, "layers", "at most 8");
}

#[test]
fn channel_that_does_not_exist() {
    expect_invalid(
        &format!("{GOOD}channel = \"x\"\n"),
        "layers[0].channel",
        "unknown variant",
    );
}

#[test]
fn overflowing_profile_exponent() {
    expect_invalid(
        &format!("{GOOD}density_profile = {{ a = 1.0, b = 200.0, c = 0.0, d = 0.0 }}\n"),
        "layers[0].density_profile.b",
        "finite",
    );
}

#[test]
fn name_must_match_the_file() {
    expect_invalid(
        &GOOD.replace("name = \"test\"", "name = \"other\""),
        "name",
        "file name",
    );
}

#[test]
fn toml_syntax_errors_name_the_line() {
    expect_invalid("name = \"test\"\ndescription = \n", "line 2", "TOML syntax");
}

#[test]
fn a_scene_naming_a_missing_genus_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir_all(tmp.path().join("genera")).expect("mkdir");
    std::fs::create_dir_all(tmp.path().join("scenes")).expect("mkdir");
    std::fs::write(tmp.path().join("genera/test.toml"), GOOD).expect("write");
    std::fs::write(
        tmp.path().join("scenes/foggy.toml"),
        "name = \"foggy\"\ndescription = \"x\"\ngenus = \"fog\"\n",
    )
    .expect("write");
    // The scene is left out and its error kept; the good genus still loads.
    let lib = CloudLibrary::load(tmp.path()).expect("the folder loads");
    assert!(lib.genus("test").is_some());
    assert!(lib.scenes.is_empty());
    let err = lib.problems.first().expect("the scene's problem is kept");
    assert!(
        matches!(err, DataError::UnknownReference { name, .. } if name == "fog"),
        "{err}"
    );
    assert!(err.to_string().contains("foggy.toml"), "{err}");
}
