//! The cloud model as variants: every genus × quality preset generates, validates with naga and
//! passes glslangValidator and spirv-val; a toggle that is off leaves no trace in any target;
//! the variant manifest and representative variants are pinned as snapshots.

mod common;

use std::path::Path;

use nimbus_codegen::external::{ExternalCheck, check_files};
use std::collections::BTreeMap;

use nimbus_clouds::catalog::{ShaderKey, assignments, cloud_catalog};
use nimbus_clouds::model::clouds::{CloudVariant, cloud_module};
use nimbus_clouds::{CloudKey, CloudLibrary, Features, PhaseSpec, Quality, Toggle};
use nimbus_codegen::{Contents, Generated, Target, generate, generate_variant, print_and_validate};
use nimbus_dsl::ShaderVariant;

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

fn build(lib: &CloudLibrary, genus: &str, quality: Quality, features: Features) -> Generated {
    let v = CloudVariant::new(lib.genus(genus).expect("genus"), quality, features);
    let module = cloud_module(&v.key).expect("records");
    generate(module, &v.key.name(), &Target::ALL).unwrap_or_else(|e| panic!("{}: {e}", v.name()))
}

fn texts(g: &Generated) -> Vec<(String, String)> {
    g.files
        .iter()
        .filter_map(|f| match &f.contents {
            Contents::Text(t) => Some((f.file_name.clone(), t.clone())),
            Contents::SpirV(_) => None,
        })
        .collect()
}

#[test]
fn every_genus_at_every_quality_validates_everywhere() {
    let lib = library();
    let external = common::tool_available("glslangValidator")
        && common::tool_available("spirv-val")
        && common::slang_available();
    if !external {
        if std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("NIMBUS_REQUIRE_TOOLS=1 but glslangValidator, spirv-val or Slang is missing");
        }
        eprintln!(
            "SKIPPED external validation: glslangValidator, spirv-val or Slang (slangpy) not installed (naga still validates)"
        );
    }
    let variants = cloud_catalog(&lib);
    // Each genus × preset resolves to a cloud key and, when it samples shadows, a shadow key;
    // the catalogue holds each distinct key once, and every pair is some entry's user.
    let pairs = assignments(&lib);
    assert_eq!(pairs.len(), lib.genera.len() * 4);
    for module in ["clouds", "shadow"] {
        let users: usize = variants
            .iter()
            .filter(|v| v.module() == module)
            .map(|v| v.users.len())
            .sum();
        assert_eq!(users, pairs.len(), "{module}: every pair runs one shader");
    }
    let generated: Vec<_> = variants
        .iter()
        .map(|v| generate_variant(v, &Target::ALL).unwrap_or_else(|e| panic!("{}: {e}", v.id())))
        .collect();
    let files: Vec<_> = generated.iter().flat_map(|g| &g.files).collect();
    let mut hlsl = 0;
    if external {
        // One batch: Slang checks every HLSL file in one process.
        for (f, check) in files.iter().zip(check_files(&files)) {
            match check {
                ExternalCheck::Passed { .. } | ExternalCheck::NotApplicable => {}
                other => panic!("{}: {other:?}", f.file_name),
            }
            hlsl += usize::from(f.target == Target::Hlsl);
        }
    }
    println!(
        "{} cloud variants, {} files validated, {hlsl} HLSL files by glslang and Slang",
        variants.len(),
        files.len()
    );
}

/// Text that only the code of `toggle` produces (function names, locals and bindings).
fn markers(toggle: Toggle) -> &'static [&'static str] {
    match toggle {
        Toggle::ShapeDetail => &["detail_erosion", "detail_texture", "detail_tex"],
        Toggle::Turbulence => &["turbulence_texture", "turbulence_tex", "curl"],
        Toggle::LightShafts => &["shadow_length"],
        Toggle::Haze => &["haze_opacity", "haze_light"],
        Toggle::Shadows => &["shadow_optical_depth(map.texel, to_top, reach)"],
        Toggle::GroundBounce => &["ground_bounce_light", "ground_irradiance"],
        Toggle::Diffusion => &[
            "slab_diffuse_fluence",
            "forward_peak(",
            "phase_second_moment",
            "sunlit_face",
        ],
        Toggle::Powder => &["powder_exponent)"],
        Toggle::AccurateSunSkyLight => &["sun_attenuation"],
        Toggle::AccuratePhaseFunction => &["approximate_mie"],
        Toggle::FlatHighLayer => &["flat_path_depth"],
        Toggle::SceneDepth => &[
            "scene_distance",
            "scene_depth_texture",
            "composite_over_scene",
        ],
        Toggle::Orthographic => &["orthographic_ray", "ray_block", "clouds_input"],
        Toggle::UntiledWeather => &["hex_corners", "vertex_offset"],
        Toggle::AccurateAirLight => &["air_integrals"],
    }
}

#[test]
fn each_toggle_off_removes_its_code_and_bindings_from_every_target() {
    let lib = library();
    // Every effect on; the flat high layer, which replaces the march they live in, is tested on
    // top of them.
    let mut all_on = Features::default();
    for &t in Toggle::ALL {
        t.set(&mut all_on, t != Toggle::FlatHighLayer);
    }
    let mut flat = all_on;
    Toggle::FlatHighLayer.set(&mut flat, true);
    let flat_on = build(&lib, "cirrus", Quality::High, flat);
    let on = build(&lib, "cumulus", Quality::High, all_on);
    for &t in Toggle::ALL {
        if t == Toggle::AccurateAirLight {
            // It swaps code rather than adding it, and an orthographic camera (on here) has
            // it whatever the toggle says: `the_air_table_stands_in_for_the_air_integrals`.
            continue;
        }
        let (on, all_on) = if t == Toggle::FlatHighLayer {
            (&flat_on, flat)
        } else {
            (&on, all_on)
        };
        let wgsl_on = &on.wgsl;
        for m in markers(t) {
            assert!(
                wgsl_on.contains(m),
                "{}: marker `{m}` missing with the toggle on",
                t.name()
            );
        }
        let mut f = all_on;
        t.set(&mut f, false);
        let genus = if t == Toggle::FlatHighLayer {
            "cirrus"
        } else {
            "cumulus"
        };
        let off = build(&lib, genus, Quality::High, f);
        for (name, text) in texts(&off) {
            for m in markers(t) {
                // Only the WGSL keeps our names; the other targets' names derive from them.
                if name.ends_with(".wgsl") || !m.contains('(') {
                    assert!(
                        !text.contains(m),
                        "{} off: {name} still contains `{m}`",
                        t.name()
                    );
                }
            }
        }
        // The flat layer is the cheap path: off, the march it replaces comes back.
        let shrank = if t == Toggle::FlatHighLayer {
            off.wgsl.len() > on.wgsl.len()
        } else {
            off.wgsl.len() < on.wgsl.len()
        };
        assert!(
            shrank,
            "{} off did not change the shader's size the right way",
            t.name()
        );
    }
    // Textures used by no remaining effect lose their bindings too.
    let mut none = all_on;
    for t in [
        Toggle::Shadows,
        Toggle::LightShafts,
        Toggle::ShapeDetail,
        Toggle::Turbulence,
        Toggle::SceneDepth,
        Toggle::Orthographic,
    ] {
        t.set(&mut none, false);
    }
    let bare = build(&lib, "cumulus", Quality::High, none);
    assert_eq!(
        bare.stats.bindings, 4,
        "clouds + weather + shape + sampler:\n{}",
        bare.wgsl
    );
    for (name, text) in texts(&bare) {
        for gone in ["shadow_map", "detail_texture", "turbulence_texture"] {
            assert!(!text.contains(gone), "{name} still declares {gone}");
        }
    }
    for f in bare.files.iter().filter_map(|f| f.manifest.as_ref()) {
        assert!(
            f.bindings.iter().all(|b| !b.name.contains("shadow")),
            "{:?}",
            f.bindings
        );
    }
}

/// Without `accurate-air-light` the composite reads the air table (its binding, its lookup)
/// and integrates nothing per pixel; with it, the reverse. An orthographic camera integrates
/// whatever the toggle says, so its key drops the toggle.
#[test]
fn the_air_table_stands_in_for_the_air_integrals() {
    let lib = library();
    let table = build(&lib, "cumulus", Quality::High, Quality::High.features());
    let mut accurate = Quality::High.features();
    accurate.accurate_air_light = true;
    let integral = build(&lib, "cumulus", Quality::High, accurate);
    assert!(table.wgsl.contains("var air_table"), "{}", table.wgsl);
    assert!(table.wgsl.contains("fn air_from_table("));
    assert!(!table.wgsl.contains("fn air_integrals("));
    assert!(integral.wgsl.contains("fn air_integrals("));
    assert!(!integral.wgsl.contains("var air_table"));
    assert!(!integral.wgsl.contains("fn air_from_table("));
    assert_eq!(integral.stats.bindings + 1, table.stats.bindings);
    let genus = lib.genus("cumulus").expect("genus");
    let mut ortho = Quality::High.features();
    ortho.orthographic = true;
    let plain = CloudVariant::new(genus, Quality::High, ortho).key;
    ortho.accurate_air_light = true;
    assert_eq!(CloudVariant::new(genus, Quality::High, ortho).key, plain);
    assert!(!plain.reads_air_table());
    assert!(
        CloudVariant::new(genus, Quality::High, Quality::High.features())
            .key
            .reads_air_table()
    );
}

/// The slices path's march reads the stack in place of the noise and the secondary marches
/// (its slice pass is what reads them); the volume's has no trace of the stack.
#[test]
fn the_slices_path_marches_through_its_stack() {
    let lib = library();
    let mut features = Quality::Medium.features();
    features.path = nimbus_clouds::Path::Slices;
    let sliced = build(&lib, "cumulus", Quality::Medium, features);
    let volume = build(&lib, "cumulus", Quality::Medium, Quality::Medium.features());
    assert!(sliced.wgsl.contains("var cloud_bake"), "{}", sliced.wgsl);
    assert!(sliced.wgsl.contains("fn slices_at("));
    // No secondary march is left; the march itself reads no noise (the ground's overhead
    // occlusion under a shadowing deck still takes its four density samples).
    for marched in ["fn sun_optical_depth(", "fn secondary_optical_depth("] {
        assert!(
            !sliced.wgsl.contains(marched),
            "{marched} in the slices march"
        );
        assert!(volume.wgsl.contains(marched));
    }
    let march = |wgsl: &str| {
        let start = wgsl.find("fn march_clouds(").expect("a march");
        let end = wgsl[start + 1..]
            .find("\nfn ")
            .map_or(wgsl.len(), |e| start + 1 + e);
        wgsl[start..end].to_string()
    };
    for noise in ["weather_density(", "eroded_density("] {
        assert!(
            !march(&sliced.wgsl).contains(noise),
            "{noise} in the slices march"
        );
        assert!(march(&volume.wgsl).contains(noise));
    }
    assert!(!volume.wgsl.contains("cloud_bake"));
    let genus = lib.genus("cumulus").expect("genus");
    let key = CloudVariant::new(genus, Quality::Medium, features).key;
    assert!(key.reads_slices() && key.name().ends_with("-slices"));
    let stack = generate_variant(&ShaderKey::Bake(key), &Target::ALL).expect("slice pass");
    assert!(stack.wgsl.contains("fn slices_fragment("));
    assert!(
        stack.wgsl.contains("fn sun_optical_depth(")
            || stack.wgsl.contains("fn secondary_optical_depth(")
    );
    // A path asked for draws a thin high layer from its stack (the flat layer is the volume's
    // shortcut: the key drops it); an orthographic camera keeps the volume (the key drops the
    // path).
    let mut flat = features;
    flat.flat_high_layer = true;
    let flat = CloudVariant::new(genus, Quality::Medium, flat).key;
    assert!(flat.reads_slices() && !flat.features.flat_high_layer);
    let mut ortho = features;
    ortho.orthographic = true;
    assert!(
        !CloudVariant::new(genus, Quality::Medium, ortho)
            .key
            .reads_slices()
    );
}

/// Builds cumulus at `medium` drawn by `path` and by the volume, and checks what every path
/// that bakes the density holds: its cloud pass reads its bake and `drawn` (its drawing
/// functions), and no noise, no march, no march to the sun, all of which the volume's has and
/// none of `drawn`; its bake pass has `baked` and marches to the sun. Returns the key.
fn draws_from_its_bake_alone(
    path: nimbus_clouds::Path,
    drawn: &[&str],
    baked: &[&str],
) -> nimbus_clouds::CloudKey {
    let lib = library();
    let mut features = Quality::Medium.features();
    features.path = path;
    let pass = build(&lib, "cumulus", Quality::Medium, features);
    let volume = build(&lib, "cumulus", Quality::Medium, Quality::Medium.features());
    assert!(pass.wgsl.contains("var cloud_bake"), "{}", pass.wgsl);
    assert!(!volume.wgsl.contains("cloud_bake"));
    for f in drawn {
        assert!(pass.wgsl.contains(f), "{f} not in the {path} path");
        assert!(!volume.wgsl.contains(f), "{f} in the volume");
    }
    for marched in [
        "fn march_clouds(",
        "fn weather_density(",
        "fn eroded_density(",
        "fn secondary_optical_depth(",
        "var weather_texture",
        "var shape_texture",
    ] {
        assert!(!pass.wgsl.contains(marched), "{marched} in the {path} path");
        assert!(volume.wgsl.contains(marched), "{marched} not in the volume");
    }
    let genus = lib.genus("cumulus").expect("genus");
    let key = CloudVariant::new(genus, Quality::Medium, features).key;
    assert!(key.bakes() && key.name().ends_with(&format!("-{path}")));
    let bake = generate_variant(&ShaderKey::Bake(key), &Target::ALL).expect("bake pass");
    for f in baked.iter().chain(&["fn secondary_optical_depth("]) {
        assert!(bake.wgsl.contains(f), "{f} not in the {path} bake");
    }
    key
}

/// The 2D path's cloud pass reads its map and no noise at all, and marches nothing (the
/// ground's overhead occlusion reads the map too); its map pass reads the noise and marches
/// to the sun. The volume's has no trace of the map.
#[test]
fn the_blob2d_path_draws_from_its_map_alone() {
    let key = draws_from_its_bake_alone(
        nimbus_clouds::Path::Blob2d,
        &["fn blob2d_clouds(", "fn blob2d_overhead("],
        &["fn blob2d_fragment("],
    );
    assert!(key.reads_blob2d());
}

/// The mesh path's cloud pass reads its cluster table and no noise at all, and marches
/// nothing (the ground's overhead occlusion sums the puffs' columns); its bake fits the puffs
/// to the density and marches to the sun from each. The volume's has no trace of the table.
#[test]
fn the_mesh_path_draws_from_its_table_alone() {
    let key = draws_from_its_bake_alone(
        nimbus_clouds::Path::Mesh,
        &["fn mesh_clouds(", "fn mesh_overhead("],
        &["fn mesh_fragment(", "fn puff_fit("],
    );
    assert!(key.reads_mesh());
}

/// The impostor path's cloud pass reads its map and marches nothing (no view march, no march
/// to the sun; the ground's overhead occlusion keeps its four density samples, as the
/// volume's); its bake is the volume's own march per direction (the same `march_clouds`, its
/// marches to the sun), without the engine's depth, which the cloud pass applies.
#[test]
fn the_impostor_path_draws_from_its_map_alone() {
    let lib = library();
    let mut features = Quality::Medium.features();
    features.path = nimbus_clouds::Path::Impostor;
    features.scene_depth = true;
    let drawn = build(&lib, "cumulus", Quality::Medium, features);
    assert!(drawn.wgsl.contains("var cloud_bake"), "{}", drawn.wgsl);
    assert!(drawn.wgsl.contains("fn impostor_clouds("));
    assert!(drawn.wgsl.contains("fn composite_over_scene("));
    for marched in [
        "fn march_clouds(",
        "fn sun_optical_depth(",
        "fn secondary_optical_depth(",
    ] {
        assert!(
            !drawn.wgsl.contains(marched),
            "{marched} in the impostor path"
        );
    }
    let genus = lib.genus("cumulus").expect("genus");
    let key = CloudVariant::new(genus, Quality::Medium, features).key;
    assert!(key.reads_impostor() && key.bakes() && key.name().ends_with("-impostor"));
    let bake = generate_variant(&ShaderKey::Bake(key), &Target::ALL).expect("impostor pass");
    assert!(bake.wgsl.contains("fn impostor_fragment("));
    assert!(bake.wgsl.contains("fn march_clouds("));
    assert!(bake.wgsl.contains("fn secondary_optical_depth("));
    assert!(
        !bake.wgsl.contains("scene_depth"),
        "the bake's rays are directions, not the engine's pixels"
    );
    // The bake's marches to the sun read the shadow map, as the volume's; the cloud pass
    // reads it for the ground's shadows.
    assert!(bake.wgsl.contains("fn shadow_read("));
    assert!(
        drawn.wgsl.contains("var shadow_map"),
        "the ground's shadows went"
    );
}

/// Without the engine's depth the impostor's map holds the whole picture: its bake marches and
/// composites (the air table, the ground's shadows, the haze), and the cloud pass reads the
/// map and draws the sun's disc, nothing else (no march, no composite, no noise, no air table,
/// no shadow map).
#[test]
fn the_impostor_path_without_the_scene_reads_its_view() {
    let lib = library();
    let mut features = Quality::Medium.features();
    features.path = nimbus_clouds::Path::Impostor;
    let drawn = build(&lib, "cumulus", Quality::Medium, features);
    for read in ["fn impostor_view(", "fn disc_through(", "var cloud_bake"] {
        assert!(drawn.wgsl.contains(read), "{read} not in the cloud pass");
    }
    for gone in [
        "fn composite(",
        "fn march_clouds(",
        "fn impostor_clouds(",
        "var air_table",
        "var shadow_map",
        "var weather_texture",
        "var shape_texture",
    ] {
        assert!(
            !drawn.wgsl.contains(gone),
            "{gone} in the cloud pass of an impostor that holds the view"
        );
    }
    let genus = lib.genus("cumulus").expect("genus");
    let key = CloudVariant::new(genus, Quality::Medium, features).key;
    assert!(key.bakes_view() && key.reads_air_table());
    let bake = generate_variant(&ShaderKey::Bake(key), &Target::ALL).expect("impostor pass");
    for baked in [
        "fn view_texel(",
        "fn march_clouds(",
        "fn composite(",
        "var air_table",
        "fn haze_light(",
    ] {
        assert!(bake.wgsl.contains(baked), "{baked} not in the bake");
    }
    // The disc is drawn per pixel, not baked: the bake's composite leaves it out.
    assert!(
        !bake.wgsl.contains("fn sun_disc("),
        "the bake draws the sun's disc"
    );
}

/// The uber-shader reads every generation-time choice from the key uniforms: it validates on
/// every target, declares the `key` binding, loops to run-time bounds and keeps every effect's
/// code; a specialised shader has none of that.
#[test]
fn the_uber_shader_branches_at_run_time_on_every_target() {
    let uber = cloud_module(&CloudKey::uber()).expect("records");
    let g = generate(uber, "uber", &Target::ALL).unwrap_or_else(|e| panic!("uber: {e}"));
    // One WGSL and one HLSL file holding both entry points, and a vertex and a fragment file
    // for each of the four other targets.
    assert_eq!(g.files.len(), 2 + 2 * (Target::ALL.len() - 2));
    let w = &g.wgsl;
    assert!(w.contains("var<uniform> key: KeyUniforms"), "{w}");
    for marker in [
        "key.toggles",
        "octave < key.octaves",
        "group < key.groups",
        "key.phase == 1u",
        "fn shadow_length",
        "fn haze_opacity",
        "fn sun_attenuation",
        "fn approximate_mie",
    ] {
        assert!(w.contains(marker), "uber lacks `{marker}`");
    }
    let lib = library();
    let specialised = build(&lib, "cumulus", Quality::High, Quality::High.features());
    let code = code_of(&specialised.wgsl);
    assert!(
        !code.contains("var<uniform> key") && !code.contains("key.toggles"),
        "a specialised shader reads no key uniform"
    );
}

#[test]
fn octave_count_bounds_the_loop() {
    let lib = library();
    let mut f = Quality::High.features();
    // The octaves, not the diffusion that replaces them.
    f.diffusion = false;
    f.octaves = 3;
    let g = build(&lib, "cumulus", Quality::High, f);
    // Unrolled: one copy per octave, each reading a fixed lane (a loop indexing the phases by
    // its counter was 7 % of `low`'s frame in SwiftShader).
    let body = g
        .wgsl
        .split("fn multiple_scattering")
        .nth(1)
        .and_then(|rest| rest.split("\n}\n").next())
        .expect("multiple_scattering in the shader");
    assert!(!body.contains("for ("), "{body}");
    assert_eq!(
        body.matches("attenuation = attenuation * attenuation")
            .count(),
        3,
        "{body}"
    );
}

/// The channels of each sample of `texture` (a WGSL global) in `wgsl`: the swizzle after each
/// `textureSampleLevel(texture, ...)` call ("" for the whole texel).
fn sampled_channels(wgsl: &str, texture: &str) -> Vec<String> {
    let call = format!("textureSampleLevel({texture},");
    wgsl.match_indices(&call)
        .map(|(start, _)| {
            let mut depth = 0;
            let rest = &wgsl[start..];
            let close = rest
                .char_indices()
                .find(|&(_, c)| {
                    depth += i32::from(c == '(') - i32::from(c == ')');
                    c == ')' && depth == 0
                })
                .map_or(rest.len(), |(i, _)| i + 1);
            let after = &rest[close..];
            after
                .strip_prefix('.')
                .map(|s| s.chars().take_while(char::is_ascii_alphabetic).collect())
                .unwrap_or_default()
        })
        .collect()
}

/// The runtime and every engine package hold the 3D noises as one channel (`r16float`,
/// `NoiseKind::channels`): no shader of the catalogue may read more than their red.
#[test]
fn the_3d_noises_are_read_by_their_red_channel_alone() {
    use nimbus_runtime::textures::NoiseKind;
    let lib = library();
    assert_eq!(NoiseKind::Shape.channels(), 1);
    assert_eq!(NoiseKind::Detail.channels(), 1);
    let mut reads = 0;
    for v in cloud_catalog(&lib) {
        let g = generate_variant(&v, &[Target::Wgsl]).expect("generate");
        for texture in ["shape_texture", "detail_texture"] {
            for channels in sampled_channels(&g.wgsl, texture) {
                assert_eq!(channels, "x", "{}: {texture} read as `.{channels}`", v.id());
                reads += 1;
            }
        }
    }
    assert!(
        reads > 10,
        "only {reads} reads of the 3D noises in the catalogue"
    );
    // The check sees a read of more than red: the weather map's whole texel is read.
    let g = generate_variant(&cloud_catalog(&lib)[0], &[Target::Wgsl]).expect("generate");
    assert!(
        sampled_channels(&g.wgsl, "weather_texture").contains(&String::new()),
        "the weather's whole-texel read was not seen"
    );
}

#[test]
fn cloud_variant_manifest_is_pinned() {
    let lib = library();
    let lines: Vec<String> = cloud_catalog(&lib)
        .iter()
        .map(|v| {
            generate_variant(v, &Target::ALL)
                .expect("generate")
                .stats
                .manifest_line(&v.id())
        })
        .collect();
    insta::assert_snapshot!("cloud_variant_manifest", lines.join("\n"));
}

#[test]
fn representative_cloud_keys_are_pinned_per_target() {
    let lib = library();
    // Three distinct cloud keys (low, high, and a Henyey–Greenstein genus at medium), the
    // shadow pass of high, the air table, and the flat high layer the analysis chooses for high cirrus; the
    // reference library's default genus at high runs the same shader as cumulus at high (the
    // genus is uniform values; stratus has the droplets' phase function, a key of its own). Cirrus names its own weather function (`streak_weather`).
    let mut keys = Vec::new();
    for (genus, q) in [
        ("cumulus", Quality::Low),
        ("cumulus", Quality::High),
        ("cirrus", Quality::Medium),
    ] {
        let v = CloudVariant::new(lib.genus(genus).expect("genus"), q, q.features());
        keys.push(ShaderKey::Clouds(v.key));
    }
    let high = CloudVariant::new(
        lib.genus("takram-default").expect("genus"),
        Quality::High,
        Quality::High.features(),
    );
    assert_eq!(keys[1], ShaderKey::Clouds(high.key));
    keys.extend(high.key.shadow_key().map(ShaderKey::Shadow));
    // The air table every real-time key reads.
    assert!(high.key.reads_air_table());
    keys.push(ShaderKey::AirTable);
    // The flat high layer, as the analysis derives it for the high-cirrus scene.
    let scene = &lib.scenes["high-cirrus"].1;
    let cirrus = lib.genus("cirrus").expect("genus");
    let derived = nimbus_clouds::analyse(scene, cirrus).features;
    assert!(
        derived.flat_high_layer,
        "high-cirrus no longer derives the flat layer"
    );
    keys.push(ShaderKey::Clouds(
        CloudVariant::new(cirrus, Quality::High, derived).key,
    ));
    // The slices path of cumulus at low: its cloud pass and its slice pass.
    let mut sliced = Quality::Low.features();
    sliced.path = nimbus_clouds::Path::Slices;
    let sliced = CloudVariant::new(lib.genus("cumulus").expect("genus"), Quality::Low, sliced).key;
    keys.push(ShaderKey::Clouds(sliced));
    keys.push(ShaderKey::Bake(sliced));
    // The 2D path of cumulus at low: its cloud pass and its map pass.
    let mut flat2d = Quality::Low.features();
    flat2d.path = nimbus_clouds::Path::Blob2d;
    let flat2d = CloudVariant::new(lib.genus("cumulus").expect("genus"), Quality::Low, flat2d).key;
    keys.push(ShaderKey::Clouds(flat2d));
    keys.push(ShaderKey::Bake(flat2d));
    // The impostor path of cumulus at low: its cloud pass and its bake.
    let mut impostor = Quality::Low.features();
    impostor.path = nimbus_clouds::Path::Impostor;
    let impostor =
        CloudVariant::new(lib.genus("cumulus").expect("genus"), Quality::Low, impostor).key;
    keys.push(ShaderKey::Clouds(impostor));
    keys.push(ShaderKey::Bake(impostor));
    // The mesh path of cumulus at low: its cloud pass and its cluster table.
    let mut mesh = Quality::Low.features();
    mesh.path = nimbus_clouds::Path::Mesh;
    let mesh = CloudVariant::new(lib.genus("cumulus").expect("genus"), Quality::Low, mesh).key;
    keys.push(ShaderKey::Clouds(mesh));
    keys.push(ShaderKey::Bake(mesh));
    for key in keys {
        let g = generate_variant(&key, &Target::ALL).expect("generate");
        insta::assert_snapshot!(format!("{}.wgsl", g.id()), g.wgsl);
        for f in &g.files {
            match &f.contents {
                Contents::Text(t) if f.target != Target::Wgsl => {
                    insta::assert_snapshot!(f.file_name.clone(), t);
                }
                Contents::SpirV(words) => {
                    insta::assert_snapshot!(f.file_name.clone(), common::spirv_text(words));
                }
                _ => {}
            }
        }
    }
}

/// The code of a WGSL module without its comments (which name the key).
fn code_of(wgsl: &str) -> String {
    wgsl.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn distinct_emitted_shaders_have_distinct_code() {
    // The catalogue: no two modules of the same stage print the same code.
    let lib = library();
    let mut seen: BTreeMap<(String, String), String> = BTreeMap::new();
    for v in cloud_catalog(&lib) {
        let (_, wgsl, _, _) = print_and_validate(v.record().expect("record"), &v.variant())
            .unwrap_or_else(|e| panic!("{}: {e}", v.id()));
        if let Some(other) = seen.insert((v.module().to_string(), code_of(&wgsl)), v.id()) {
            panic!("{} and {other} print the same code", v.id());
        }
    }
    assert!(seen.len() >= 9, "{}", seen.len());
}

#[test]
fn every_toggle_combination_gives_distinct_code_for_distinct_canonical_keys() {
    // Every combination of the toggles that touch one another's code (the shadow map is read
    // by shadows and by shafts, shafts live in the haze, the Mie toggle picks the phase) for a
    // dual-lobe genus: canonical keys that differ print different code, and combinations that
    // canonicalise alike are one key (shafts without haze, the Mie toggle as a phase kind).
    let varied = [
        Toggle::ShapeDetail,
        Toggle::Turbulence,
        Toggle::LightShafts,
        Toggle::Haze,
        Toggle::Shadows,
        Toggle::AccuratePhaseFunction,
    ];
    let mut by_key: BTreeMap<String, CloudKey> = BTreeMap::new();
    for bits in 0u32..(1 << varied.len()) {
        let mut f = Features::default();
        for (i, &t) in varied.iter().enumerate() {
            t.set(&mut f, bits & (1 << i) != 0);
        }
        let phase = PhaseSpec::DualLobe {
            g1: 0.7,
            g2: -0.2,
            weight: 0.5,
        };
        let key = CloudKey::new(f, &phase, 1);
        by_key.insert(key.name(), key);
    }
    // 2³ for detail, turbulence and shadows; 3 of the 4 shaft/haze pairs; 2 phase kinds.
    assert_eq!(by_key.len(), 8 * 3 * 2);
    let mut seen: BTreeMap<String, String> = BTreeMap::new();
    for (name, key) in &by_key {
        let (_, wgsl, _, _) =
            print_and_validate(cloud_module(key).expect("record"), name).expect("valid");
        if let Some(other) = seen.insert(code_of(&wgsl), name.clone()) {
            panic!("{name} and {other} print the same code: a key bit changes nothing");
        }
    }
}

#[test]
fn more_than_four_layers_use_a_second_lane_group() {
    let lib = library();
    let mut genus = lib.genus("takram-default").expect("genus").clone();
    let extra = genus.layers[0].clone();
    for i in 0..3 {
        let mut l = extra.clone();
        l.altitude = 3000.0 + 1000.0 * i as f32;
        l.height = 500.0;
        genus.layers.push(l);
    }
    genus.validate().expect("seven layers are valid");
    assert_eq!(genus.layer_groups(), 2);
    let v = CloudVariant::new(&genus, Quality::High, Quality::High.features());
    let g = generate(
        cloud_module(&v.key).expect("records"),
        "seven",
        &Target::ALL,
    )
    .expect("validates");
    // Two groups: the layer-group loops walk the array.
    assert!(
        g.wgsl.contains("group < 2u") && g.wgsl.contains("clouds.groups[group]"),
        "second group unused:\n{}",
        g.wgsl
    );
    let four = build(
        &lib,
        "takram-default",
        Quality::High,
        Quality::High.features(),
    );
    // One group: each loop is unrolled to its one iteration, on group 0.
    assert!(
        !four.wgsl.contains("< 2u") && !four.wgsl.contains("groups[1u]"),
        "a four-layer genus must not read group 1"
    );
    assert!(
        four.wgsl.contains("layers_containing(h, 0u)"),
        "{}",
        four.wgsl
    );
}

/// The engine's depth is loaded texel by texel, never sampled: its binding is declared
/// unfilterable (so a WebGPU `depth32float` texture and an `r32float` one without
/// FLOAT32_FILTERABLE bind), and every texture the march samples stays filterable.
#[test]
fn the_engine_depth_is_the_one_unfilterable_texture() {
    let lib = library();
    let mut features = Quality::High.features();
    features.scene_depth = true;
    let g = build(&lib, "cumulus", Quality::High, features);
    let mut seen = 0;
    for b in &g.bindings {
        if let nimbus_codegen::BindingKind::Texture { filterable, .. } = b.kind {
            seen += 1;
            assert_eq!(
                filterable,
                b.name != "scene_depth_texture",
                "{}: filterable {filterable}",
                b.name
            );
        }
    }
    assert!(seen >= 4, "{seen} textures");
    assert!(
        g.wgsl.contains("textureLoad(scene_depth_texture"),
        "the depth is loaded"
    );
    // GLSL names the loaded texture as a combined sampler with no sampler (texelFetch).
    let es = g
        .files
        .iter()
        .find(|f| f.file_name.ends_with(".es300.frag"))
        .and_then(|f| f.manifest.as_ref())
        .expect("a GLSL ES fragment manifest");
    let depth = es
        .combined_samplers
        .iter()
        .find(|c| c.texture == "scene_depth_texture")
        .expect("the depth's combined sampler");
    assert_eq!(depth.sampler, None);
}
