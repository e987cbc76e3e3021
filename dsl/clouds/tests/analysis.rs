//! The scene analysis: each rule decides its effect from the scene's content, the preset and
//! forced toggles come on top, and the derived variant follows.

use std::path::{Path, PathBuf};

use nimbus_clouds::analysis::{
    SceneContent, clouds_present, ground_bounce, haze, light_shafts, shadows, shape_detail, sun_up,
    turbulence,
};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::{CloudLibrary, Genus, Quality, ScenePreset, Toggle, analyse};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn library() -> CloudLibrary {
    CloudLibrary::load(&data_dir()).expect("data")
}

fn genus(name: &str) -> Genus {
    library().genus(name).expect("genus").clone()
}

/// The default scene with `genus`.
fn scene(genus: &str) -> ScenePreset {
    let lib = library();
    let mut s = lib.scenes["default"].1.clone();
    s.genus = genus.to_string();
    s.coverage = None;
    s
}

fn content<'a>(g: &'a Genus, s: &ScenePreset) -> SceneContent<'a> {
    SceneContent::of(s, g)
}

#[test]
fn no_coverage_or_no_density_means_no_clouds_and_no_cloud_effects() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    assert!(clouds_present(&content(&g, &s)).visible);
    s.coverage = Some(0.0);
    let c = content(&g, &s);
    assert!(!clouds_present(&c).visible);
    for rule in [shadows, shape_detail, turbulence, ground_bounce] {
        assert!(!rule(&c).visible, "{:?}", rule(&c));
    }
    let mut thin = g.clone();
    for l in &mut thin.layers {
        l.density_scale = 0.0;
    }
    assert!(!clouds_present(&content(&thin, &scene("cumulus"))).visible);
}

#[test]
fn shadows_need_a_shadow_casting_layer_whatever_the_sun() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    assert!(shadows(&content(&g, &s)).visible);
    // With the sun down the cloud overhead still dims the sky's light on the ground: shadows
    // stay, or an overcast's ground would brighten at sunset.
    s.sun_elevation_deg = -0.5;
    let v = shadows(&content(&g, &s));
    assert!(v.visible && v.reason.contains("sun is down"), "{v:?}");
    assert!(!sun_up(&content(&g, &s)).visible);
    let c = genus("cirrostratus");
    let v = shadows(&content(&c, &scene("cirrostratus")));
    assert!(
        !v.visible && v.reason.contains("no layer casts shadows"),
        "{v:?}"
    );
}

#[test]
fn haze_needs_density() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    assert!(haze(&content(&g, &s)).visible);
    s.haze_density = 0.0;
    assert!(!haze(&content(&g, &s)).visible);
}

#[test]
fn light_shafts_need_haze_sun_and_a_shadowing_layer_above_the_camera() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    assert!(light_shafts(&content(&g, &s)).visible);
    s.camera_altitude = 5000.0;
    let v = light_shafts(&content(&g, &s));
    assert!(
        !v.visible && v.reason.contains("above every shadow-casting layer"),
        "{v:?}"
    );
    let mut s = scene("cumulus");
    s.haze_density = 0.0;
    assert!(!light_shafts(&content(&g, &s)).visible);
    let mut s = scene("cumulus");
    s.sun_elevation_deg = -3.0;
    assert!(!light_shafts(&content(&g, &s)).visible);
}

#[test]
fn shape_detail_needs_a_layer_with_an_amount() {
    let g = genus("cumulus");
    assert!(shape_detail(&content(&g, &scene("cumulus"))).visible);
    let c = genus("cirrus");
    let v = shape_detail(&content(&c, &scene("cirrus")));
    assert!(!v.visible && v.reason.contains("amount is 0"), "{v:?}");
}

#[test]
fn turbulence_needs_a_displacement() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    assert!(turbulence(&content(&g, &s)).visible);
    s.turbulence_displacement = 0.0;
    assert!(!turbulence(&content(&g, &s)).visible);
}

#[test]
fn ground_bounce_is_dropped_only_far_above_the_layers() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    s.camera_altitude = 3500.0;
    assert!(
        ground_bounce(&content(&g, &s)).visible,
        "just above the tops"
    );
    s.camera_altitude = 9000.0;
    assert!(!ground_bounce(&content(&g, &s)).visible);
}

#[test]
fn one_layer_packs_into_one_lane_group_and_five_need_two() {
    let one = analyse(&scene("cumulus"), &genus("cumulus"));
    assert_eq!((one.layers, one.layer_groups), (1, 1));
    let mut five = genus("takram-default");
    while five.layers.len() < 5 {
        let l = five.layers[0].clone();
        five.layers.push(l);
    }
    let a = analyse(&scene("takram-default"), &five);
    assert_eq!(a.layer_groups, 2);
}

#[test]
fn the_preset_still_bounds_the_rules() {
    // Low has no shape detail whatever the layers say.
    let mut s = scene("cumulus");
    s.quality = Quality::Low;
    let a = analyse(&s, &genus("cumulus"));
    assert!(!a.features.shape_detail);
    let d = a
        .decisions
        .iter()
        .find(|d| d.toggle == Toggle::ShapeDetail)
        .expect("decision");
    assert!(d.reason.contains("`low` preset"), "{d:?}");
}

#[test]
fn forcing_an_effect_changes_the_variant() {
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    s.haze_density = 0.0;
    let derived = analyse(&s, &g);
    assert!(!derived.features.haze);
    s.features.haze = Some(true);
    let forced = analyse(&s, &g);
    assert!(forced.features.haze);
    let d = forced
        .decisions
        .iter()
        .find(|d| d.toggle == Toggle::Haze)
        .expect("decision");
    assert_eq!(d.reason, "forced on by the scene");
    let a = CloudVariant::new(&g, s.quality, derived.features);
    let b = CloudVariant::new(&g, s.quality, forced.features);
    assert_ne!(a.key, b.key);
    assert_ne!(a.name(), b.name());
    // And off: shadows forced off although the scene would show them.
    let mut s = scene("cumulus");
    s.features.shadows = Some(false);
    assert!(!analyse(&s, &g).features.shadows);
}

#[test]
fn the_example_scenes_derive_what_their_descriptions_say() {
    let lib = library();
    let derive = |name: &str| {
        let (_, s) = &lib.scenes[name];
        analyse(s, lib.genus(&s.genus).expect("genus")).features
    };
    let deck = derive("above-the-deck");
    assert!(!deck.light_shafts && !deck.ground_bounce && deck.shadows);
    let twilight = derive("twilight-cirrus");
    assert!(!twilight.shadows && !twilight.light_shafts && !twilight.haze);
    assert!(!twilight.turbulence && !twilight.shape_detail);
    let veil = derive("still-cirrostratus");
    assert!(!veil.shadows && !veil.shape_detail && !veil.turbulence && veil.haze);
    // A full scene keeps everything its preset has.
    assert_eq!(derive("partly-cloudy"), Quality::High.features());
}

/// A scene naming no path but a `[budget]` is drawn by the most accurate path that fits it,
/// and `explain`'s reason says so; a scene that moves keeps the volume (a baked path would
/// rebake every frame), and so does an orthographic camera; a path the scene names wins.
#[test]
fn a_budget_picks_the_path_that_fits() {
    use nimbus_clouds::Path as DrawPath;
    use nimbus_clouds::budget::{Budget, cost_ratio};
    let g = genus("cumulus");
    let mut s = scene("cumulus");
    s.quality = Quality::Low;
    s.clock = None;
    s.wind = None;
    s.weather.clear();
    s.formation = None;
    assert_eq!(analyse(&s, &g).path.path, DrawPath::Volume);
    let impostor = cost_ratio(DrawPath::Impostor, Quality::Low);
    s.budget = Some(Budget {
        frame_ms: 40.0 * impostor * 1.05,
        volume_ms: 40.0,
    });
    let a = analyse(&s, &g);
    assert_eq!(a.path.path, DrawPath::Impostor, "{}", a.path.reason);
    assert!(a.path.reason.contains("budget"), "{}", a.path.reason);
    assert_eq!(a.features.path, DrawPath::Impostor);
    // The same budget with the volume within it.
    s.budget = Some(Budget {
        frame_ms: 40.0,
        volume_ms: 30.0,
    });
    assert_eq!(analyse(&s, &g).path.path, DrawPath::Volume);
    // Moving clouds: every frame a bake.
    s.budget = Some(Budget {
        frame_ms: 4.0,
        volume_ms: 40.0,
    });
    let mut windy = s.clone();
    windy.wind = lib_wind();
    let a = analyse(&windy, &g);
    assert_eq!(a.path.path, DrawPath::Volume, "{}", a.path.reason);
    assert!(a.path.reason.contains("wind"), "{}", a.path.reason);
    // An orthographic camera.
    let mut ortho = s.clone();
    ortho.features.orthographic = Some(true);
    assert_eq!(analyse(&ortho, &g).path.path, DrawPath::Volume);
    // The scene's own path wins over its budget.
    let mut named = s.clone();
    named.features.path = Some(DrawPath::Blob2d);
    assert_eq!(analyse(&named, &g).path.path, DrawPath::Blob2d);
}

/// The wind of the example scene that has one.
fn lib_wind() -> Option<nimbus_clouds::wind::Wind> {
    let lib = library();
    let wind = lib.scenes["day-with-wind"].1.wind;
    assert!(wind.is_some(), "day-with-wind has no wind");
    wind
}
