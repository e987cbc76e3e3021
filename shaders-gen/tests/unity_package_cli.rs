//! `nimbus emit --engine unity` writes what a Unity project takes: per pass one HLSL file with
//! both stages and plain registers (no sampler heap), a ShaderLab `.shader` (or, for the kernel,
//! a `.compute`) that includes it and names its entry points, and C# host functions printed from
//! the IR. The HLSL itself is checked by glslang and Slang in `tests/external_validation.rs` and
//! `tests/clouds.rs`, and drawn on Vulkan in `vulkan_host_cli.rs`; here the C# is compiled by
//! mono's C# compiler and run, and must compute what the Rust CPU twins compute.

mod common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use common::{examples, nimbus, text};
use glam::{Vec2, Vec4};
use nimbus_clouds::frame_sequence::{cloud_frame, drift_at, resolve_frame};
use nimbus_clouds::model::resolve::facing_altitude;
use nimbus_clouds::model::sun::sun_direction;
use nimbus_clouds::timeline::{weather_coverage, weather_progress};
use nimbus_clouds::wind::{wind_drift, wind_velocity, wind_velocity_at};
use nimbus_dsl::prelude::*;
use nimbus_dsl::{ModuleBuilder, host_fn, loc};

fn emit_unity(dir: &Path, scene: &str) -> std::path::PathBuf {
    let out = dir.join("unity");
    let o = nimbus(&[
        "emit",
        "--engine",
        "unity",
        "--scene",
        &examples(scene),
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
    out
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_pass_is_a_unity_asset_over_one_hlsl_program() {
    let dir = tempfile::tempdir().expect("temp dir");
    for scene in ["scenes/default.toml", "scenes/overcast.toml"] {
        let out = emit_unity(dir.path(), scene);
        let description: serde_json::Value =
            serde_json::from_str(&read(&out.join("nimbus-package.json"))).expect("JSON");
        let mut passes = BTreeMap::new();
        for pass in description["pairs"]
            .as_array()
            .expect("pairs")
            .iter()
            .flat_map(|p| p["passes"].as_array().expect("passes"))
        {
            passes.insert(pass["shader"].as_str().expect("shader").to_string(), pass);
        }
        assert!(passes.len() >= 5, "{scene}: {passes:?}");
        for (shader, pass) in &passes {
            let hlsl = read(&out.join(format!("{shader}.hlsl")));
            for heap in ["nagaSamplerHeap", "space255", "SamplerIndexArray"] {
                assert!(!hlsl.contains(heap), "{shader}.hlsl holds `{heap}`");
            }
            // Every binding in the file, in the register its manifest names.
            let manifest: serde_json::Value =
                serde_json::from_str(&read(&out.join(format!("{shader}.hlsl.json"))))
                    .expect("manifest");
            for b in manifest["bindings"].as_array().expect("bindings") {
                let target = b["target_name"].as_str().expect("target name");
                let (name, register) = target.split_once(" : ").expect("name : register");
                assert!(
                    hlsl.contains(&format!("{name} : {register}")),
                    "{shader}.hlsl does not declare `{target}`"
                );
                if b["kind"] == "uniform" {
                    assert!(
                        hlsl.contains(&format!("cbuffer {name} : ")),
                        "{shader}.hlsl: the block `{name}` is not a cbuffer of that name"
                    );
                }
            }
            let entries = pass["entry_points"].as_object().expect("entry points");
            // A constant defined twice would not compile as one program; glslang and Slang
            // compile each file whole, so here only: each stage's entry point is in the file.
            for entry in entries.values() {
                let entry = entry.as_str().expect("entry");
                assert!(
                    hlsl.contains(&format!(" {entry}(")),
                    "{shader}.hlsl lacks {entry}"
                );
            }
            let include = format!("#include \"{shader}.hlsl\"");
            if let Some(kernel) = entries.get("compute") {
                let compute = read(&out.join(format!("{shader}.compute")));
                assert!(compute.contains(&include), "{compute}");
                let pragma = format!("#pragma kernel {}", kernel.as_str().expect("kernel"));
                assert!(compute.contains(&pragma), "{compute}");
            } else {
                let lab = read(&out.join(format!("{shader}.shader")));
                assert!(
                    lab.contains(&format!("Shader \"Nimbus/{shader}\"")),
                    "{lab}"
                );
                assert!(lab.contains(&include), "{lab}");
                for (stage, pragma) in [("vertex", "vertex"), ("fragment", "fragment")] {
                    let entry = entries[stage].as_str().expect("entry");
                    let line = format!("#pragma {pragma} {entry}");
                    assert!(lab.contains(&line), "{shader}.shader lacks `{line}`");
                }
            }
        }
        for cs in [
            "NimbusFrame.cs",
            "NimbusWind.cs",
            "NimbusSun.cs",
            "NimbusClouds.cs",
        ] {
            assert!(out.join(cs).exists(), "{scene}: no {cs}");
        }
        std::fs::remove_dir_all(&out).expect("clean");
    }
}

fn tool(name: &str) -> bool {
    Command::new(name).arg("--version").output().is_ok()
}

/// Whether mono's C# compiler and runtime are here; says why a test skips (CI fails instead).
fn mono_available() -> bool {
    if tool("mcs") && tool("mono") {
        return true;
    }
    assert!(
        !std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1"),
        "NIMBUS_REQUIRE_TOOLS=1 but mono's C# compiler (apt-get install mono-mcs) is missing"
    );
    eprintln!("SKIPPED: mcs and mono are not installed (apt-get install mono-mcs)");
    false
}

/// `float` bits as C# prints them back.
fn bits(x: f32) -> String {
    x.to_bits().to_string()
}

/// One call per line: the C# expression printing its result as `bits` of each component, and
/// what the Rust CPU twin gives.
struct Calls {
    csharp: Vec<String>,
    rust: Vec<Vec<f32>>,
}

fn calls() -> Calls {
    let mut c = Calls {
        csharp: Vec::new(),
        rust: Vec::new(),
    };
    let f = |x: f32| format!("{x:?}f");
    let v2 = |v: Vec2| format!("new float2({}, {})", f(v.x), f(v.y));
    let v4 = |v: Vec4| format!("new float4({}, {}, {}, {})", f(v.x), f(v.y), f(v.z), f(v.w));
    for index in [0u32, 1, 2, 5, 15, 16, 17, 40, 1000, 4_000_000_000] {
        for seed in [0u32, 7, 123_456] {
            for upscale in [0u32, 1] {
                let r = cloud_frame(index, seed, upscale);
                c.csharp.push(format!(
                    "P(NimbusFrame.cloud_frame({index}u, {seed}u, {upscale}u))"
                ));
                c.rust.push(vec![
                    f32::from_bits(r.frame),
                    r.jitter,
                    r.pixel_offset.x,
                    r.pixel_offset.y,
                    r.pixel_scale,
                    r.subpixel.x,
                    r.subpixel.y,
                ]);
            }
        }
    }
    let drifts = [
        Vec4::ZERO,
        Vec4::new(120.5, -30.25, 0.004, -0.001),
        Vec4::new(-5000.0, 812.0, 0.02, 0.03),
    ];
    for (i, drift) in drifts.iter().enumerate() {
        let previous = drifts[(i + 1) % drifts.len()];
        for (index, upscale, moved) in [(0u32, 0u32, 0u32), (3, 1, 0), (17, 0, 1), (16, 1, 1)] {
            let resolution = Vec2::new(641.0, 359.0);
            let r = resolve_frame(index, upscale, moved, *drift, previous, 1500.0, resolution);
            c.csharp.push(format!(
                "P(NimbusFrame.resolve_frame({index}u, {upscale}u, {moved}u, {}, {}, 1500.0f, {}))",
                v4(*drift),
                v4(previous),
                v2(resolution)
            ));
            c.rust.push(vec![
                r.low_resolution.x,
                r.low_resolution.y,
                r.pixel_offset.x,
                r.pixel_offset.y,
                r.pixel_scale,
                r.current_weight,
                r.variance_gamma,
                r.history_valid,
                r.cloud_shift.x,
                r.cloud_shift.y,
                r.cloud_shift.z,
            ]);
        }
        let d = drift_at(*drift, 2500.0);
        c.csharp
            .push(format!("P(NimbusFrame.drift_at({}, 2500.0f))", v4(*drift)));
        c.rust.push(vec![d.x, d.y, d.z]);
    }
    for (speed, dir) in [(0.0f32, 0.0f32), (6.0, 260.0), (22.5, 91.0), (3.0, -45.0)] {
        let ground = wind_velocity(speed, dir);
        let top = wind_velocity(speed * 2.5, dir + 30.0);
        c.csharp.push(format!(
            "P(NimbusWind.wind_velocity({}, {}))",
            f(speed),
            f(dir)
        ));
        c.rust.push(vec![ground.x, ground.y]);
        for altitude in [0.0f32, 1500.0, 12_000.0] {
            let v = wind_velocity_at(ground, top, altitude);
            c.csharp.push(format!(
                "P(NimbusWind.wind_velocity_at({}, {}, {}))",
                v2(ground),
                v2(top),
                f(altitude)
            ));
            c.rust.push(vec![v.x, v.y]);
        }
        let d = wind_drift(ground, top, 900.0);
        c.csharp.push(format!(
            "P(NimbusWind.wind_drift({}, {}, 900.0f))",
            v2(ground),
            v2(top)
        ));
        c.rust.push(vec![d.x, d.y, d.z, d.w]);
    }
    for (seconds, from_at, to_at, over) in [
        (0.0f32, 0.0f32, 600.0f32, -1.0f32),
        (300.0, 0.0, 600.0, -1.0),
        (500.0, 0.0, 600.0, 200.0),
        (700.0, 600.0, 600.0, 0.0),
    ] {
        let p = weather_progress(seconds, from_at, to_at, over);
        c.csharp.push(format!(
            "P(NimbusWind.weather_progress({}, {}, {}, {}))",
            f(seconds),
            f(from_at),
            f(to_at),
            f(over)
        ));
        c.rust.push(vec![p]);
        c.csharp.push(format!(
            "P(NimbusWind.weather_coverage(0.2f, 0.7f, {}))",
            f(p)
        ));
        c.rust.push(vec![weather_coverage(0.2, 0.7, p)]);
    }
    for camera in [2.0f32, 1600.0, 5000.0] {
        c.csharp.push(format!(
            "P(NimbusWind.facing_altitude({}, 1500.0f, 3000.0f))",
            f(camera)
        ));
        c.rust.push(vec![facing_altitude(camera, 1500.0, 3000.0)]);
    }
    for (el, az) in [(30.0f32, 150.0f32), (-3.0, 90.0), (89.0, 0.0), (8.0, 230.0)] {
        let s = sun_direction(el, az);
        c.csharp
            .push(format!("P(NimbusSun.sun_direction({}, {}))", f(el), f(az)));
        c.rust.push(vec![s.x, s.y, s.z]);
    }
    c
}

/// The C# program that prints each call's result, one line each (`frames`: it prints the
/// frame sequence's structs, whose file is compiled with it).
fn driver(calls: &[String], frames: bool) -> String {
    let mut s = String::from(
        "using System;\nusing Nimbus;\nusing Unity.Mathematics;\n\
         static class Driver\n{\n\
         static string B(float x) => BitConverter.ToUInt32(BitConverter.GetBytes(x), 0).ToString();\n\
         static string U(uint x) => x.ToString();\n\
         static void Line(params string[] p) => Console.WriteLine(string.Join(\" \", p));\n\
         static void P(uint x) => Line(U(x));\n\
         static void P(int x) => Line(x.ToString());\n\
         static void P(float x) => Line(B(x));\n\
         static void P(float2 v) => Line(B(v.x), B(v.y));\n\
         static void P(float3 v) => Line(B(v.x), B(v.y), B(v.z));\n\
         static void P(float4 v) => Line(B(v.x), B(v.y), B(v.z), B(v.w));\n",
    );
    if frames {
        s.push_str(
            "static void P(CloudFrame f) => Line(U(f.frame), B(f.jitter), B(f.pixel_offset.x), \
             B(f.pixel_offset.y), B(f.pixel_scale), B(f.subpixel.x), B(f.subpixel.y));\n\
             static void P(ResolveFrame f) => Line(B(f.low_resolution.x), B(f.low_resolution.y), \
             B(f.pixel_offset.x), B(f.pixel_offset.y), B(f.pixel_scale), B(f.current_weight), \
             B(f.variance_gamma), B(f.history_valid), B(f.cloud_shift.x), B(f.cloud_shift.y), \
             B(f.cloud_shift.z));\n",
        );
    }
    s.push_str("static void Main()\n{\n");
    for c in calls {
        s.push_str(c);
        s.push_str(";\n");
    }
    s.push_str("}\n}\n");
    s
}

/// Whether two results agree: integers exactly, floats to an ulp or so (the C# runtime's
/// `Math.Sin` is not Rust's).
fn agree(want: f32, got: f32) -> bool {
    want.to_bits() == got.to_bits() || (want - got).abs() <= 1e-6 * want.abs().max(1e-3)
}

#[test]
fn the_csharp_host_functions_compute_what_the_cpu_twins_do() {
    if !mono_available() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let out = emit_unity(dir.path(), "scenes/default.toml");
    let calls = calls();
    let sources = ["NimbusFrame.cs", "NimbusWind.cs", "NimbusSun.cs"].map(|f| out.join(f));
    let lines: Vec<Vec<f32>> = run_csharp(dir.path(), &sources, &calls.csharp, true)
        .iter()
        .map(|l| {
            l.split(' ')
                .map(|w| f32::from_bits(w.parse().expect("bits")))
                .collect()
        })
        .collect();
    assert_eq!(lines.len(), calls.rust.len(), "one line per call");
    let mut compared = 0;
    for ((call, want), got) in calls.csharp.iter().zip(&calls.rust).zip(&lines) {
        assert_eq!(want.len(), got.len(), "{call}");
        for (w, g) in want.iter().zip(got) {
            assert!(
                agree(*w, *g),
                "{call}: C# {g:?} ({}), Rust {w:?} ({})",
                bits(*g),
                bits(*w)
            );
            compared += 1;
        }
    }
    // The control: the comparison tells neighbouring frames apart.
    let shifted =
        lines.iter().skip(1).zip(&calls.rust).filter(|(g, w)| {
            g.len() != w.len() || g.iter().zip(w.iter()).any(|(a, b)| !agree(*b, *a))
        });
    assert!(
        shifted.count() > calls.rust.len() / 2,
        "the comparison cannot fail"
    );
    println!(
        "{} calls, {compared} values: the C# twins (mono) agree with the Rust CPU twins",
        calls.rust.len()
    );
}

// WGSL's edge cases, as host functions: C# would throw on an integer division by zero, cast a
// negative float to a huge `uint`, rank `==` above `&`, and let a local hide `math`.
#[shader_fn]
fn quotient(a: u32, b: u32) -> u32 {
    a / b
}

#[shader_fn]
fn remainder(a: i32, b: i32) -> i32 {
    a % b
}

#[shader_fn]
fn to_unsigned(x: f32) -> u32 {
    x as u32
}

#[shader_fn]
fn to_signed(x: f32) -> i32 {
    x as i32
}

#[shader_fn]
fn parity(a: u32) -> u32 {
    // C# ranks `==` above `&`: the printed comparison needs its parentheses.
    select(0u32, 1u32, (a & 1u32) == 1u32)
}

#[shader_fn]
fn shadowing(x: f32) -> f32 {
    let math = x * 2.0;
    math + x.abs()
}

/// Compiles the driver of `calls` with `sources` and runs it: each call's output line.
fn run_csharp(
    dir: &Path,
    sources: &[std::path::PathBuf],
    calls: &[String],
    frames: bool,
) -> Vec<String> {
    let program = dir.join("Driver.cs");
    std::fs::write(&program, driver(calls, frames)).expect("write driver");
    let exe = dir.join("driver.exe");
    let shim = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/csharp/UnityMathematics.cs");
    let o = Command::new("mcs")
        .arg("-warnaserror+")
        .arg(format!("-out:{}", exe.display()))
        .arg(&shim)
        .args(sources)
        .arg(&program)
        .output()
        .expect("run mcs");
    assert!(
        o.status.success(),
        "mcs: {}{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    let o = Command::new("mono").arg(&exe).output().expect("run mono");
    assert!(o.status.success(), "mono: {}", text(&o.stderr));
    text(&o.stdout).lines().map(str::to_string).collect()
}

#[test]
fn the_csharp_twins_keep_wgsl_semantics_where_csharp_differs() {
    if !mono_available() {
        return;
    }
    let module = ModuleBuilder::build("edges", "WGSL's edge cases.", loc!(), |m| {
        m.host(host_fn!(quotient), loc!());
        m.host(host_fn!(remainder), loc!());
        m.host(host_fn!(to_unsigned), loc!());
        m.host(host_fn!(to_signed), loc!());
        m.host(host_fn!(parity), loc!());
        m.host(host_fn!(shadowing), loc!());
    })
    .expect("records");
    let exports = [
        "quotient",
        "remainder",
        "to_unsigned",
        "to_signed",
        "parity",
        "shadowing",
    ];
    let text_cs = nimbus_codegen::print_csharp(&module, &exports, "Edges").expect("prints");
    let dir = tempfile::tempdir().expect("temp dir");
    let source = dir.path().join("Edges.cs");
    std::fs::write(&source, &text_cs).expect("write");
    // (call, WGSL's result as printed by the driver): integers as decimal, floats as bits.
    let cases: Vec<(String, String)> = vec![
        ("P(Edges.quotient(7u, 2u))".into(), "3".into()),
        // WGSL: a / 0 is a, a % 0 is 0, the most negative i32 % -1 is 0.
        ("P(Edges.quotient(7u, 0u))".into(), "7".into()),
        ("P(Edges.remainder(-7, 2))".into(), "-1".into()),
        ("P(Edges.remainder(-7, 0))".into(), "0".into()),
        ("P(Edges.remainder(int.MinValue, -1))".into(), "0".into()),
        // Float to integer saturates.
        ("P(Edges.to_unsigned(-3.5f))".into(), "0".into()),
        ("P(Edges.to_unsigned(3.9f))".into(), "3".into()),
        ("P(Edges.to_unsigned(1e20f))".into(), "4294967040".into()),
        ("P(Edges.to_signed(-1e20f))".into(), "-2147483648".into()),
        ("P(Edges.to_signed(-2.5f))".into(), "-2".into()),
        ("P(Edges.parity(5u))".into(), "1".into()),
        ("P(Edges.parity(4u))".into(), "0".into()),
        ("P(Edges.shadowing(-1.5f))".into(), bits(-1.5)),
    ];
    // The CPU twins agree where Rust defines the value (not for a division by zero).
    assert_eq!(quotient(7, 2), 3);
    assert_eq!(remainder(-7, 2), -1);
    assert_eq!(to_unsigned(-3.5), 0);
    assert_eq!(to_signed(-2.5), -2);
    assert_eq!(parity(5), 1);
    assert_eq!(shadowing(-1.5), -1.5);
    let calls: Vec<String> = cases.iter().map(|(c, _)| c.clone()).collect();
    let got = run_csharp(dir.path(), &[source], &calls, false);
    assert_eq!(got.len(), cases.len(), "{text_cs}");
    for ((call, want), got) in cases.iter().zip(&got) {
        assert_eq!(got, want, "{call} in:\n{text_cs}");
    }
}
