//! The Vulkan package runs outside wgpu: `examples/vulkan-host`, written against the Vulkan API
//! alone (ash), loads what `nimbus emit --engine vulkan --scene` wrote and draws the scene's
//! frame on this machine's Vulkan device (lavapipe here); the picture must be `nimbus render`'s
//! for the same scene. The control: the same comparison tells two sun positions apart, so a host
//! that ignored the package's uniforms, or drew the wrong pass, would fail.
//!
//! The same host also draws the Unity package's HLSL: glslang compiles each pass's one HLSL
//! file to SPIR-V for each entry point (HLSL packing offsets, registers as bindings) in place of
//! the Vulkan package's, so the frame checks what the HLSL means — its arithmetic, matrices,
//! register numbers and cbuffer packing — not only that it compiles.

mod common;

use std::path::{Path, PathBuf};

use common::{have_gpu, mean_difference, nimbus, text};

/// At most this mean difference per channel (of 255) between the host's frame and Nimbus's.
const MAX_MEAN: f64 = 1.0;

struct View {
    name: &'static str,
    quality: &'static str,
    sun_elevation: f32,
    pitch: f32,
}

const VIEWS: [View; 3] = [
    View {
        name: "high",
        quality: "high",
        sun_elevation: 35.0,
        pitch: 10.0,
    },
    // The control: the first view with the sun low.
    View {
        name: "high-low-sun",
        quality: "high",
        sun_elevation: 8.0,
        pitch: 10.0,
    },
    View {
        name: "low",
        quality: "low",
        sun_elevation: 20.0,
        pitch: 4.0,
    },
];

fn scene(dir: &Path, v: &View) -> PathBuf {
    let file = dir.join(format!("vulkan-{}.toml", v.name));
    let toml = format!(
        "name = \"vulkan-{name}\"\n\
         description = \"The Vulkan host test's view {name}.\"\n\
         genus = \"cumulus\"\n\
         quality = \"{quality}\"\n\
         coverage = 0.6\n\
         sun_elevation_deg = {el}\n\
         sun_azimuth_deg = 150.0\n\
         camera_altitude = 2.0\n\
         camera_pitch_deg = {pitch}\n\
         camera_yaw_deg = 0.0\n",
        name = v.name,
        quality = v.quality,
        el = v.sun_elevation,
        pitch = v.pitch,
    );
    std::fs::write(&file, toml).expect("write scene");
    file
}

/// Emits `engine`'s package for `scene_file` into `dir/package-<name>-<engine>`.
fn emit(dir: &Path, scene_file: &Path, name: &str, engine: &str) -> PathBuf {
    let package = dir.join(format!("package-{name}-{engine}"));
    common::emit_scene(engine, scene_file, &package);
    package
}

/// Replaces every SPIR-V file of the Vulkan package `vulkan` by glslang's compile of the entry
/// point from the pass's HLSL file in the Unity package `unity`; returns how many.
fn spirv_from_hlsl(vulkan: &Path, unity: &Path) -> usize {
    let description: serde_json::Value = serde_json::from_slice(
        &std::fs::read(vulkan.join("nimbus-package.json")).expect("package description"),
    )
    .expect("JSON");
    let mut done = std::collections::BTreeSet::new();
    for pass in description["pairs"]
        .as_array()
        .expect("pairs")
        .iter()
        .flat_map(|p| p["passes"].as_array().expect("passes"))
    {
        let hlsl = unity.join(format!("{}.hlsl", pass["shader"].as_str().expect("shader")));
        assert!(hlsl.exists(), "the Unity package has no {}", hlsl.display());
        for file in pass["files"].as_array().expect("files") {
            let spv = file["file"].as_str().expect("file");
            if !done.insert(spv.to_string()) {
                continue;
            }
            let entry = file["entry_point"].as_str().expect("entry point");
            let stage = match file["stage"].as_str().expect("stage") {
                "vertex" => "vert",
                "fragment" => "frag",
                _ => "comp",
            };
            let out = std::process::Command::new("glslangValidator")
                .args(["-D", "-V", "--hlsl-offsets", "-S", stage, "-e", entry])
                .args(["--source-entrypoint", entry, "-o"])
                .arg(vulkan.join(spv))
                .arg(&hlsl)
                .output()
                .expect("run glslangValidator");
            assert!(
                out.status.success(),
                "glslang on {} ({entry}): {}",
                hlsl.display(),
                text(&out.stdout)
            );
        }
    }
    done.len()
}

/// Draws each view with the Vulkan host (its shaders from the HLSL when `hlsl`) and compares
/// it with `nimbus render`, then the control.
fn host_matches_render(hlsl: bool) {
    if !have_gpu() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let (w, h) = (160u32, 90u32);
    let source = if hlsl { "HLSL" } else { "SPIR-V" };
    let mut frames = Vec::new();
    for v in &VIEWS {
        let scene_file = scene(dir.path(), v);
        let package = emit(dir.path(), &scene_file, v.name, "vulkan");
        if hlsl {
            let unity = emit(dir.path(), &scene_file, v.name, "unity");
            let n = spirv_from_hlsl(&package, &unity);
            println!("{}: {n} SPIR-V files compiled from the Unity HLSL", v.name);
        }
        let reference = dir.path().join(format!("{}-nimbus.png", v.name));
        let size = format!("{w}x{h}");
        let o = nimbus(&[
            "render",
            scene_file.to_str().expect("utf8"),
            "-r",
            &size,
            "-f",
            "1",
            "-o",
            reference.to_str().expect("utf8"),
        ]);
        assert!(o.status.success(), "render: {}", text(&o.stderr));
        let picture = nimbus_vulkan_host::render(&package, None, w, h)
            .unwrap_or_else(|e| panic!("{}: the Vulkan host: {e}", v.name));
        println!("{}: drawn by the Vulkan host on {}", v.name, picture.device);
        let drawn = image::DynamicImage::ImageRgba8(
            image::RgbaImage::from_raw(w, h, picture.rgba).expect("a whole picture"),
        )
        .to_rgb8();
        frames.push((v.name, common::rgb(&reference), drawn));
    }
    for (name, want, got) in &frames {
        let mean = mean_difference(want, got);
        println!("{name}: Vulkan host ({source}) vs nimbus render: mean difference {mean:.3}/255");
        assert!(
            mean <= MAX_MEAN,
            "{name}: the Vulkan host's frame ({source}) differs from nimbus render by {mean:.3}/255"
        );
    }
    let control = mean_difference(&frames[0].1, &frames[1].2);
    println!("control (sun 35° vs 8°): mean difference {control:.3}/255");
    assert!(control > 4.0 * MAX_MEAN, "the comparison cannot fail");
}

#[test]
fn the_vulkan_host_draws_what_nimbus_renders() {
    host_matches_render(false);
}

#[test]
fn the_unity_hlsl_draws_what_nimbus_renders() {
    host_matches_render(true);
}
