//! Genus functions from data: a file names them, the key carries them, bad names are refused
//! with the file and field, and a registered name means one function.

use std::path::Path;

use glam::Vec4;
use nimbus_clouds::functions::{RegisterError, lookup};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::genus_fns::{
    ANVIL_SHAPE, CELLULAR_WEATHER, EXPONENTIAL_PROFILE, LINEAR_PROFILE, UNIT_EXPONENT,
    WEATHER_EXPONENT, exponential_profile, linear_profile,
};
use nimbus_clouds::model::layers::LayerGroup;
use nimbus_clouds::{DataError, HeightFn, Quality, height_fn, parse_genus, register};
use nimbus_dsl::prelude::*;

const BASE: &str = r#"
name = "tower"
description = "test"
[[layers]]
channel = "r"
altitude = 1000.0
height = 8000.0
"#;

fn genus_with(functions: &str) -> Result<nimbus_clouds::Genus, DataError> {
    let text = BASE.replace("[[layers]]", &format!("{functions}\n[[layers]]"));
    parse_genus(Path::new("genera/tower.toml"), &text)
}

#[test]
fn a_file_names_built_in_functions_and_the_key_carries_them() {
    let plain = genus_with("").expect("plain");
    let tower =
        genus_with(r#"functions = { shape = "anvil_shape", weather = "cellular_weather" }"#)
            .expect("tower");
    assert_eq!(tower.functions.shape, ANVIL_SHAPE);
    assert_eq!(tower.functions.weather, CELLULAR_WEATHER);
    assert_eq!(tower.functions.profile, LINEAR_PROFILE);
    let key = |g| CloudVariant::new(g, Quality::High, Quality::High.features()).key;
    let (a, b) = (key(&plain), key(&tower));
    assert_ne!(a, b, "different functions, different keys");
    assert!(!a.name().contains("anvil"), "{}", a.name());
    assert!(
        b.name().ends_with("-cellular_weather-anvil_shape"),
        "{}",
        b.name()
    );
    let shadow = b.shadow_key().expect("shadow pass");
    assert_ne!(
        Some(shadow),
        a.shadow_key(),
        "the shadow pass has the density's functions"
    );
    assert!(shadow.name().contains("anvil_shape"), "{}", shadow.name());
    // A height function serves as a profile too, tagged with its slot.
    let profile = genus_with(r#"functions = { profile = "anvil_shape" }"#).expect("profile");
    assert!(key(&profile).name().ends_with("-profile_anvil_shape"));
}

/// The reference profile's two forms: a genus gets the exponential one exactly where a layer
/// needs it (its `a` and `b` both non-zero), whichever of the two its file names, and the
/// linear one computes the same numbers, to the bit, for every layer it is chosen for. The
/// weather exponent's power likewise only where a layer's exponent is not 1.
#[test]
fn the_profile_and_the_weather_exponent_take_their_general_form_only_where_a_layer_needs_it() {
    let layer = |a: f32, b: f32| {
        format!(
            "[[layers]]\nchannel = \"g\"\naltitude = 500.0\nheight = 900.0\ndensity_profile = {{ a = {a:?}, b = {b:?}, c = 0.6, d = 0.4 }}\n"
        )
    };
    let key = |functions: &str, layers: &str| {
        let g = genus_with(&format!("{functions}\n{layers}")).expect("genus");
        CloudVariant::new(&g, Quality::Low, Quality::Low.features()).key
    };
    for named in [
        "",
        r#"functions = { profile = "exponential_profile" }"#,
        r#"functions = { profile = "linear_profile" }"#,
    ] {
        for (a, b) in [(0.0, 0.0), (0.0, 3.0), (0.7, 0.0)] {
            let k = key(named, &layer(a, b));
            assert_eq!(k.functions.profile, LINEAR_PROFILE, "{named:?} a {a} b {b}");
            assert!(!k.name().contains("profile"), "{}", k.name());
        }
        let k = key(named, &format!("{}{}", layer(0.0, 3.0), layer(0.5, -2.0)));
        assert_eq!(
            k.functions.profile, EXPONENTIAL_PROFILE,
            "{named:?}: the second layer's term varies"
        );
        assert!(k.name().ends_with("-exponential_profile"), "{}", k.name());
    }
    // The weather exponent likewise: the power only where a layer's exponent is not 1.
    let exponent = |e: f32| {
        format!(
            "[[layers]]\nchannel = \"b\"\naltitude = 500.0\nheight = 900.0\nweather_exponent = {e:?}\n"
        )
    };
    let unit = key("", &exponent(1.0));
    assert_eq!(unit.functions.exponent, UNIT_EXPONENT);
    assert!(!unit.name().contains("exponent"), "{}", unit.name());
    let powered = key("", &exponent(0.8));
    assert_eq!(powered.functions.exponent, WEATHER_EXPONENT);
    assert!(
        powered.name().ends_with("-weather_exponent"),
        "{}",
        powered.name()
    );
    assert_eq!(
        powered.shadow_key().map(|k| k.functions.exponent),
        Some(WEATHER_EXPONENT),
        "the shadow pass raises the weather alike"
    );
    // A file cannot choose it: it follows from the layers.
    assert!(genus_with(r#"functions = { exponent = "unit_exponent" }"#).is_err());

    // Another profile is the genus' own choice, left as it is.
    let own = key(
        r#"functions = { profile = "anvil_shape" }"#,
        &layer(0.0, 0.0),
    );
    assert_eq!(own.functions.profile, ANVIL_SHAPE);

    // Same numbers: every height in [0, 1] and coefficients of either kind, bit for bit. The
    // control (a layer with both terms) must tell the two forms apart.
    let mut differs = false;
    for i in 0..=200u32 {
        let eta = Vec4::new(
            i as f32 / 200.0,
            1.0 - i as f32 / 200.0,
            (i as f32 * 0.37).fract(),
            0.5,
        );
        for (a, b) in [
            (0.0, 0.0),
            (0.0, 7.5),
            (0.0, -80.0),
            (1.3, 0.0),
            (-0.4, 0.0),
        ] {
            let mut g = LayerGroup::empty();
            g.profile_a = Vec4::new(a, 0.0, a, 0.25);
            g.profile_b = Vec4::new(b, b, 0.0, 0.0);
            g.profile_c = Vec4::new(0.75, -0.2, 0.3, 0.6);
            g.profile_d = Vec4::new(0.25, 1.0, -0.1, 0.4);
            let (e, l) = (exponential_profile(eta, g), linear_profile(eta, g));
            assert_eq!(
                e.to_array().map(f32::to_bits),
                l.to_array().map(f32::to_bits),
                "eta {eta} a {a} b {b}"
            );
        }
        let mut g = LayerGroup::empty();
        g.profile_a = Vec4::splat(0.5);
        g.profile_b = Vec4::splat(2.0);
        differs |= exponential_profile(eta, g) != linear_profile(eta, g);
    }
    assert!(differs, "the control: with both terms the forms differ");
}

#[test]
fn an_unknown_function_is_refused_with_file_field_and_the_known_names() {
    let err = genus_with(r#"functions = { shape = "no_such_shape" }"#).expect_err("unknown");
    let text = err.to_string();
    assert!(
        text.starts_with("genera/tower.toml: functions.shape: "),
        "{text}"
    );
    assert!(
        text.contains("unknown height function `no_such_shape`"),
        "{text}"
    );
    assert!(
        text.contains("rounded_shape") && text.contains("anvil_shape"),
        "{text}"
    );
    let err = genus_with(r#"functions = { colour = "anvil_shape" }"#).expect_err("slot");
    assert!(err.to_string().contains("functions"), "{err}");
}

/// A user's own function, for the registry tests.
#[shader_fn]
pub fn flat_top(eta: Vec4, layers: LayerGroup) -> Vec4 {
    Vec4::ONE - eta * 0.0 * layers.shape_amount
}

mod other {
    use glam::Vec4;
    use nimbus_clouds::model::layers::LayerGroup;
    use nimbus_clouds::{HeightFn, height_fn};
    use nimbus_dsl::prelude::*;

    /// Another function with the same name, elsewhere.
    #[shader_fn]
    pub fn flat_top(eta: Vec4, layers: LayerGroup) -> Vec4 {
        eta + layers.shape_amount * 0.0
    }

    pub const FLAT_TOP: HeightFn = height_fn!(flat_top, "the other flat top");
}

#[test]
fn registering_lets_files_name_a_function_and_one_name_means_one_function() {
    const FLAT_TOP: HeightFn = height_fn!(flat_top, "flat");
    assert!(lookup::<HeightFn>("flat_top").is_err(), "not known before");
    register(FLAT_TOP).expect("register");
    register(FLAT_TOP).expect("twice is harmless");
    assert_eq!(lookup::<HeightFn>("flat_top"), Ok(FLAT_TOP));
    let g = genus_with(r#"functions = { shape = "flat_top" }"#).expect("named");
    assert_eq!(g.functions.shape, FLAT_TOP);
    assert_eq!(
        (g.functions.shape.cpu)(Vec4::splat(0.5), LayerGroup::empty()),
        Vec4::ONE
    );
    let err = register(other::FLAT_TOP).expect_err("same name, another function");
    assert_eq!(
        err,
        RegisterError {
            kind: "height",
            name: "flat_top",
            path: other::FLAT_TOP.path,
            other: FLAT_TOP.path,
        }
    );
    // Built-in names are taken too.
    let mut clash = other::FLAT_TOP;
    clash.name = "anvil_shape";
    assert!(register(clash).is_err());
}
