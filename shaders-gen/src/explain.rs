//! `nimbus explain scene.toml`: which effects the scene's variant simulates, and why.

use std::path::Path;

use nimbus_codegen::VariantSource;
use nimbus_dsl::cloud::{Analysis, CloudLibrary, ScenePreset, analyse, load_scene};
use nimbus_dsl::model::clouds::CloudVariant;

use crate::render::{genus_of, library_for};

/// The scene file, its genus and the derived variant.
pub(crate) fn derive(
    data: Option<&Path>,
    scene_file: &Path,
) -> Result<(ScenePreset, CloudVariant, Analysis), Box<dyn std::error::Error>> {
    let lib: CloudLibrary = library_for(data, Some(scene_file))?;
    let scene = load_scene(scene_file)?;
    let mut genus = genus_of(&lib, &scene.genus)?;
    if let Some(c) = scene.coverage {
        genus.coverage = c;
    }
    let analysis = analyse(&scene, &genus);
    let variant = CloudVariant::new(&genus, scene.quality, analysis.features);
    Ok((scene, variant, analysis))
}

/// The derived variant as a catalogue entry, for `emit --scene`.
pub(crate) fn variant_source(
    data: Option<&Path>,
    scene_file: &Path,
) -> Result<Vec<VariantSource>, Box<dyn std::error::Error>> {
    let (scene, variant, _) = derive(data, scene_file)?;
    let mut out: Vec<VariantSource> = VariantSource::shadow(&variant).into_iter().collect();
    out.push(VariantSource::clouds(variant, &scene.description));
    Ok(out)
}

pub(crate) fn run(
    data: Option<&Path>,
    scene_file: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let (scene, variant, analysis) = derive(data, scene_file)?;
    println!(
        "scene {} ({}): genus `{}`, quality `{}`, sun {}°, camera {} m",
        scene.name,
        scene_file.display(),
        scene.genus,
        scene.quality.name(),
        scene.sun_elevation_deg,
        scene.camera_altitude
    );
    println!();
    for d in &analysis.decisions {
        println!(
            "  {:<24} {:<4} {}",
            d.toggle.name(),
            if d.included { "in" } else { "out" },
            d.reason
        );
    }
    println!(
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
    println!(
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
    println!();
    println!("variant: {}", variant.name());
    println!(
        "key: phase {:?}, {} layer group(s), octaves {}, features {}",
        variant.key.phase,
        variant.key.groups,
        variant.key.features.octaves,
        variant.key.features.key()
    );
    Ok(())
}
