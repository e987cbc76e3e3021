//! `nimbus explain scene.toml`: which effects the scene's variant simulates, and why.

use std::path::Path;

use nimbus_clouds::catalog::{Assignment, assign, distinct};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::{Analysis, CloudLibrary, ScenePreset, analyse, load_scene};

use nimbus_dsl::ShaderVariant;

use crate::render::{library_for, scene_genus};

/// The scene file, its genus and the derived variant.
pub(crate) fn derive(
    data: Option<&Path>,
    scene_file: &Path,
) -> Result<(ScenePreset, CloudVariant, Analysis), Box<dyn std::error::Error>> {
    let lib: CloudLibrary = library_for(data, Some(scene_file))?;
    let scene = load_scene(scene_file)?;
    let mut genus = scene_genus(&lib, scene_file, &scene)?;
    if let Some(c) = scene.coverage {
        genus.coverage = c;
    }
    let analysis = analyse(&scene, &genus);
    let variant = CloudVariant::new(&genus, scene.quality, analysis.features);
    Ok((scene, variant, analysis))
}

/// The shaders of the scene's derived key, for `emit --scene`.
/// The pair a scene derives, with `--enable`/`--disable` applied over the analysis (an engine
/// integration such as `scene-depth` is the host's choice, not the scene's).
pub(crate) fn resolved(
    data: Option<&Path>,
    scene_file: &Path,
    sel: &crate::data::Selection<'_>,
) -> Result<crate::data::Resolved, Box<dyn std::error::Error>> {
    let lib: CloudLibrary = library_for(data, Some(scene_file))?;
    let scene = load_scene(scene_file)?;
    let mut genus = scene_genus(&lib, scene_file, &scene)?;
    if let Some(c) = scene.coverage {
        genus.coverage = c;
    }
    let mut features = analyse(&scene, &genus).features;
    for t in sel.enable {
        t.set(&mut features, true);
    }
    for t in sel.disable {
        t.set(&mut features, false);
    }
    let table: Vec<Assignment> = vec![assign(&genus, scene.quality, features)];
    Ok(crate::data::Resolved {
        entries: distinct(&table),
        // The scene's own sun, camera, weather offset and haze, as `render` sets them up.
        uniforms: vec![nimbus_runtime::render::Renderer::uniforms(
            &nimbus_runtime::render::Frame::from_scene(&scene, &genus, 640, 360),
        )],
        table,
    })
}

pub(crate) fn run(
    data: Option<&Path>,
    scene_file: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let (scene, variant, analysis) = derive(data, scene_file)?;
    say!(
        "scene {} ({}): genus `{}`, quality `{}`, sun {}°, camera {} m",
        scene.name,
        scene_file.display(),
        scene.genus,
        scene.quality.name(),
        scene.sun_elevation_deg,
        scene.camera_altitude
    );
    say!();
    for d in &analysis.decisions {
        say!(
            "  {:<24} {:<4} {}",
            d.toggle.name(),
            if d.included { "in" } else { "out" },
            d.reason
        );
    }
    say!(
        "  {:<24} {:<4} {} layer(s) in {} lane group(s){}",
        "layer-packing",
        if analysis.layer_groups > 1 {
            "in"
        } else {
            "out"
        },
        analysis.layers,
        analysis.layer_groups,
        if analysis.layer_groups > 1 {
            ": the second vec4 group is sampled"
        } else {
            ": one vec4 group, the second is never sampled"
        }
    );
    say!(
        "  {:<24} {:<4} {}",
        "shadow-map-pass",
        if variant.key.uses_shadow_map() {
            "in"
        } else {
            "out"
        },
        if variant.key.uses_shadow_map() {
            "shadows or light shafts sample it"
        } else {
            "nothing samples it: no pass, no texture"
        }
    );
    // The genus' density functions: built-in defaults, or its own (each in the key).
    for (slot, name, path, about) in variant.key.functions.slots() {
        let own = variant
            .key
            .functions
            .custom()
            .iter()
            .any(|(s, _)| *s == slot);
        say!(
            "  {:<24} {:<4} {name}{}: {about}",
            format!("{slot}-function"),
            if own { "own" } else { "std" },
            if own {
                format!(" ({path})")
            } else {
                String::new()
            },
        );
    }
    say!();
    say!("variant: {}", variant.name());
    say!(
        "shader: {}",
        nimbus_clouds::catalog::ShaderKey::Clouds(variant.key).id()
    );
    if let Some(k) = variant.key.shadow_key() {
        say!(
            "shadow pass: {}",
            nimbus_clouds::catalog::ShaderKey::Shadow(k).id()
        );
    }
    Ok(())
}
