//! `nimbus emit --engine`: a package per engine, complete and consistent, with textures equal to
//! what the runtime samples; bad requests refused with nothing written.

mod common;

use std::path::Path;
use std::process::Command;

use common::{have_gpu, nimbus, text};
use nimbus_clouds::{CloudLibrary, parse_scene};
use serde_json::{Value, json};

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
        // cumulus at low samples a shadow map and reads the air table, so it draws all five
        // passes; hosts without JavaScript first complete the block on the GPU (the sun_light
        // kernel).
        let javascript = matches!(engine, "three" | "webgpu");
        let expected: &[&str] = if javascript {
            &["shadow", "air", "clouds", "resolve", "display"]
        } else {
            &["sun_light", "shadow", "air", "clouds", "resolve", "display"]
        };
        assert_eq!(passes, expected, "{engine}");
        assert_eq!(
            pair["air_table"],
            serde_json::json!({ "width": 256, "height": 384 }),
            "{engine}"
        );
        assert_eq!(
            out.join("nimbus-sun.js").is_file(),
            javascript,
            "{engine}: the sun's JavaScript twin ships with JavaScript hosts only"
        );
        assert_eq!(
            out.join("nimbus-wind.js").is_file(),
            javascript,
            "{engine}: the wind's JavaScript twin ships with JavaScript hosts only"
        );
        for host in ["nimbus-timeline.js", "nimbus-host.js", "nimbus-frame.js"] {
            assert_eq!(
                out.join(host).is_file(),
                javascript,
                "{engine}: {host} ships with JavaScript hosts only"
            );
        }
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
                // Stage flags as the APIs take them: numbers (GPUShaderStage, VkShaderStageFlags).
                for e in entries.as_array().expect("entries") {
                    let flags = if engine == "vulkan" {
                        &e["stageFlags"]
                    } else {
                        &e["visibility"]
                    };
                    assert!(flags.as_u64().is_some_and(|f| f > 0), "{engine}: {e}");
                }
            }
            // The pipeline's entry points, by stage.
            let entry = &pass["entry_points"];
            if pass["pass"] == "sun_light" {
                assert!(entry["compute"].is_string(), "{engine}: {entry}");
            } else {
                assert!(
                    entry["vertex"].is_string() && entry["fragment"].is_string(),
                    "{engine}: {entry}"
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
                // One byte a texel: the red channel, the one the shaders read, uploaded as
                // `r16float`.
                assert_eq!(t["format"], "r16float", "{t}");
                assert_eq!(t["file_format"], "r8unorm", "{t}");
                let len = std::fs::metadata(&file).expect("3D texture file").len();
                assert_eq!(len, size.iter().product::<u64>(), "{}", file.display());
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
            "unity" => assert!(
                stdout.contains("glslangValidator (HLSL) and Slang"),
                "{stdout}"
            ),
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
        (NoiseKind::Detail, "textures/detail.r8", 32u32),
        (NoiseKind::Weather, "textures/weather.png", 512),
    ] {
        // The runtime's texels, as many channels of each as the file holds.
        let channels = kind.channels() as usize;
        let want: Vec<u8> = gpu
            .noise_texels(kind, size)
            .expect("texels")
            .iter()
            .flat_map(|t| t.to_le_bytes().into_iter().take(channels))
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
    let cases: [(&[&str], &str); 3] = [
        (&["--engine", "dx9", "-g", "cumulus"], "invalid value 'dx9'"),
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

/// Scenes of the timeline test: a wind (`[wind]`) and weather states within the genus
/// (`[[weather]]`), as TOML, and the same as `NimbusTimeline` calls take them.
struct Timeline {
    wind: &'static str,
    weather: &'static str,
    /// `[speed, directionDeg, topSpeed?, topDirectionDeg?]`, then `[coverage, at, over?]` each.
    js_wind: &'static [f64],
    js_weather: &'static [&'static [f64]],
}

const TIMELINES: [Timeline; 4] = [
    // A westerly that strengthens and veers with height; the cumulus grow, then a cut.
    Timeline {
        wind: "speed = 6.0\ndirection_deg = 260.0\ntop_speed = 20.0\ntop_direction_deg = 280.0\n",
        weather: "[[weather]]\nat = 7200.0\ncoverage = 0.35\n\
                  [[weather]]\nat = 20000.0\ncoverage = 0.6\n\
                  [[weather]]\nat = 20000.0\ncoverage = 0.1\n",
        js_wind: &[6.0, 260.0, 20.0, 280.0],
        js_weather: &[&[0.35, 7200.0], &[0.6, 20000.0], &[0.1, 20000.0]],
    },
    // No shear (the top wind defaults to the ground's); a north-easterly.
    Timeline {
        wind: "speed = 11.5\ndirection_deg = 45.0\n",
        weather: "[[weather]]\nat = 600.0\ncoverage = 0.9\n",
        js_wind: &[11.5, 45.0],
        js_weather: &[&[0.9, 600.0]],
    },
    // Shear from still air at the ground to a southerly jet, and a thinning held at first:
    // `over` starts the ramp late, as a state that keeps the coverage at `at - over` does.
    Timeline {
        wind: "speed = 0.0\ndirection_deg = 0.0\ntop_speed = 45.0\ntop_direction_deg = 180.0\n",
        weather: "[[weather]]\nat = 3000.0\n\
                  [[weather]]\nat = 90000.0\ncoverage = 0.05\n",
        js_wind: &[0.0, 0.0, 45.0, 180.0],
        js_weather: &[&[0.05, 90000.0, 87000.0]],
    },
    // An easterly veering through north with height.
    Timeline {
        wind: "speed = 3.0\ndirection_deg = 90.0\ntop_speed = 8.0\ntop_direction_deg = 350.0\n",
        weather: "",
        js_wind: &[3.0, 90.0, 8.0, 350.0],
        js_weather: &[],
    },
];

const TIMES: [f64; 9] = [
    0.0, 1.0, 299.5, 600.0, 3600.0, 9000.0, 19999.0, 20000.0, 99_999.0,
];

/// The three.js package's timeline (`nimbus-timeline.js` with the generated `nimbus-wind.js`,
/// run by node, no browser) gives the cloud block the drift and coverage Nimbus's own timeline
/// (`ScenePreset::at`, what `nimbus render --time` draws) gives, for four winds and weathers at
/// nine times up to a day.
#[test]
fn the_three_package_timeline_drifts_and_changes_as_nimbus_does() {
    if !nimbus_testkit::skip::browser_tools_present(
        "the package timeline test",
        nimbus_testkit::skip::node_missing(),
    ) {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let pkg = tmp.path().join("pkg");
    let (p, _) = package("three", &pkg);
    let uniforms: Value = read_json(&pkg.join(p["pairs"][0]["uniforms"].as_str().expect("file")));
    let coverage = uniforms["members"]
        .as_array()
        .and_then(|m| m.iter().find(|m| m["member"] == "media.coverage"))
        .and_then(|m| m["value"][0].as_f64())
        .expect("media.coverage");
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples"))
        .expect("data");
    let genus_coverage = |g: &str| lib.genus(g).map_or(0.0, |g| g.coverage);
    // Nimbus's timeline, for a scene at the package's coverage.
    let mut want = Vec::new();
    for t in &TIMELINES {
        let text = format!(
            "name = \"t\"\ndescription = \"\"\ngenus = \"cumulus\"\ncoverage = {coverage}\n\
             quality = \"low\"\n[wind]\n{}{}",
            t.wind, t.weather
        );
        let scene = parse_scene(Path::new("t.toml"), &text).expect("scene");
        let at: Vec<Value> = TIMES
            .iter()
            .map(|&s| {
                let a = scene.at(s, &genus_coverage);
                assert_eq!(a.layers.len(), 1, "one genus");
                json!({
                    "wind_drift": a.drift.ground.to_array(),
                    "wind_shear_drift": a.drift.per_metre.to_array(),
                    "coverage": a.layers[0].coverage,
                })
            })
            .collect();
        want.push(at);
    }
    let cases: Vec<Value> = TIMELINES
        .iter()
        .map(|t| json!({ "wind": t.js_wind, "weather": t.js_weather }))
        .collect();
    let runner = tmp.path().join("run.mjs");
    std::fs::write(
        &runner,
        format!(
            "import {{ NimbusTimeline }} from {module};\n\
             const cases = {cases};\n\
             const times = {times};\n\
             console.log(JSON.stringify(cases.map((c) => {{\n\
               const t = new NimbusTimeline({coverage});\n\
               t.setWind(...c.wind);\n\
               for (const [coverage, at, over] of c.weather) t.setWeather(coverage, {{ at, over }});\n\
               return times.map((s) => t.at(s));\n\
             }})));\n",
            module = json!(format!("file://{}", pkg.join("nimbus-timeline.js").display())),
            cases = Value::Array(cases),
            times = json!(TIMES),
        ),
    )
    .expect("write runner");
    let o = Command::new("node").arg(&runner).output().expect("node");
    assert!(o.status.success(), "node: {}", text(&o.stderr));
    let got: Vec<Vec<Value>> = serde_json::from_slice(&o.stdout).expect("node's JSON");
    let floats = |v: &Value| -> Vec<f64> {
        v.as_array()
            .map(|a| a.iter().filter_map(Value::as_f64).collect())
            .unwrap_or_default()
    };
    // Relative to the drift's size (at least 1 m, or 1e-4 per metre): the JavaScript twin
    // computes the velocity in double precision, the CPU twin in single.
    let (mut drift_err, mut shear_err, mut coverage_err) = (0.0f64, 0.0f64, 0.0f64);
    let mut largest = 0.0f64;
    for (i, (w, g)) in want.iter().zip(&got).enumerate() {
        for (j, (w, g)) in w.iter().zip(g).enumerate() {
            let at = format!("timeline {i} at {} s", TIMES[j]);
            for (key, floor, err) in [
                ("wind_drift", 1.0, &mut drift_err),
                ("wind_shear_drift", 1e-4, &mut shear_err),
            ] {
                let (w, g) = (floats(&w[key]), floats(&g[key]));
                assert_eq!(g.len(), 2, "{at}: {key} {g:?}");
                let size = w[0].hypot(w[1]);
                if key == "wind_drift" {
                    largest = largest.max(size);
                }
                let e = (w[0] - g[0]).hypot(w[1] - g[1]) / size.max(floor);
                *err = err.max(e);
                assert!(e < 1e-5, "{at}: {key} {g:?}, Nimbus {w:?}");
            }
            let (wc, gc) = (
                w["coverage"].as_f64().expect("coverage"),
                g["coverage"].as_f64().expect("coverage"),
            );
            coverage_err = coverage_err.max((wc - gc).abs());
            assert!((wc - gc).abs() < 1e-6, "{at}: coverage {gc}, Nimbus {wc}");
        }
    }
    println!(
        "{} timelines × {} times: drift {drift_err:.1e} (relative; up to {largest:.0} m), shear \
         drift {shear_err:.1e}, coverage {coverage_err:.1e} from Nimbus's timeline",
        TIMELINES.len(),
        TIMES.len()
    );
}

/// The packages hold their textures as 8-bit files (the 3D noises one channel, the 2D maps four)
/// but tell the host to upload half floats,
/// and the shipped host module (`widenTexels` in nimbus-host.js, run by node) widens every byte
/// of a texture file to exactly the value Nimbus's runtime samples (`texel_value`): the
/// engines filter in float as the runtime does, with no 8-bit halo round the clouds.
#[test]
fn the_package_host_widens_texels_to_what_the_runtime_samples() {
    if !nimbus_testkit::skip::browser_tools_present(
        "the texel widening test",
        nimbus_testkit::skip::node_missing(),
    ) {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let pkg = tmp.path().join("pkg");
    let (p, _) = package("three", &pkg);
    for t in p["textures"].as_array().expect("textures") {
        let (format, file_format) = if t["dimension"] == "3d" {
            ("r16float", "r8unorm")
        } else {
            ("rgba16float", "rgba8unorm")
        };
        assert_eq!(t["format"], format, "{t}");
        assert_eq!(t["file_format"], file_format, "{t}");
    }
    let detail = std::fs::read(pkg.join("textures/detail.r8")).expect("detail texture");
    let sample: Vec<u8> = detail.iter().take(4096).copied().collect();
    let every_byte: Vec<u8> = (0..=u8::MAX).collect();
    let runner = tmp.path().join("widen.mjs");
    std::fs::write(
        &runner,
        format!(
            "import {{ readFileSync }} from 'node:fs';\n\
             import {{ widenTexels }} from {module};\n\
             const pkg = JSON.parse(readFileSync({json}, 'utf8'));\n\
             const widen = (bytes) => Array.from(widenTexels(Uint8Array.from(bytes), pkg.texel_halves));\n\
             let refused = '';\n\
             try {{ widenTexels(Uint8Array.from([1]), pkg.texel_halves.slice(1)); }} catch (e) {{ refused = e.message; }}\n\
             console.log(JSON.stringify({{ every: widen({every}), sample: widen({sample}), refused }}));\n",
            module = json!(format!("file://{}", pkg.join("nimbus-host.js").display())),
            json = json!(pkg.join("nimbus-package.json").display().to_string()),
            every = json!(every_byte),
            sample = json!(sample),
        ),
    )
    .expect("write runner");
    let o = Command::new("node").arg(&runner).output().expect("node");
    assert!(o.status.success(), "node: {}", text(&o.stderr));
    let got: Value = serde_json::from_slice(&o.stdout).expect("node's JSON");
    let values = |key: &str| -> Vec<f32> {
        got[key]
            .as_array()
            .expect("halves")
            .iter()
            .map(|h| half::f16::from_bits(h.as_u64().expect("u16") as u16).to_f32())
            .collect()
    };
    let runtime = |bytes: &[u8]| -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .flat_map(|t| {
                nimbus_runtime::textures::texel_value(u32::from_le_bytes([t[0], t[1], t[2], t[3]]))
                    .to_array()
            })
            .collect()
    };
    assert_eq!(values("every"), runtime(&every_byte), "every byte value");
    assert_eq!(
        values("sample"),
        runtime(&sample),
        "the detail texture's first texels"
    );
    // The widened value is the byte's own, not its 8-bit neighbour's: 1/255 apart at each step.
    let every = values("every");
    assert!((every[128] - 128.0 / 255.0).abs() < 5e-4, "{}", every[128]);
    let refused = got["refused"].as_str().unwrap_or_default();
    assert!(
        refused.contains("texel_halves"),
        "a short table is refused: {refused:?}"
    );
}
