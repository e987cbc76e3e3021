//! `nimbus explain scene.toml`: which effects the scene's variant simulates, and why.

use std::path::Path;

use nimbus_clouds::catalog::{Assignment, assign, distinct};
use nimbus_clouds::limits::{self, Origin};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::{Analysis, analyse};
use nimbus_runtime::render::Frame;

use nimbus_dsl::ShaderVariant;

use crate::scene_input::{SceneInput, SceneState};

/// One state of a scene with the variant it derives and the analysis that chose it.
pub(crate) type Derived = (SceneState, CloudVariant, Analysis);

/// The scene at `seconds` (one state, or two while one genus gives way to another), each with
/// its derived variant and the analysis that chose it.
pub(crate) fn derive(
    data: Option<&Path>,
    scene_file: &Path,
    seconds: f64,
) -> Result<Vec<Derived>, Box<dyn std::error::Error>> {
    derive_from(&SceneInput::load(data, scene_file, None)?, seconds)
}

/// [`derive`] of a scene already loaded.
pub(crate) fn derive_from(
    input: &SceneInput,
    seconds: f64,
) -> Result<Vec<Derived>, Box<dyn std::error::Error>> {
    limits::TIME.check(seconds, Origin::Flag(limits::TIME.flag))?;
    let mut out = Vec::new();
    for state in input.at(seconds)? {
        let analysis = analyse(&state.scene, &state.genus);
        let variant = CloudVariant::new(&state.genus, state.scene.quality, analysis.features);
        out.push((state, variant, analysis));
    }
    Ok(out)
}

/// The pairs a scene derives at `seconds` (one, or two while one genus gives way to another),
/// with `--enable`/`--disable` applied over the analysis (an engine integration such as
/// `scene-depth` is the host's choice, not the scene's), for `emit --scene`.
pub(crate) fn resolved(
    data: Option<&Path>,
    scene_file: &Path,
    sel: &crate::data::Selection<'_>,
    seconds: f64,
) -> Result<crate::data::Resolved, Box<dyn std::error::Error>> {
    resolved_from(&SceneInput::load(data, scene_file, None)?, sel, seconds)
}

/// [`resolved`] of a scene already loaded.
pub(crate) fn resolved_from(
    input: &SceneInput,
    sel: &crate::data::Selection<'_>,
    seconds: f64,
) -> Result<crate::data::Resolved, Box<dyn std::error::Error>> {
    let mut table: Vec<Assignment> = Vec::new();
    let mut uniforms = Vec::new();
    for (state, _, analysis) in derive_from(input, seconds)? {
        let mut features = analysis.features;
        for t in sel.enable {
            t.set(&mut features, true);
        }
        for t in sel.disable {
            t.set(&mut features, false);
        }
        if let Some(p) = sel.path {
            features.path = p;
        }
        table.push(assign(&state.genus, state.scene.quality, features));
        // The scene's own sun, camera, weather offset and haze at that time, as `render` sets
        // them up.
        let mut frame = Frame::from_scene(&state.scene, &state.genus, 640, 360);
        frame.wind = state.drift;
        uniforms.push(nimbus_runtime::render::Renderer::uniforms(&frame));
    }
    Ok(crate::data::Resolved {
        entries: distinct(&table),
        uniforms,
        table,
    })
}

pub(crate) fn run(
    data: Option<&Path>,
    scene_file: &Path,
    seconds: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let states = derive(data, scene_file, seconds)?;
    for (i, (state, variant, analysis)) in states.iter().enumerate() {
        if i > 0 {
            say!();
        }
        explain_state(
            scene_file,
            seconds,
            states.len() > 1,
            state,
            variant,
            analysis,
        );
    }
    Ok(())
}

/// One state of the scene: its decisions, variant and shaders.
fn explain_state(
    scene_file: &Path,
    seconds: f64,
    blended: bool,
    state: &SceneState,
    variant: &CloudVariant,
    analysis: &Analysis,
) {
    let scene = &state.scene;
    say!(
        "scene {} ({}) at second {seconds}: genus `{}` (coverage {:.3}), quality `{}`, sun {:.1}° \
         at {:.1}°, camera {} m{}",
        scene.name,
        scene_file.display(),
        scene.genus,
        state.genus.coverage,
        scene.quality.name(),
        scene.sun_elevation_deg,
        scene.sun_azimuth_deg,
        scene.camera_altitude,
        if blended {
            format!(", weight {:.3} of the blend", state.weight)
        } else {
            String::new()
        }
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
    say!(
        "  {:<24} {:<4} {}",
        "path",
        analysis.path.path.name(),
        analysis.path.reason
    );
    if variant.key.reads_slices() {
        let (w, h) = nimbus_clouds::model::slices::slices_size();
        say!(
            "  {:<24} {:<4} {w}×{h} stack of {} slices, baked when the sun, the camera's place \
             or the weather moves",
            "slice-pass",
            "in",
            nimbus_clouds::model::slices::SLICE_LEVELS,
        );
    }
    if variant.key.reads_blob2d() {
        use nimbus_clouds::model::blob2d::{
            BLOB_BANDS as bands, BLOB_COLUMN_STEPS, BLOB_SAMPLES, blob2d_size,
        };
        let (w, h) = blob2d_size();
        say!(
            "  {:<24} {:<4} {w}×{h} map of the columns in {bands} altitude bands ({} samples up \
             each, the sun from 4 depths), baked when the sun, the camera's place or the \
             weather moves; at most {} reads a pixel",
            "map-pass",
            "in",
            BLOB_COLUMN_STEPS,
            3 * bands * BLOB_SAMPLES,
        );
    }
    if variant.key.reads_impostor() {
        use nimbus_clouds::model::impostor::{IMPOSTOR_MARCHES, impostor_size};
        let (w, h) = impostor_size();
        if variant.key.bakes_view() {
            say!(
                "  {:<24} {:<4} {w}×{h} octahedral map of every direction: the whole picture \
                 (the volume's march a texel, composited over the sky or the ground with the air \
                 and the haze), {} marches, above and below the horizon; baked when the sun, the \
                 camera's place, the weather, the haze or the composite's switches change; {} \
                 reads and the sun's disc a pixel",
                "impostor-pass",
                "in",
                IMPOSTOR_MARCHES,
                IMPOSTOR_MARCHES,
            );
        } else {
            say!(
                "  {:<24} {:<4} {w}×{h} octahedral map of every direction ({} light tiles, each \
                 the volume's march a texel, and the front's depth), baked when the sun, the \
                 camera's place or the weather moves; {} reads a pixel, composited per pixel",
                "impostor-pass",
                "in",
                IMPOSTOR_MARCHES,
                IMPOSTOR_MARCHES + 1,
            );
        }
    }
    if variant.key.reads_mesh() {
        use nimbus_clouds::model::mesh::{
            MESH_LAYERS, MESH_PUFFS, MESH_RINGS, MESH_SECTORS, MESH_SUB, mesh_size,
        };
        let (w, h) = mesh_size();
        say!(
            "  {:<24} {:<4} {w}×{h} table of {} clusters a band ({MESH_RINGS} rings × \
             {MESH_SECTORS} sectors) of {MESH_PUFFS} puffs ({MESH_SUB}×{MESH_SUB}×{MESH_LAYERS}) \
             fitted to the density, baked when the sun, the camera's place or the weather \
             moves; a ray visits two clusters a ring it passes",
            "mesh-pass",
            "in",
            MESH_RINGS * MESH_SECTORS,
        );
    }
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
}
