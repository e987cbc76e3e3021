//! `nimbus emit --engine`: a package per engine, complete and consistent, with textures equal to
//! what the runtime samples; bad requests refused with nothing written.

mod common;

use std::path::Path;

use common::{have_gpu, nimbus, text};
use serde_json::Value;

const ENGINES: [&str; 6] = ["three", "webgpu", "wgpu", "vulkan", "unity", "metal"];

fn read_json(path: &Path) -> Value {
    let s = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&s).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn package(engine: &str, out: &Path) -> (Value, String) {
    let o = nimbus(&[
        "emit",
        "--engine",
        engine,
        "-g",
        "cumulus",
        "-q",
        "low",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{engine}: {}", text(&o.stderr));
    (read_json(&out.join("nimbus-package.json")), text(&o.stdout))
}

#[test]
fn every_engine_gets_a_complete_package() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for engine in ENGINES {
        let out = tmp.path().join(engine);
        let (p, stdout) = package(engine, &out);
        println!("{engine}: {}", stdout.trim());
        assert_eq!(p["engine"], engine);
        assert!(out.join("README.md").is_file() && out.join("nimbus-manifest.txt").is_file());
        let pairs = p["pairs"].as_array().expect("pairs");
        assert_eq!(pairs.len(), 1);
        let pair = &pairs[0];
        assert_eq!(pair["pair"], "cumulus.low");
        let passes: Vec<&str> = pair["passes"]
            .as_array()
            .expect("passes")
            .iter()
            .filter_map(|x| x["pass"].as_str())
            .collect();
        // cumulus at low samples a shadow map, so it draws all four passes; hosts without
        // JavaScript first complete the block on the GPU (the sun_light kernel).
        let javascript = matches!(engine, "three" | "webgpu");
        let expected: &[&str] = if javascript {
            &["shadow", "clouds", "resolve", "display"]
        } else {
            &["sun_light", "shadow", "clouds", "resolve", "display"]
        };
        assert_eq!(passes, expected, "{engine}");
        assert_eq!(
            out.join("nimbus-sun.js").is_file(),
            javascript,
            "{engine}: the sun's JavaScript twin ships with JavaScript hosts only"
        );
        if !javascript {
            let sun = &pair["passes"][0];
            assert_eq!(sun["dispatch"], serde_json::json!([1, 1, 1]), "{engine}");
            let holds: Vec<&str> = sun["bindings"]
                .as_array()
                .expect("bindings")
                .iter()
                .filter_map(|b| b["holds"]["id"].as_str())
                .collect();
            assert_eq!(holds, ["pair_inputs", "pair"], "{engine}");
            // Metal's runtime-sized output needs naga's buffer of sizes, named in the graph.
            let sizes = &sun["files"][0]["buffer_sizes"];
            assert_eq!(
                sizes["target_name"].as_str().is_some(),
                engine == "metal",
                "{engine}: {sizes}"
            );
        }
        for pass in pair["passes"].as_array().expect("passes") {
            for f in pass["files"].as_array().expect("files") {
                let file = f["file"].as_str().expect("file name");
                assert!(
                    out.join(file).is_file(),
                    "{engine}: {file} listed but missing"
                );
                if let Some(m) = f["manifest"].as_str() {
                    assert!(out.join(m).is_file(), "{engine}: {m} missing");
                }
            }
            // WebGPU and Vulkan get each pass's layout in the API's own terms, one entry per
            // binding.
            let layout = match engine {
                "webgpu" | "wgpu" => Some(&pass["bind_group_layout"]["entries"]),
                "vulkan" => Some(&pass["descriptor_set_layout"]["bindings"]),
                _ => None,
            };
            if let Some(entries) = layout {
                assert_eq!(
                    entries.as_array().map(Vec::len),
                    pass["bindings"].as_array().map(Vec::len),
                    "{engine}: {}",
                    pass["pass"]
                );
            }
            for b in pass["bindings"].as_array().expect("bindings") {
                assert_ne!(b["holds"]["kind"], "unknown", "{engine}: {b}");
                // three.js binds each block as vec4 words (a UniformsGroup of one Vector4
                // array); the other engines bind the struct.
                if b["kind"] == "uniform" {
                    let ty = b["wgsl_type"].as_str().expect("type");
                    assert_eq!(
                        ty.starts_with("array<vec4<u32>, "),
                        engine == "three",
                        "{ty}"
                    );
                }
            }
        }
        // Every uniform block a pass binds has its file, and its layout covers its size.
        let uniforms = pair["uniforms"].as_str().expect("uniform file");
        for file in [uniforms, "uniforms/resolve.json", "uniforms/display.json"] {
            let u = read_json(&out.join(file));
            let size = u["size"].as_u64().expect("size");
            assert_eq!(
                u["bytes_hex"].as_str().map(str::len),
                Some(2 * size as usize)
            );
            let last = u["members"]
                .as_array()
                .and_then(|m| m.last())
                .expect("members");
            assert!(last["offset"].as_u64().expect("offset") < size, "{file}");
        }
        let display = read_json(&out.join("uniforms/display.json"));
        let flip = display["members"]
            .as_array()
            .and_then(|m| m.iter().find(|x| x["member"] == "flip_y"))
            .map(|x| x["value"][0].as_f64());
        let bottom_up = engine == "three";
        assert_eq!(
            flip,
            Some(Some(if bottom_up { 1.0 } else { 0.0 })),
            "{engine}"
        );
        // Textures: the files the descriptors name, of the sizes they state.
        for t in p["textures"].as_array().expect("textures") {
            let file = out.join(t["file"].as_str().expect("file"));
            let size: Vec<u64> = t["size"]
                .as_array()
                .expect("size")
                .iter()
                .filter_map(Value::as_u64)
                .collect();
            if size.len() == 3 {
                let len = std::fs::metadata(&file).expect("3D texture file").len();
                assert_eq!(len, size.iter().product::<u64>() * 4, "{}", file.display());
            } else {
                let img = image::open(&file).expect("PNG").to_rgba8();
                assert_eq!(
                    (img.width() as u64, img.height() as u64),
                    (size[0], size[1])
                );
            }
        }
        match engine {
            "three" => assert!(stdout.contains("glslangValidator"), "{stdout}"),
            "vulkan" => assert!(stdout.contains("spirv-val"), "{stdout}"),
            _ => assert!(stdout.contains("validated by naga"), "{stdout}"),
        }
    }
}

#[test]
fn package_textures_are_the_runtimes_texels() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("pkg");
    let (p, _) = package("webgpu", &out);
    assert!(
        p["textures_generated_by"]
            .as_str()
            .is_some_and(|s| s.contains("compute kernels")),
        "{}",
        p["textures_generated_by"]
    );
    let gpu = nimbus_runtime::Gpu::new().expect("adapter");
    use nimbus_runtime::textures::NoiseKind;
    for (kind, file, size) in [
        (NoiseKind::Detail, "textures/detail.rgba8", 32u32),
        (NoiseKind::Weather, "textures/weather.png", 512),
    ] {
        let want: Vec<u8> = gpu
            .noise_texels(kind, size)
            .expect("texels")
            .iter()
            .flat_map(|t| t.to_le_bytes())
            .collect();
        let got = if file.ends_with(".png") {
            image::open(out.join(file))
                .expect("png")
                .to_rgba8()
                .into_raw()
        } else {
            std::fs::read(out.join(file)).expect("raw")
        };
        assert_eq!(got.len(), want.len(), "{file}");
        let differing = got.iter().zip(&want).filter(|(a, b)| a != b).count();
        println!("{file}: {} bytes, {differing} differ", got.len());
        assert_eq!(differing, 0, "{file} differs from the runtime's texels");
    }
}

#[test]
fn requests_an_engine_cannot_run_are_refused_and_nothing_is_written() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let cases: [(&[&str], &str); 4] = [
        (&["--engine", "dx9", "-g", "cumulus"], "invalid value 'dx9'"),
        (
            &["--engine", "three", "-g", "cumulus", "-q", "reference"],
            "cumulus.reference: the shadow atlas (4 cascades of 1024 px side by side) is 4096 px, \
             beyond the 2048 px",
        ),
        (&["--engine", "three", "preview-hg"], "genus × preset pairs"),
        (
            &["--engine", "three", "-t", "wgsl", "-g", "cumulus"],
            "cannot be used with",
        ),
    ];
    for (i, (args, want)) in cases.iter().enumerate() {
        let out = tmp.path().join(format!("case{i}"));
        let mut all = vec!["emit"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", out.to_str().expect("utf8")]);
        let o = nimbus(&all);
        let err = text(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    // A folder Nimbus did not write is left as it was.
    let mine = tmp.path().join("mine");
    std::fs::create_dir(&mine).expect("mkdir");
    std::fs::write(mine.join("notes.txt"), "keep").expect("write");
    let o = nimbus(&[
        "emit",
        "--engine",
        "webgpu",
        "-g",
        "cumulus",
        "-q",
        "low",
        "-o",
        mine.to_str().expect("utf8"),
    ]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("not written by Nimbus"));
    let left: Vec<_> = std::fs::read_dir(&mine).expect("read").collect();
    assert_eq!(left.len(), 1);
    assert_eq!(
        std::fs::read_to_string(mine.join("notes.txt"))
            .ok()
            .as_deref(),
        Some("keep")
    );
}
