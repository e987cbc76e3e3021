//! `nimbus emit --engine E`: a package another engine runs with no Nimbus code. For each genus ×
//! preset pair of the selection it holds every pass the pair draws (shadow atlas when its key
//! samples one, clouds, temporal resolve, display transform) in the engine's language, the
//! noise textures as files, the uniform blocks' layouts with the pair's values, and
//! `nimbus-package.json`: the pass graph (order, targets, formats, what each binding slot
//! holds, how the engine names it) and the conventions that make the first frame right.

use nimbus_clouds::view_defaults::VIEW_DEFAULTS;
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::path::Path;

use nimbus_clouds::catalog::{Assignment, ShaderKey};
use nimbus_clouds::model::air_table::air_table_size;
use nimbus_clouds::model::bake::{bake_ignores, bake_size};
use nimbus_clouds::model::bindings::{
    CloudBinding, DisplayBinding, ResolveBinding, SunLightBinding,
};
use nimbus_clouds::model::blob2d::blob2d_size;
use nimbus_clouds::model::display::DisplayParams;
use nimbus_clouds::model::impostor::impostor_size;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::mesh::mesh_size;
use nimbus_clouds::model::resolve::ResolveParams;
use nimbus_clouds::model::resource::Resource;
use nimbus_clouds::model::scene_depth::SceneDepthParams;
use nimbus_clouds::model::shadow::ShadowParams;
use nimbus_clouds::model::slices::slices_size;
use nimbus_codegen::external::{ExternalCheck, check_files};
use nimbus_codegen::{
    BindingInfo, EmitExtras, Generated, emit, flatten_uniform_blocks, generate, print_csharp,
    print_dts, print_js,
};
use nimbus_codegen::{BindingKind, TextureDimension};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::ir::{AddressMode, FilterMode, SamplerDesc, Type};
use nimbus_dsl::layout::{LayoutError, UniformBytes, member_layout};
use nimbus_output::{Overwrite, check_folder};
use nimbus_runtime::render::TextureSizes;
use nimbus_runtime::textures::NoiseKind;

use crate::data::{Resolved, Selection, load, resolve, table_text};
use crate::engine::Engine;
use crate::error::CliError;
use crate::package_description::{
    AtlasSize, Bake, BindGroupLayout, BindingDescription, BlockMember, CameraKind,
    DescriptorSetLayout, FORMAT_VERSION, GpuBufferLayout, GpuLayoutEntry, GpuSamplerLayout,
    GpuTextureLayout, NameInFile, Output, PACKAGE_FILE, PACKAGE_SCHEMA_FILE, PackageDescription,
    Pair, Pass, PassDescription, ResourceEntry, SamplerDescriptor, ShaderFile, Target, Targets,
    Temporal, UNIFORMS_SCHEMA_FILE, UniformBlockFile, VulkanBarrier, VulkanLayoutBinding,
    VulkanSampler, pretty, schema_files,
};
use crate::package_textures::texture_files;

/// The JavaScript twin of `sun_light`, in packages for engines with a JavaScript host.
const SUN_MODULE: &str = "nimbus-sun.js";

/// The JavaScript twins of the wind's velocity, the weather's ramp and the altitude the
/// resolve moves with the wind (`timeline::host_module`), in packages for engines with a
/// JavaScript host.
const WIND_MODULE: &str = "nimbus-wind.js";

/// The JavaScript twins of the frame sequence (`frame_sequence::host_module`): what a host
/// writes into the cloud and resolve blocks each frame, in packages for engines with a
/// JavaScript host.
const FRAME_MODULE: &str = "nimbus-frame.js";

/// What `FRAME_MODULE` exports.
const FRAME_EXPORTS: [&str; 3] = ["cloud_frame", "resolve_frame", "drift_at"];

/// The Unity host: a camera component of the built-in pipeline that loads the package.
const UNITY_HOST: (&str, &str) = (
    "NimbusClouds.cs",
    include_str!("../assets/unity/NimbusClouds.cs"),
);

/// The Metal host sample: a Swift `MTKViewDelegate` that loads the package.
const METAL_HOST: (&str, &str) = (
    "NimbusMetal.swift",
    include_str!("../assets/metal/NimbusMetal.swift"),
);

/// The C# twins' files (each a static class named as the file) and what the sun's exports.
pub(crate) const CS_SUN: &str = "NimbusSun.cs";
pub(crate) const CS_WIND: &str = "NimbusWind.cs";
pub(crate) const CS_FRAME: &str = "NimbusFrame.cs";
const CS_SUN_EXPORTS: [&str; 1] = ["sun_direction"];

/// What `SUN_MODULE` exports.
const SUN_EXPORTS: [&str; 9] = [
    "sun_direction",
    "sun_light",
    "atlas_columns",
    "atlas_rows",
    "shadow_anchor",
    "redrawn_tiles",
    "anchored_tiles",
    "tiles_out_of_date",
    "band_redraw",
];

/// What `WIND_MODULE` exports: the functions and the altitude of a scene's top wind.
const WIND_EXPORTS: [&str; 7] = [
    "wind_velocity",
    "wind_velocity_at",
    "wind_drift",
    "weather_progress",
    "weather_coverage",
    "facing_altitude",
    "TOP_ALTITUDE",
];

/// What every JavaScript host of a package keeps and writes into the blocks, with no graphics
/// API (`NimbusHost`: camera, sun, timeline, frame sequence), and the timeline's weather states
/// (`NimbusTimeline`), with their TypeScript declarations: shipped in three and webgpu packages,
/// used by their renderers.
const HOST_MODULES: [(&str, &str); 4] = [
    (
        "nimbus-host.js",
        include_str!("../assets/host/nimbus-host.js"),
    ),
    (
        "nimbus-host.d.ts",
        include_str!("../assets/host/nimbus-host.d.ts"),
    ),
    (
        "nimbus-timeline.js",
        include_str!("../assets/host/nimbus-timeline.js"),
    ),
    (
        "nimbus-timeline.d.ts",
        include_str!("../assets/host/nimbus-timeline.d.ts"),
    ),
];

/// The three.js files a three package ships: the renderer of the package (with its TypeScript
/// declarations), an EffectComposer pass around it, and an example page where the sun moves
/// (`npx serve DIR`, open `example.html`).
const THREE_MODULES: [(&str, &str); 4] = [
    (
        "nimbus-clouds.js",
        include_str!("../assets/three/nimbus-clouds.js"),
    ),
    (
        "nimbus-clouds.d.ts",
        include_str!("../assets/three/nimbus-clouds.d.ts"),
    ),
    (
        "nimbus-clouds-pass.js",
        include_str!("../assets/three/nimbus-clouds-pass.js"),
    ),
    ("example.html", include_str!("../assets/three/example.html")),
];

/// The WebGPU host: draws a webgpu package with the API alone (`NimbusWebGPU`), and its
/// TypeScript declarations.
const WEBGPU_MODULES: [(&str, &str); 2] = [
    (
        "nimbus-webgpu.js",
        include_str!("../assets/webgpu/nimbus-webgpu.js"),
    ),
    (
        "nimbus-webgpu.d.ts",
        include_str!("../assets/webgpu/nimbus-webgpu.d.ts"),
    ),
];

/// A page of the README: a tower of the user's scene standing in the clouds (three packages
/// built with `--enable scene-depth`).
const TOWER_PAGE: (&str, &str) = ("tower.html", include_str!("../assets/three/tower.html"));

/// Format of every intermediate target (linear HDR radiance, alpha = cloud opacity).
const HDR_FORMAT: &str = "rgba16float";

pub(crate) fn run(
    data: Option<&Path>,
    sel: &Selection<'_>,
    scene: Option<(&Path, f64)>,
    engine: Engine,
    (out, overwrite): (&Path, Overwrite),
) -> Result<(), Box<dyn std::error::Error>> {
    check_folder(out, overwrite)?;
    let resolved = match scene {
        Some((file, seconds)) => crate::explain::resolved(data, file, sel, seconds)?,
        None => resolve(sel, &load(data)?)?,
    };
    let package = build(&resolved, engine)?;
    // The engine's own compiler where this machine has one; naga validated every file already.
    let mut checked = Vec::new();
    let files: Vec<_> = package.shaders.iter().flat_map(|g| &g.files).collect();
    for (f, check) in files.iter().zip(check_files(&files)) {
        match check {
            ExternalCheck::Passed { tool } => checked.push(tool),
            ExternalCheck::Failed { tool, output } => {
                return Err(CliError::External {
                    tool,
                    file: f.file_name.clone(),
                    output,
                }
                .into());
            }
            ExternalCheck::ToolMissing { tool } => {
                say!("not checked by {tool}: it is not installed here")
            }
            ExternalCheck::NotApplicable => {}
        }
    }
    let validated_by = match checked.first() {
        Some(tool) => format!("naga and {tool} ({} files)", checked.len()),
        None => format!("naga; {}", engine.unchecked_note()),
    };
    let report = emit(&package.shaders, &package.extras, out, overwrite)?;
    say!("validated by {validated_by}");
    say!(
        "{} package: {} pass shader(s) for {} genus × preset pair(s), {} texture(s) from {}",
        engine.name(),
        package.shaders.len(),
        resolved.table.len(),
        package.texture_count,
        package.textures_from
    );
    say!(
        "wrote {} files to {} (start with {PACKAGE_FILE} and README.md)",
        report.files.len(),
        report.dir.display()
    );
    Ok(())
}

/// A package in memory: generated and validated shaders, and every other file.
pub(crate) struct Package {
    pub shaders: Vec<Generated>,
    pub extras: EmitExtras,
    pub texture_count: usize,
    pub textures_from: String,
}

/// Whether the shadow atlas of pair `pair` fits the textures every device of `engine` can
/// make.
fn check_atlas(pair: &str, shadow: &ShadowParams, engine: Engine) -> Result<(), CliError> {
    let limits = engine.limits();
    let (width, height) = shadow.atlas_size();
    if width.max(height) <= limits.texture_2d {
        return Ok(());
    }
    Err(CliError::EngineLimit {
        engine: engine.name(),
        what: format!(
            "{pair}: the shadow atlas ({} cascades of {} px, {width}×{height})",
            shadow.cascade_count, shadow.map_size
        ),
        size: width.max(height),
        limit: limits.texture_2d,
        basis: limits.source,
    })
}

/// Every file of the package for `resolved`, or the first reason the engine cannot run it.
pub(crate) fn build(resolved: &Resolved, engine: Engine) -> Result<Package, CliError> {
    let Resolved {
        table, uniforms, ..
    } = resolved;
    if table.is_empty() {
        return Err(CliError::NoPairs);
    }
    // The baked paths' renderers run in Nimbus's runtime and the JavaScript hosts (three.js,
    // WebGPU); the other engines' hosts do not draw a bake pass yet.
    if let Some(a) = table.iter().find(|a| {
        a.clouds.features.path != nimbus_clouds::Path::Volume
            && !(matches!(engine, Engine::Three | Engine::Webgpu) && a.clouds.bakes())
    }) {
        return Err(CliError::PathWithoutPackage {
            engine: engine.name(),
            pair: a.name(),
            path: a.clouds.features.path,
        });
    }
    let limits = engine.limits();
    let sizes = TextureSizes::default();
    for (a, u) in table.iter().zip(uniforms) {
        if a.shadow.is_some() {
            check_atlas(&a.name(), &u.shadow, engine)?;
        }
    }
    for (what, size, limit) in [
        ("the weather texture", sizes.weather, limits.texture_2d),
        (
            "the turbulence texture",
            sizes.turbulence,
            limits.texture_2d,
        ),
        ("the shape texture (3D)", sizes.shape, limits.texture_3d),
        ("the detail texture (3D)", sizes.detail, limits.texture_3d),
    ] {
        if size > limit {
            return Err(CliError::EngineLimit {
                engine: engine.name(),
                what: what.to_string(),
                size,
                limit,
                basis: limits.source,
            });
        }
    }

    // Each distinct shader once, then the passes of every pair refer to them.
    let mut keys: Vec<ShaderKey> = Vec::new();
    for a in table {
        for k in a.keys() {
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
    }
    keys.extend([ShaderKey::Resolve, ShaderKey::Display]);
    if table.iter().any(casts_scene_shadow) {
        keys.push(ShaderKey::SceneShadow);
    }
    if engine.sun_kernel() {
        keys.push(ShaderKey::SunLight);
    }
    let target = engine.target();
    // Every key on every core; the first failure in key order is the one reported.
    let shaders: Vec<Generated> = keys
        .par_iter()
        .map(|k| {
            let mut module = k.record()?;
            if engine.flat_uniforms() {
                flatten_uniform_blocks(&mut module);
            }
            generate(module, &k.variant(), &[target])
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    let shader = |k: ShaderKey| keys.iter().position(|x| *x == k).map(|i| &shaders[i]);

    // The textures some pair's shaders bind, made once.
    let mut kinds = BTreeSet::new();
    for g in &shaders {
        for b in &g.bindings {
            if let Some(kind) =
                CloudBinding::at(b.group, b.binding).and_then(|c| NoiseKind::of(c.resource()))
            {
                kinds.insert(kind);
            }
        }
    }
    let kinds: Vec<NoiseKind> = kinds.into_iter().collect();
    let texels = texture_files(&kinds, sizes).map_err(|e| CliError::Textures(e.to_string()))?;

    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let mut pairs = Vec::new();
    for (a, u) in table.iter().zip(uniforms) {
        let uniforms_file = format!("uniforms/{}.json", a.name());
        files.push((uniforms_file.clone(), pretty(&uniform_file(a, u)?)));
        let mut passes = Vec::new();
        if let Some(g) = shader(ShaderKey::SunLight) {
            passes.push(pass_description(Pass::SunLight, g, engine)?);
        }
        if let Some(k) = a.shadow
            && let Some(g) = shader(ShaderKey::Shadow(k))
        {
            passes.push(pass_description(Pass::Shadow, g, engine)?);
        }
        if casts_scene_shadow(a)
            && let Some(g) = shader(ShaderKey::SceneShadow)
        {
            passes.push(pass_description(Pass::SceneShadow, g, engine)?);
        }
        if a.clouds.reads_air_table()
            && let Some(g) = shader(ShaderKey::AirTable)
        {
            passes.push(pass_description(Pass::Air, g, engine)?);
        }
        if a.clouds.bakes()
            && let Some(g) = shader(ShaderKey::Bake(a.clouds))
        {
            passes.push(pass_description(Pass::Bake, g, engine)?);
        }
        if let Some(g) = shader(ShaderKey::Clouds(a.clouds)) {
            passes.push(pass_description(Pass::Clouds, g, engine)?);
        }
        for (pass, key) in [
            (Pass::Resolve, ShaderKey::Resolve),
            (Pass::Display, ShaderKey::Display),
        ] {
            if let Some(g) = shader(key) {
                passes.push(pass_description(pass, g, engine)?);
            }
        }
        if engine == Engine::Vulkan {
            vulkan_barriers(&mut passes);
        }
        pairs.push(Pair {
            pair: a.name(),
            genus: a.genus.clone(),
            quality: a.quality.name().to_string(),
            uniforms: uniforms_file,
            camera: if a.clouds.features.orthographic {
                CameraKind::Orthographic
            } else {
                CameraKind::Perspective
            },
            scene_depth: a.clouds.features.scene_depth,
            shadow_atlas: a.shadow.map(|_| {
                let (width, height) = u.shadow.atlas_size();
                AtlasSize { width, height }
            }),
            air_table: a.clouds.reads_air_table().then(|| {
                let (width, height) = air_table_size();
                AtlasSize { width, height }
            }),
            cloud_bake: bake_size(a.clouds.features.path)
                .filter(|_| a.clouds.bakes())
                .map(|(width, height)| Bake {
                    width,
                    height,
                    ignores: bake_ignores(&a.clouds)
                        .iter()
                        .map(|m| m.to_string())
                        .collect(),
                }),
            passes,
        });
    }
    let resolve_defaults = ResolveParams {
        inverse_view_projection: glam::Mat4::IDENTITY,
        previous_view_projection: glam::Mat4::IDENTITY,
        cloud_shift: glam::Vec3::ZERO,
        cloud_altitude: 1500.0,
        camera_altitude: VIEW_DEFAULTS.camera_altitude,
        planet_radius: nimbus_clouds::model::shell::EARTH_RADIUS,
        resolution: glam::Vec2::new(VIEW_DEFAULTS.width as f32, VIEW_DEFAULTS.height as f32),
        low_resolution: glam::Vec2::new(
            VIEW_DEFAULTS.width.div_ceil(4) as f32,
            VIEW_DEFAULTS.height.div_ceil(4) as f32,
        ),
        pixel_offset: glam::Vec2::ZERO,
        pixel_scale: 4.0,
        current_weight: 1.0,
        variance_gamma: 2.0,
        history_valid: 0.0,
    };
    let display_defaults = DisplayParams {
        flip_y: if engine.bottom_up() { 1.0 } else { 0.0 },
        ..DisplayParams::default()
    };
    for (name, block) in [
        (
            "uniforms/resolve.json",
            block_file(
                ResolveParams::shader_type(),
                &resolve_defaults.to_uniform_bytes()?,
                RESOLVE_NOTES,
            ),
        ),
        (
            "uniforms/display.json",
            block_file(
                DisplayParams::shader_type(),
                &display_defaults.to_uniform_bytes()?,
                DISPLAY_NOTES,
            ),
        ),
    ] {
        files.push((name.to_string(), pretty(&block)));
    }
    if table.iter().any(|a| a.clouds.features.scene_depth) {
        // The engine's depth encoding: an OpenGL-style perspective buffer until the host says
        // otherwise.
        let d = VIEW_DEFAULTS;
        let scene = SceneDepthParams::opengl(
            glam::Mat4::perspective_rh_gl(
                d.fov_deg.to_radians(),
                d.width as f32 / d.height as f32,
                1.0,
                1e6,
            ),
            glam::Mat4::IDENTITY,
            -glam::Vec3::Z,
            d.width,
            d.height,
        );
        files.push((
            "uniforms/scene.json".to_string(),
            pretty(&block_file(
                SceneDepthParams::shader_type(),
                &scene.to_uniform_bytes()?,
                SCENE_NOTES,
            )),
        ));
    }
    let texture_count = texels.files.len();
    let mut textures = Vec::new();
    for t in texels.files {
        files.push((t.file, t.bytes));
        textures.push(t.descriptor);
    }
    // Every resource some pass of the package binds, once, in the order of `Resource::ALL`.
    let bound: BTreeSet<Resource> = pairs
        .iter()
        .flat_map(|p| &p.passes)
        .flat_map(|p| &p.bindings)
        .map(|b| b.holds.id)
        .collect();
    let description = PackageDescription {
        schema: PACKAGE_SCHEMA_FILE.to_string(),
        nimbus_package: FORMAT_VERSION,
        engine: engine.name().to_string(),
        language: engine.language().to_string(),
        conventions: engine
            .conventions()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
        bindings: engine.binding_note().to_string(),
        frame: frame_order(engine).into_iter().map(String::from).collect(),
        temporal: Temporal {
            sequence: "each frame's cloud-block members (frame, jitter, pixel_offset, \
                       pixel_scale, subpixel) are cloud_frame(index, seed, upscale) and the \
                       resolve block's (low_resolution, pixel_offset, pixel_scale, \
                       current_weight, variance_gamma, history_valid, cloud_shift) \
                       resolve_frame(...), each result field written to the member of the \
                       same name; index counts frames since the history started (0 for a \
                       frame nothing resolves). nimbus-frame.js in JavaScript packages; the \
                       Rust source is nimbus_clouds::frame_sequence"
                .to_string(),
        },
        resources: bound.into_iter().map(ResourceEntry::of).collect(),
        targets: targets(),
        textures,
        textures_generated_by: texels.generated_by.clone(),
        texel_halves: (0..=u8::MAX)
            .map(nimbus_runtime::textures::texel_half_bits)
            .collect(),
        pairs,
    };
    files.push((PACKAGE_FILE.to_string(), pretty(&description)));
    for (file, schema) in schema_files() {
        files.push((file.to_string(), schema));
    }
    if engine.javascript_host() {
        // What the sun's position decides, as the host computes it: the JavaScript twin of
        // the same `sun_light` whose CPU twin fills the uniform values above.
        // What the wind and the weather change as the scene runs: the JavaScript twins of the
        // same functions whose CPU twins give `nimbus render --time` its drift and coverage;
        // and the frame sequence, as the runtime's render loop computes it. Each with its
        // TypeScript declarations, printed from the same IR.
        for (file, host, exports) in [
            (
                SUN_MODULE,
                nimbus_clouds::model::sun::host_module()?,
                &SUN_EXPORTS[..],
            ),
            (
                WIND_MODULE,
                nimbus_clouds::timeline::host_module()?,
                &WIND_EXPORTS[..],
            ),
            (
                FRAME_MODULE,
                nimbus_clouds::frame_sequence::host_module()?,
                &FRAME_EXPORTS[..],
            ),
        ] {
            files.push((file.to_string(), print_js(&host, exports)?.into_bytes()));
            let typings = file.replace(".js", ".d.ts");
            files.push((typings, print_dts(&host, exports)?.into_bytes()));
        }
        for (name, text) in HOST_MODULES {
            files.push((name.to_string(), text.as_bytes().to_vec()));
        }
    }
    if engine == Engine::Webgpu {
        // The ES module that draws the package with the WebGPU API alone.
        for (name, text) in WEBGPU_MODULES {
            files.push((name.to_string(), text.as_bytes().to_vec()));
        }
    }
    if engine == Engine::Unity {
        // Each pass's HLSL as a Unity asset: a ShaderLab shader, or the kernel's compute shader.
        for g in &shaders {
            let (name, text) = crate::unity_shaderlab::unity_wrapper(g);
            files.push((name, text.into_bytes()));
        }
        // The host functions a C# host calls (the sun's other effects run on the GPU, in the
        // `sun_light` kernel), printed from the same IR as the JavaScript twins.
        for (file, host, exports) in [
            (
                CS_SUN,
                nimbus_clouds::model::sun::host_module()?,
                &CS_SUN_EXPORTS[..],
            ),
            (
                CS_WIND,
                nimbus_clouds::timeline::host_module()?,
                &WIND_EXPORTS[..],
            ),
            (
                CS_FRAME,
                nimbus_clouds::frame_sequence::host_module()?,
                &FRAME_EXPORTS[..],
            ),
        ] {
            let class = file.trim_end_matches(".cs");
            files.push((
                file.to_string(),
                print_csharp(&host, exports, class)?.into_bytes(),
            ));
        }
        // The component that runs the passes with a command buffer.
        files.push((UNITY_HOST.0.to_string(), UNITY_HOST.1.as_bytes().to_vec()));
    }
    if engine == Engine::Metal {
        // A Swift MTKView delegate that draws the package's still frame (not compiled here).
        files.push((METAL_HOST.0.to_string(), METAL_HOST.1.as_bytes().to_vec()));
    }
    if engine == Engine::Three {
        // The ES modules that draw the package with three.js alone.
        for (name, text) in THREE_MODULES {
            files.push((name.to_string(), text.as_bytes().to_vec()));
        }
        // Clouds in a scene of the user's: the README's tower page, for the pairs that read
        // the engine's depth.
        if table.iter().any(|a| a.clouds.features.scene_depth) {
            files.push((TOWER_PAGE.0.to_string(), TOWER_PAGE.1.as_bytes().to_vec()));
        }
    }
    files.push(("README.md".to_string(), readme(engine, table).into_bytes()));
    Ok(Package {
        shaders,
        extras: EmitExtras {
            manifest_appendix: table_text(table),
            files,
        },
        texture_count,
        textures_from: texels.generated_by,
    })
}

/// Whether `a`'s clouds shadow the engine's objects: its key reads the engine's depth through a
/// perspective camera and has a shadow atlas to read the shadow from.
fn casts_scene_shadow(a: &Assignment) -> bool {
    let f = a.clouds.features;
    f.scene_depth && !f.orthographic && a.shadow.is_some()
}

/// What a host binds at a pass's slot: the [`Resource`] the pass's binding enum declares there.
fn resource_at(pass: Pass, b: &BindingInfo) -> Option<Resource> {
    let (group, binding) = (b.group, b.binding);
    match pass {
        Pass::SunLight => SunLightBinding::at(group, binding).map(SunLightBinding::resource),
        Pass::Shadow | Pass::SceneShadow | Pass::Air | Pass::Bake | Pass::Clouds => {
            CloudBinding::at(group, binding).map(CloudBinding::resource)
        }
        Pass::Resolve => ResolveBinding::at(group, binding).map(ResolveBinding::resource),
        Pass::Display => DisplayBinding::at(group, binding).map(DisplayBinding::resource),
    }
}

fn pass_description(
    pass: Pass,
    g: &Generated,
    engine: Engine,
) -> Result<PassDescription, CliError> {
    let files = g
        .files
        .iter()
        .map(|f| ShaderFile {
            file: f.file_name.clone(),
            entry_point: f.entry_point.as_ref().map(|(e, _)| e.clone()),
            stage: f
                .entry_point
                .as_ref()
                .map(|(_, s)| format!("{s:?}").to_lowercase()),
            manifest: f.manifest.as_ref().map(|_| format!("{}.json", f.file_name)),
            buffer_sizes: f.manifest.as_ref().and_then(|m| m.buffer_sizes.clone()),
        })
        .collect();
    let mut bindings = Vec::new();
    for b in &g.bindings {
        let Some(resource) = resource_at(pass, b) else {
            return Err(CliError::UndeclaredBinding {
                shader: g.id(),
                binding: b.name.clone(),
                group: b.group,
                slot: b.binding,
            });
        };
        let mut in_files = Vec::new();
        for m in g.files.iter().filter_map(|f| f.manifest.as_ref()) {
            // The stages of the file (one; every one of the module in an HLSL file) that see
            // the binding.
            let stages: Vec<&String> = m
                .entry_points
                .keys()
                .filter(|s| b.visibility.iter().any(|v| v.name() == s.as_str()))
                .collect();
            for stage in stages {
                in_files.extend(
                    m.bindings
                        .iter()
                        .filter(|mb| (mb.group, mb.binding) == (b.group, b.binding))
                        .filter(|mb| !mb.target_name.is_empty())
                        .map(|mb| NameInFile {
                            stage: stage.clone(),
                            name: Some(mb.target_name.clone()),
                            combined_sampler: None,
                        }),
                );
                in_files.extend(
                    m.combined_samplers
                        .iter()
                        .filter(|c| c.texture == b.name || c.sampler.as_ref() == Some(&b.name))
                        .map(|c| NameInFile {
                            stage: stage.clone(),
                            name: None,
                            combined_sampler: Some(c.name.clone()),
                        }),
                );
            }
        }
        bindings.push(BindingDescription {
            group: b.group,
            binding: b.binding,
            name: b.name.clone(),
            kind: b.kind.word().to_string(),
            wgsl_type: b.wgsl_type.clone(),
            holds: ResourceEntry::of(resource),
            in_files,
        });
    }
    // The module's entry points by stage: what a pipeline descriptor names (a WGSL file holds
    // them all; the other languages have a file each).
    let entry_points =
        g.ir.entry_points
            .iter()
            .map(|e| (format!("{:?}", e.stage).to_lowercase(), e.function.clone()))
            .collect();
    let (bind_group_layout, descriptor_set_layout) = match engine {
        Engine::Webgpu | Engine::Wgpu => (Some(bind_group_layout(g)), None),
        Engine::Vulkan => (None, Some(descriptor_set_layout(g))),
        Engine::Three | Engine::Unity | Engine::Metal => (None, None),
    };
    Ok(PassDescription {
        pass,
        shader: g.id(),
        language: engine.language().to_string(),
        entry_points,
        files,
        bindings,
        bind_group_layout,
        descriptor_set_layout,
        dispatch: (pass == Pass::SunLight).then_some([1, 1, 1]),
        writes: match pass {
            Pass::SunLight => Output::Pair,
            Pass::Shadow => Output::ShadowAtlas,
            Pass::SceneShadow => Output::SceneShadow,
            Pass::Air => Output::AirTable,
            Pass::Bake => Output::CloudBake,
            Pass::Clouds => Output::CloudsHdr,
            Pass::Resolve => Output::History,
            Pass::Display => Output::Screen,
        },
        vulkan_barriers: None,
    })
}

/// A binding's stages in words, and as the API's flags given the flag of each stage.
fn stage_names(b: &BindingInfo) -> Vec<&'static str> {
    b.visibility
        .iter()
        .map(|s| match s {
            nimbus_dsl::ir::Stage::Vertex => "VERTEX",
            nimbus_dsl::ir::Stage::Fragment => "FRAGMENT",
            nimbus_dsl::ir::Stage::Compute => "COMPUTE",
        })
        .collect()
}

fn stage_flags(b: &BindingInfo, [vertex, fragment, compute]: [u32; 3]) -> u32 {
    b.visibility
        .iter()
        .map(|s| match s {
            nimbus_dsl::ir::Stage::Vertex => vertex,
            nimbus_dsl::ir::Stage::Fragment => fragment,
            nimbus_dsl::ir::Stage::Compute => compute,
        })
        .fold(0, |a, f| a | f)
}

/// The pass's bindings as a WebGPU `GPUBindGroupLayoutDescriptor` (with the samplers'
/// `GPUSamplerDescriptor`s), to hand to the API as it is.
fn bind_group_layout(g: &Generated) -> BindGroupLayout {
    let entries = g
        .bindings
        .iter()
        .map(|b| {
            let mut entry = GpuLayoutEntry {
                binding: b.binding,
                // GPUShaderStage: VERTEX 1, FRAGMENT 2, COMPUTE 4.
                visibility: stage_flags(b, [1, 2, 4]),
                visibility_names: stage_names(b).join(" | "),
                buffer: None,
                texture: None,
                sampler: None,
                sampler_descriptor: None,
            };
            match &b.kind {
                BindingKind::Uniform { size, .. } => {
                    entry.buffer = Some(GpuBufferLayout {
                        kind: "uniform".into(),
                        min_binding_size: Some(*size as u64),
                    })
                }
                BindingKind::Storage { read_write } => {
                    entry.buffer = Some(GpuBufferLayout {
                        kind: if *read_write {
                            "storage"
                        } else {
                            "read-only-storage"
                        }
                        .into(),
                        min_binding_size: None,
                    })
                }
                BindingKind::Texture {
                    dimension,
                    filterable,
                } => {
                    entry.texture = Some(GpuTextureLayout {
                        // Loaded by texel only (the engine's depth): a depth texture binds here.
                        sample_type: if *filterable {
                            "float"
                        } else {
                            "unfilterable-float"
                        }
                        .into(),
                        view_dimension: match dimension {
                            TextureDimension::D2 => "2d",
                            TextureDimension::D3 => "3d",
                        }
                        .into(),
                    })
                }
                BindingKind::Sampler(desc) => {
                    entry.sampler = Some(GpuSamplerLayout {
                        kind: "filtering".into(),
                    });
                    entry.sampler_descriptor = Some(sampler_descriptor(*desc));
                }
            }
            entry
        })
        .collect();
    BindGroupLayout { group: 0, entries }
}

/// The pass's bindings as a Vulkan descriptor-set layout.
fn descriptor_set_layout(g: &Generated) -> DescriptorSetLayout {
    let bindings = g
        .bindings
        .iter()
        .map(|b| VulkanLayoutBinding {
            binding: b.binding,
            descriptor_type: match &b.kind {
                BindingKind::Uniform { .. } => "VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER",
                BindingKind::Storage { .. } => "VK_DESCRIPTOR_TYPE_STORAGE_BUFFER",
                BindingKind::Texture { .. } => "VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE",
                BindingKind::Sampler(_) => "VK_DESCRIPTOR_TYPE_SAMPLER",
            }
            .into(),
            descriptor_count: 1,
            // VkShaderStageFlagBits: VERTEX 0x1, FRAGMENT 0x10, COMPUTE 0x20.
            stage_flags: stage_flags(b, [0x1, 0x10, 0x20]),
            stage_flag_names: stage_names(b)
                .iter()
                .map(|s| format!("VK_SHADER_STAGE_{s}_BIT"))
                .collect::<Vec<_>>()
                .join(" | "),
            sampler: match &b.kind {
                BindingKind::Sampler(desc) => Some(vulkan_sampler(*desc)),
                _ => None,
            },
        })
        .collect();
    DescriptorSetLayout { set: 0, bindings }
}

/// A sampler's state in Vulkan's terms.
fn vulkan_sampler(desc: SamplerDesc) -> VulkanSampler {
    let address = match desc.address {
        AddressMode::Repeat => "VK_SAMPLER_ADDRESS_MODE_REPEAT",
        AddressMode::ClampToEdge => "VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE",
        AddressMode::MirrorRepeat => "VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT",
    };
    let (filter, mipmap) = match desc.filter {
        FilterMode::Nearest => ("VK_FILTER_NEAREST", "VK_SAMPLER_MIPMAP_MODE_NEAREST"),
        FilterMode::Linear => ("VK_FILTER_LINEAR", "VK_SAMPLER_MIPMAP_MODE_LINEAR"),
    };
    VulkanSampler {
        mag_filter: filter.into(),
        min_filter: filter.into(),
        mipmap_mode: mipmap.into(),
        address_mode_u: address.into(),
        address_mode_v: address.into(),
        address_mode_w: address.into(),
    }
}

/// The pass graph's barriers for Vulkan, pass by pass in frame order: before a pass, what an
/// earlier pass wrote and it reads (the block `sun_light` completes, read as uniforms; a
/// target, read by a fragment shader), and its own target made a colour attachment (its
/// contents discarded: every pass overwrites all of it).
fn vulkan_barriers(passes: &mut [PassDescription]) {
    let mut written: Vec<Output> = Vec::new();
    // Once made readable, a resource stays so for the rest of the frame.
    let mut readable: Vec<Resource> = Vec::new();
    for p in passes.iter_mut() {
        let mut barriers = Vec::new();
        for b in &p.bindings {
            let id = b.holds.id;
            if readable.contains(&id) {
                continue;
            }
            let producer = match id {
                Resource::Pair if written.contains(&Output::Pair) => Some("sun_light"),
                Resource::ShadowAtlas if written.contains(&Output::ShadowAtlas) => Some("shadow"),
                Resource::AirTable if written.contains(&Output::AirTable) => Some("air"),
                Resource::CloudBake if written.contains(&Output::CloudBake) => Some("bake"),
                Resource::CloudsHdr if written.contains(&Output::CloudsHdr) => Some("clouds"),
                Resource::Shown => Some("clouds or resolve"),
                Resource::HistoryRead => Some("the previous frame's resolve"),
                _ => None,
            };
            let Some(producer) = producer else { continue };
            readable.push(id);
            let name = serde_json::to_value(id)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            barriers.push(if id == Resource::Pair {
                VulkanBarrier {
                    resource: name,
                    reason: format!("{producer} wrote the block this pass reads as uniforms"),
                    src_stage_mask: "VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT".into(),
                    src_access_mask: "VK_ACCESS_SHADER_WRITE_BIT".into(),
                    dst_stage_mask: "VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT".into(),
                    dst_access_mask: "VK_ACCESS_UNIFORM_READ_BIT".into(),
                    old_layout: None,
                    new_layout: None,
                }
            } else {
                VulkanBarrier {
                    resource: name,
                    reason: format!("{producer} drew the target this pass samples"),
                    src_stage_mask: "VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT".into(),
                    src_access_mask: "VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT".into(),
                    dst_stage_mask: "VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT".into(),
                    dst_access_mask: "VK_ACCESS_SHADER_READ_BIT".into(),
                    old_layout: Some("VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL".into()),
                    new_layout: Some("VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL".into()),
                }
            });
        }
        if p.writes != Output::Pair {
            let name = serde_json::to_value(p.writes)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            barriers.push(VulkanBarrier {
                resource: name,
                reason:
                    "this pass draws all of its target; reads of it by earlier passes finish first"
                        .into(),
                src_stage_mask: "VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT".into(),
                src_access_mask: "VK_ACCESS_SHADER_READ_BIT".into(),
                dst_stage_mask: "VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT".into(),
                dst_access_mask: "VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT".into(),
                old_layout: Some("VK_IMAGE_LAYOUT_UNDEFINED".into()),
                new_layout: Some("VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL".into()),
            });
        }
        written.push(p.writes);
        p.vulkan_barriers = Some(barriers);
    }
}

/// A sampler's state in WebGPU's spelling.
fn sampler_descriptor(desc: SamplerDesc) -> SamplerDescriptor {
    let address = match desc.address {
        AddressMode::Repeat => "repeat",
        AddressMode::ClampToEdge => "clamp-to-edge",
        AddressMode::MirrorRepeat => "mirror-repeat",
    };
    let filter = match desc.filter {
        FilterMode::Nearest => "nearest",
        FilterMode::Linear => "linear",
    };
    SamplerDescriptor {
        address_mode_u: address.into(),
        address_mode_v: address.into(),
        address_mode_w: address.into(),
        mag_filter: filter.into(),
        min_filter: filter.into(),
        mipmap_filter: filter.into(),
    }
}

/// The frame, in order.
fn frame_order(engine: Engine) -> Vec<&'static str> {
    let mut steps = Vec::new();
    if engine.sun_kernel() {
        steps.push(
            "sun_light: when light.sun_direction or camera_altitude changed, write the block \
             (uniforms/<pair>.json, the new direction, any non-zero length) into the inputs \
             buffer and dispatch 1 × 1 × 1 workgroups; it writes the completed block that the \
             shadow and clouds passes bind",
        );
    }
    steps.extend([
        "shadow: draw into shadow_atlas when the pair has one and the sun, the layers or any \
         media member (weather offset, wind drift, coverage) changed since it was last drawn \
         (Nimbus's runtime caches it; drawing it every frame is correct too)",
        "air (pairs with an air pass): draw into air_table when light.sun_direction, \
         camera_altitude or the sky block changed since it was last drawn (its whole size, \
         once; drawing it every frame is correct too)",
        "bake (pairs drawn by a baked path: slices, impostor, mesh, blob2d): after the air table \
         (an impostor's bake that holds the whole picture reads it), draw into cloud_bake \
         when any member of the pair's block outside the pair's cloud_bake.ignores changed since it was \
         last drawn (its whole size, once; drawing it every frame is correct too)",
        "scene_shadow (pairs that read the engine's depth and have a shadow atlas): after the \
         engine's depth and the shadow atlas, draw into scene_shadow (the depth buffer's size): \
         per pixel, the sun's light through the clouds at the engine's surface (1 where it drew \
         nothing); the engine's materials scale their direct sunlight by it",
        "clouds: draw into clouds_hdr every frame (full size, or a quarter of each side when \
         upscaling: then set pixel_scale = 4 and pixel_offset to the frame's Bayer offset)",
        "resolve: when upscaling or accumulating, draw into the history target not read this \
         frame, reading clouds_hdr and the other history target; swap them after the frame",
        "display: draw into the screen (or the engine's next pass), reading the history target \
         resolve wrote, or clouds_hdr when there is no resolve",
    ]);
    steps
}

fn targets() -> Targets {
    let hdr = |size: &str| Target {
        format: HDR_FORMAT.into(),
        size: size.into(),
        sampled_as: None,
    };
    Targets {
        shadow_atlas: Target {
            sampled_as: Some(
                "with the pass's linear, repeat sampler (the shader keeps its coordinates inside \
                 each cascade)"
                    .into(),
            ),
            ..hdr("the pair's shadow_atlas width × height (its cascades in a grid of tiles)")
        },
        air_table: Target {
            sampled_as: Some(
                "with the clouds pass's linear, repeat sampler (the shader keeps its coordinates \
                 inside each slice and band)"
                    .into(),
            ),
            ..hdr(&format!(
                "{} × {} (the same for every pair)",
                air_table_size().0,
                air_table_size().1
            ))
        },
        cloud_bake: Target {
            sampled_as: Some(
                "with the clouds pass's linear, repeat sampler (the shader keeps its coordinates \
                 inside each tile)"
                    .into(),
            ),
            ..hdr(&format!(
                "the pair's cloud_bake size: {} × {} for the slices path, {} × {} for the \
                 impostor, {} × {} for the mesh, {} × {} for blob2d",
                slices_size().0,
                slices_size().1,
                impostor_size().0,
                impostor_size().1,
                mesh_size().0,
                mesh_size().1,
                blob2d_size().0,
                blob2d_size().1
            ))
        },
        clouds_hdr: hdr("the output size, or ceil(width / 4) × ceil(height / 4) when upscaling"),
        scene_shadow: hdr(
            "the engine's depth buffer's size (pairs with a scene_shadow pass); sampled one texel \
             per pixel by the engine's materials",
        ),
        history_a: hdr("the output size"),
        history_b: hdr("the output size"),
        screen: Target {
            format: "rgba8unorm (display sRGB already encoded: not an sRGB format)".into(),
            size: "the output size".into(),
            sampled_as: None,
        },
    }
}

/// What an engine sets in the cloud uniform block, by member.
const CLOUD_NOTES: &[(&str, &str)] = &[
    (
        "inverse_view_projection",
        "every frame: inverse of (projection × view) with the view's translation removed (the \
         camera is the origin of the local frame, y up; its height is camera_altitude); any \
         depth convention",
    ),
    ("resolution", "every frame: the output size in pixels"),
    (
        "pixel_scale",
        "every frame: 1 at full resolution, 4 when upscaling",
    ),
    (
        "pixel_offset",
        "every frame: the pixel of each 4×4 block shaded this frame (Bayer order), 0 at full \
         resolution",
    ),
    (
        "subpixel",
        "every frame: where in its pixel the ray passes, fract(0.5 + v × (0.7548777, \
         0.5698403)) for the v-th visit of a pixel ((0.5, 0.5) for one frame)",
    ),
    (
        "frame",
        "every frame: a frame counter (seeds the jitter hash)",
    ),
    (
        "jitter",
        "every frame: fract(frame × 0.618034), the ray-start offset",
    ),
    (
        "camera_altitude",
        "when the camera moves up or down (m above the ground)",
    ),
    (
        "light.sun_direction",
        "when the sun moves: unit vector towards the sun, y up",
    ),
    (
        "light.sun_irradiance",
        "when the sun or camera altitude moves: sun_light(u, sun_direction).sun_irradiance \
         (nimbus-sun.js in JavaScript packages, the sun_light pass in the others; the values \
         here are for the pair's scene)",
    ),
    (
        "light.sky_irradiance",
        "when the sun or camera altitude moves: sun_light(..).sky_irradiance",
    ),
    (
        "shadow.lookup.u",
        "when the sun or camera moves: sun_light(..).shadow_lookup.u (every cascade tile drawn \
         for this sun); a host that redraws the cascades in rotation keeps the tiles with \
         redrawn_tiles and writes anchored_tiles(..).u (nimbus-sun.js)",
    ),
    (
        "shadow.lookup.v",
        "with shadow.lookup.u: sun_light(..).shadow_lookup.v, or anchored_tiles(..).v",
    ),
    (
        "shadow.inverse_matrix",
        "when the sun or camera altitude moves: sun_light(..).shadow_inverse_matrix",
    ),
    (
        "media.weather_offset",
        "to drift the clouds: the weather texture's offset in tiles",
    ),
    (
        "media.coverage",
        "to change how much of the sky is cloudy (0..1); a scene's weather states ramp it \
         within a genus as weather_coverage(from, to, fraction of the interval gone by) \
         (smoothstep; nimbus-wind.js in JavaScript packages, NimbusClouds.setWeather and \
         setTime in three.js); redraw the shadow atlas",
    ),
    (
        "media.wind_drift",
        "to move the clouds with the wind: how far the air near the ground has travelled since \
         the start (m, x east and z south): wind_velocity(speed, direction_deg) × time, the \
         direction where the wind blows from, degrees clockwise from north (nimbus-wind.js in \
         JavaScript packages; NimbusClouds.setWind and setTime in three.js); redraw the shadow \
         atlas",
    ),
    (
        "media.wind_shear_drift",
        "with media.wind_drift: how much farther the air has travelled per metre of altitude \
         (shear): (velocity at TOP_ALTITUDE = 10 km − velocity at the ground) × time / 10,000",
    ),
    (
        "media.detail_fade",
        "when media.detail_repeat or the detail texture changes: (0.5, 2) × the detail texel \
         in metres, 1 / (detail_repeat × texels per side)",
    ),
    (
        "media.detail_moments",
        "when the detail texture changes: the means of its red channel r and of r⁶ (0..1)",
    ),
];

const SCENE_NOTES: &[(&str, &str)] = &[
    (
        "view_projection",
        "with the camera: the engine camera's projection × view without translation",
    ),
    (
        "forward",
        "with the camera: its forward direction (x east, y up, z south)",
    ),
    (
        "encoding",
        "0 for a projection's depth (perspective, reversed-Z), 1 for a logarithmic buffer \
         (three.js logarithmicDepthBuffer)",
    ),
    (
        "projection_zw",
        "with the camera: its projection's (P22, P32, P23, P33), column-major indices",
    ),
    (
        "depth_scale",
        "NDC z = depth × depth_scale + depth_offset: 2 and -1 in OpenGL and WebGL, 1 and 0 \
         elsewhere",
    ),
    ("log_range", "log2(far + 1) for a logarithmic buffer"),
    (
        "clear_depth",
        "what the buffer holds where the engine drew nothing (1; 0 reversed-Z)",
    ),
    ("resolution", "the depth texture's size in pixels"),
    (
        "flip_y",
        "1 where the depth texture's first row is the bottom one (OpenGL, WebGL)",
    ),
];

const RESOLVE_NOTES: &[(&str, &str)] = &[
    (
        "inverse_view_projection",
        "every frame: the inverse of this frame's projection × view without translation (as \
         the cloud block's)",
    ),
    (
        "previous_view_projection",
        "every frame: the previous frame's projection × view without translation",
    ),
    (
        "cloud_shift",
        "every frame: how far the wind moved the clouds since the previous frame (m, x, 0, z): \
         the change of media.wind_drift + media.wind_shear_drift × cloud_altitude; 0 for still \
         clouds (the history is then reprojected for the camera alone)",
    ),
    (
        "cloud_altitude",
        "when the layers or the camera's altitude change: where view rays meet the clouds, \
         facing_altitude(camera_altitude, march.min_height, march.max_height) (the bases from \
         below, the tops from above, the middle from inside; nimbus-wind.js in JavaScript \
         packages)",
    ),
    (
        "camera_altitude",
        "when the camera moves: as in the cloud block",
    ),
    ("planet_radius", "march.radius of the cloud block"),
    ("resolution", "every frame: the output size"),
    ("low_resolution", "every frame: the size of clouds_hdr"),
    ("pixel_offset", "every frame: as in the cloud block"),
    ("pixel_scale", "every frame: as in the cloud block"),
    (
        "current_weight",
        "every frame: 1 / (visits + 1), where visits counts earlier frames that shaded this \
         pixel (frames / 16 when upscaling)",
    ),
    (
        "variance_gamma",
        "2 when upscaling, 4 when accumulating at full resolution",
    ),
    (
        "history_valid",
        "0 on the first frame (or after a cut), 1 after",
    ),
];

const DISPLAY_NOTES: &[(&str, &str)] = &[
    ("resolution", "every frame: the output size"),
    (
        "exposure",
        "linear radiance is scaled by this before ACES (8 in `nimbus render`)",
    ),
    (
        "keep_alpha",
        "1 to keep cloud opacity in alpha, 0 for an opaque image",
    ),
    (
        "flip_y",
        "1 where the framebuffer's first row is the bottom one (WebGL, OpenGL), else 0",
    ),
];

fn type_name(ty: Type) -> String {
    nimbus_codegen::wgsl_type(ty)
}

fn block_file(ty: Type, bytes: &[u8], notes: &[(&str, &str)]) -> UniformBlockFile {
    // std140 hosts (WebGL's uniform blocks) round a block's size up to 16 bytes; every API
    // accepts a buffer that large.
    let mut bytes = bytes.to_vec();
    bytes.resize(bytes.len().div_ceil(16) * 16, 0);
    let members = member_layout(ty, &bytes)
        .into_iter()
        .map(|m| BlockMember {
            set: notes
                .iter()
                .find(|(path, _)| *path == m.path)
                .map(|(_, n)| n.to_string()),
            member: m.path,
            offset: m.offset,
            ty: type_name(m.ty),
            value: m.value,
        })
        .collect();
    UniformBlockFile {
        schema: format!("../{UNIFORMS_SCHEMA_FILE}"),
        size: bytes.len(),
        layout: "WGSL uniform address-space layout (std140-compatible): write the values \
                 little-endian at these byte offsets into one buffer of `size` bytes (a \
                 multiple of 16); matrices are column-major, one 16-byte column after another"
            .into(),
        bytes_hex: bytes.iter().map(|b| format!("{b:02x}")).collect(),
        members,
        pair: None,
        scene: None,
    }
}

fn uniform_file(a: &Assignment, u: &CloudUniforms) -> Result<UniformBlockFile, LayoutError> {
    Ok(UniformBlockFile {
        pair: Some(a.name()),
        scene: Some(format!(
            "values for the pair's scene: {} (a scene file's own values with --scene)",
            VIEW_DEFAULTS.describe()
        )),
        ..block_file(
            CloudUniforms::shader_type(),
            &u.to_uniform_bytes()?,
            CLOUD_NOTES,
        )
    })
}

fn readme(engine: Engine, table: &[Assignment]) -> String {
    let pairs: Vec<String> = table.iter().map(Assignment::name).collect();
    let conventions: String = engine
        .conventions()
        .into_iter()
        .map(|(k, v)| format!("- **{k}**: {v}\n"))
        .collect();
    let frame: String = frame_order(engine)
        .iter()
        .enumerate()
        .map(|(i, s)| format!("{}. {s}\n", i + 1))
        .collect();
    format!(
        "# Nimbus package for {engine} ({language})\n\n\
         Generated by `nimbus emit --engine {engine}`; nothing here needs Nimbus at run time. \
         Pairs: {pairs}.\n\n\
         - `{PACKAGE_FILE}`: the pass graph (per pair: each pass's shader files, what each \
         binding slot holds and how the files name it), the resources the passes bind (by id: \
         how a host provides each), the render targets and formats, the textures, and these \
         conventions. `{PACKAGE_SCHEMA_FILE}` is its JSON Schema (draft 2020-12) and \
         `{UNIFORMS_SCHEMA_FILE}` that of the uniform files: both derived from the Rust types \
         the files are written from.\n\
         - `uniforms/<pair>.json`, `uniforms/resolve.json`, `uniforms/display.json`: each \
         uniform block's size, members (offset, type, value) and which members to set when; \
         `bytes_hex` is the whole block.\n\
         - `textures/`: the noise textures (2D PNG, RGBA8; 3D raw R8, the one channel the \
         shaders read; see `textures` in `{PACKAGE_FILE}`), uploaded as half floats (`format`: \
         `rgba16float`, or `r16float` for the one-channel files), each byte widened \
         through `texel_halves` as Nimbus's runtime does: a GPU that filters 8-bit textures \
         in 8-bit arithmetic leaves a faint halo of opacity round every cloud.\n\
         - the shader files, named `<module>-<key>.<entry>.<ext>` (`<module>-<key>.wgsl` and \
         `<module>-<key>.hlsl` hold every entry point), with a `.json` binding manifest beside \
         each GLSL, HLSL and MSL file.\n\n\
         ## A frame\n\n{frame}\n\
         {host}\
         ## Conventions\n\n{conventions}\n\
         Bindings: {bindings}.\n",
        engine = engine.name(),
        language = engine.language(),
        pairs = pairs.join(", "),
        bindings = engine.binding_note(),
        host = host_section(engine),
    )
}

/// The README's section on the package's host code, for engines that have one.
fn host_section(engine: Engine) -> &'static str {
    match engine {
        Engine::Three => {
            "## three.js\n\n\
             `nimbus-clouds.js` draws the package with three.js alone (`nimbus-clouds-pass.js` is \
             the same as an EffectComposer pass; `example.html` a page where the sun moves):\n\n\
             ```js\n\
             import { NimbusClouds } from './nimbus-clouds.js';\n\
             const clouds = await NimbusClouds.load(new URL('./', import.meta.url));\n\
             clouds.setSize(width, height);\n\
             clouds.setCamera(camera);              // a THREE.PerspectiveCamera, y up, metres\n\
             clouds.setSun(30, 150);                // elevation, azimuth (degrees)\n\
             clouds.setWind(6, 260, 20, 280);       // m/s and from (degrees): ground, 10 km\n\
             clouds.setWeather(0.35, { at: 7200 }); // coverage reached by second 7200\n\
             clouds.setTime(900);                   // seconds since the timeline's start\n\
             clouds.render(renderer);\n\
             ```\n\n\
             - `setSun(elevation, azimuth)`: the sun `elevation` degrees above the horizon, \
             `azimuth` clockwise from north (-z), as Nimbus's scenes give it; the sun's and sky's \
             irradiance and the shadow cascades follow (`sun_light` from `nimbus-sun.js`).\n\
             - `setWind(speed, directionDeg, topSpeed = speed, topDirectionDeg = directionDeg)`: \
             a scene's `[wind]`: m/s near the ground and where the wind blows from, degrees \
             clockwise from north (270: a westerly); `topSpeed` and `topDirectionDeg` at 10 km, \
             linear in altitude between.\n\
             - `setWeather(coverage, { at, over })`: a scene's `[[weather]]` within the pair's \
             genus: by `at` seconds the coverage is `coverage` (0..1), a smoothstep ramp from the \
             state before (its time, or second 0 and the package's coverage), or over the last \
             `over` seconds; without `at`, `over` seconds from the current time (at once without \
             it). `clearWeather()` forgets the states.\n\
             - `setTime(seconds)`: the clock, as `nimbus render --time`: sets `media.wind_drift` \
             and `media.wind_shear_drift` from the wind and `media.coverage` from the states.\n\n\
             Changing the sun, the drift or the coverage redraws the shadow atlas on the next \
             frame; only uniforms change (no other shader, no pipeline switch), so a change of \
             genus needs another pair. The formulas are Nimbus's own `#[shader_fn]`s, printed as \
             JavaScript: `nimbus-sun.js` (`sun_direction`, `sun_light`) and `nimbus-wind.js` \
             (`wind_velocity`, `wind_velocity_at`, `TOP_ALTITUDE`, `weather_coverage`); \
             `nimbus-timeline.js` (`NimbusTimeline`, no three.js) turns a wind and weather states \
             into the uniforms at a time for any JavaScript host.\n\n"
        }
        Engine::Webgpu => {
            "## JavaScript host code\n\n\
             `nimbus-sun.js` (`sun_direction`, `sun_light`) recomputes what the sun's position \
             decides, and `nimbus-wind.js` (`wind_velocity`, `wind_velocity_at`, `TOP_ALTITUDE`, \
             `weather_coverage`) gives the wind's velocity and the weather's ramp: the JavaScript \
             twins of Nimbus's own `#[shader_fn]`s (see the uniform notes of `media.wind_drift` \
             and `media.coverage`).\n\n"
        }
        Engine::Unity => {
            "## Unity\n\n\
             Each pass is `<module>-<key>.hlsl` (both stages, one program) with a ShaderLab \
             `<module>-<key>.shader` that includes it (`Shader \"Nimbus/<module>-<key>\"`); the \
             `sun_light` kernel is `sun-light.compute`. `NimbusClouds.cs` is a camera component \
             of the built-in render pipeline that runs the pair's passes with one command \
             buffer:\n\n\
             1. Copy this folder to `Assets/StreamingAssets/Nimbus` (Unity also compiles the \
             .shader, .compute and .cs files there) and install the `com.unity.mathematics` \
             package.\n\
             2. Add `NimbusClouds` to the camera and drag `sun-light.compute` onto its \
             `Sun Light` field; set the sun, the wind and `pair` in the inspector.\n\n\
             `NimbusFrame.cs` (`cloud_frame`, `resolve_frame`, `drift_at`), `NimbusWind.cs` \
             (`wind_velocity`, `wind_velocity_at`, `wind_drift`, `weather_progress`, \
             `weather_coverage`, `facing_altitude`, `TOP_ALTITUDE`) and `NimbusSun.cs` \
             (`sun_direction`) are Nimbus's own `#[shader_fn]`s printed as C# \
             (Unity.Mathematics); the sun's light and the shadow cascades come from the \
             `sun_light` kernel. Checked without Unity: both HLSL front ends (glslang, Slang) \
             take every file, the HLSL compiled to SPIR-V draws `nimbus render`'s frame, and \
             the C# twins compiled by mono compute what the Rust functions do. Not checked \
             here: Unity's own compilers (FXC, DXC) and `NimbusClouds.cs`, which needs \
             UnityEngine. In Linear colour space the display pass's sRGB-encoded output needs \
             a target without sRGB conversion.\n\n"
        }
        Engine::Metal => {
            "## Metal\n\n\
             `NimbusMetal.swift` is an `MTKViewDelegate` that draws the package's still frame \
             (sun_light, shadow, air, clouds, display) from these files alone: the MSL compiled \
             at run time (`makeLibrary(source:)`), each binding at the buffer, texture or \
             sampler index its file's `.json` lists, the sampler states from the same lists, the \
             kernel's runtime-sized buffer's length at the `buffer_sizes` index. \
             `let clouds = try NimbusMetal(view: view, package: url); view.delegate = clouds`. \
             Unverified: no Apple compiler runs where Nimbus is tested (Linux), so neither the \
             MSL nor this file has been compiled; the Vulkan host, which takes the same steps, \
             is checked against `nimbus render` there.\n\n"
        }
        Engine::Wgpu | Engine::Vulkan => "",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nimbus_clouds::Quality;

    /// Every preset's atlas fits every engine (`ultra` and `reference` in WebGL2's 2,048 since
    /// the tiles lie in a grid), and an atlas that cannot is refused with its size and why.
    #[test]
    fn atlases_fit_every_engine_or_are_refused() {
        let engines = [
            Engine::Three,
            Engine::Webgpu,
            Engine::Wgpu,
            Engine::Vulkan,
            Engine::Unity,
            Engine::Metal,
        ];
        for q in Quality::WITH_REFERENCE {
            let shadow = ShadowParams::for_quality(&q.settings());
            for engine in engines {
                assert!(
                    check_atlas(q.name(), &shadow, engine).is_ok(),
                    "{} on {}: {:?}",
                    q.name(),
                    engine.name(),
                    shadow.atlas_size()
                );
            }
        }
        let ultra = ShadowParams::for_quality(&Quality::Ultra.settings());
        assert_eq!(
            ultra.atlas_size(),
            (2048, 2048),
            "three tiles of 1,024 in a 2×2 grid"
        );
        let huge = ShadowParams {
            map_size: 2048.0,
            ..ultra
        };
        let err = check_atlas("cumulus.huge", &huge, Engine::Three)
            .expect_err("4,096 texels is past WebGL2's 2,048")
            .to_string();
        assert!(
            err.contains("cumulus.huge: the shadow atlas (3 cascades of 2048 px, 4096×4096)")
                && err.contains("2048"),
            "{err}"
        );
        assert!(check_atlas("cumulus.huge", &huge, Engine::Webgpu).is_ok());
    }
}
