//! The host contract, held: the three.js package's own JavaScript (`NimbusClouds`, run by node
//! with a renderer that keeps the block bytes it is handed) and Nimbus's wgpu runtime (its
//! uniform log) write the same cloud and resolve blocks for the same 64-frame sequences —
//! single frames, still and moving cameras, accumulated and upscaled, with the wind blowing.
//! Every member is compared: the frame sequence's (jitter, offsets, weights, clipping, the
//! wind's shift) bit for bit, since both hosts run the same host functions; the camera's
//! matrices through the rays they give (three builds its projection its own way); the rest to
//! f32 rounding.
//!
//! Needs node, `browser/node_modules` and a GPU adapter (lavapipe in CI).

mod common;

use std::path::Path;
use std::process::Command;

use glam::{Mat4, Vec4};
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::resolve::ResolveParams;
use nimbus_clouds::wind::Wind;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_dsl::ir::Type;
use nimbus_dsl::layout::UniformBytes;
use nimbus_dsl::layout::member_layout;
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes, WrittenFrame};
use nimbus_testkit::skip::{browser_tools_present, node_missing};
use serde_json::{Value, json};

use common::{browser_dir, emit_package, have_gpu, text};

const WIDTH: u32 = 24;
const HEIGHT: u32 = 14;

/// Members a host computes each frame by the frame sequence's host functions: equal bit for
/// bit.
const SEQUENCE_MEMBERS: [&str; 10] = [
    "frame",
    "jitter",
    "pixel_offset",
    "pixel_scale",
    "subpixel",
    "low_resolution",
    "current_weight",
    "variance_gamma",
    "history_valid",
    "resolution",
];

/// The wind's shift since the last frame is a difference of two drifts (hundreds of metres):
/// the drift itself comes from the wind's velocity, whose sine and cosine a JavaScript engine
/// and Rust's libm round differently, so the difference agrees to the drifts' f32 rounding: a
/// few of its steps at the sequences' drifts of up to 3 km (2.4e-4 m each).
const SHIFT_TOLERANCE_M: f64 = 1e-3;

/// One step of a sequence: the camera (pitch, yaw, fov, altitude), the clock, and how many
/// frames are drawn from it (one `render` call of that many frames in the runtime).
#[derive(Clone, Copy)]
struct Step {
    pitch: f32,
    yaw: f32,
    fov: f32,
    altitude: f32,
    time: f64,
    renders: u32,
}

struct Sequence {
    name: &'static str,
    upscale: bool,
    accumulate: bool,
    seed: u32,
    wind: Option<Wind>,
    steps: Vec<Step>,
}

fn still(renders: u32, steps: usize) -> Vec<Step> {
    vec![
        Step {
            pitch: 12.0,
            yaw: 0.0,
            fov: 60.0,
            altitude: 2.0,
            time: 0.0,
            renders,
        };
        steps
    ]
}

/// `steps` steps of `renders` frames, turning, climbing (40 m a step: the sky is relit at each
/// altitude) and going on in time.
fn moving(renders: u32, steps: usize) -> Vec<Step> {
    (0..steps)
        .map(|i| Step {
            pitch: 12.0 + i as f32 * 0.5,
            yaw: i as f32 * 1.25,
            fov: 60.0,
            altitude: 2.0 + i as f32 * 40.0,
            time: i as f64 * 2.0,
            renders,
        })
        .collect()
}

fn sequences() -> Vec<Sequence> {
    let wind = Wind {
        speed: 9.0,
        direction_deg: 250.0,
        top_speed: Some(25.0),
        top_direction_deg: Some(280.0),
    };
    vec![
        Sequence {
            name: "single frames",
            upscale: false,
            accumulate: false,
            seed: 0,
            wind: None,
            steps: still(1, 8),
        },
        Sequence {
            name: "still, accumulated",
            upscale: false,
            accumulate: true,
            seed: 3,
            wind: None,
            steps: still(64, 1),
        },
        Sequence {
            name: "still, upscaled",
            upscale: true,
            accumulate: false,
            seed: 0,
            wind: None,
            steps: still(64, 1),
        },
        Sequence {
            name: "moving in the wind, upscaled",
            upscale: true,
            accumulate: false,
            seed: 11,
            wind: Some(wind),
            steps: moving(1, 64),
        },
        Sequence {
            name: "moving in the wind, accumulated",
            upscale: false,
            accumulate: true,
            seed: 5,
            wind: Some(wind),
            steps: moving(2, 32),
        },
    ]
}

/// What the runtime writes for `seq`.
fn runtime_blocks(gpu: &Gpu, seq: &Sequence) -> Vec<WrittenFrame> {
    let lib = CloudLibrary::load(Path::new(&common::examples(""))).expect("library");
    let genus = lib.genus("cumulus").expect("cumulus").clone();
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    renderer.set_uniform_log(true);
    for (i, s) in seq.steps.iter().enumerate() {
        let mut f = Frame::new(genus.clone(), Quality::Low, WIDTH, HEIGHT);
        f.camera_pitch_deg = s.pitch;
        f.camera_yaw_deg = s.yaw;
        f.fov_deg = s.fov;
        f.camera_altitude = s.altitude;
        f.seed = seq.seed;
        f.upscale = seq.upscale;
        f.frames = s.renders;
        f.continue_history = i > 0;
        if let Some(w) = seq.wind {
            f.wind = w.drift(s.time);
        }
        renderer.render(&f).expect("renders");
    }
    renderer.uniform_log().to_vec()
}

/// What the package's JavaScript writes for `seq`: (pass, bytes) per draw.
fn package_blocks(package: &Path, seq: &Sequence, scratch: &Path) -> Vec<(String, Vec<u8>)> {
    let steps: Vec<Value> = seq
        .steps
        .iter()
        .map(|s| {
            json!({"pitch": s.pitch, "yaw": s.yaw, "fov": s.fov, "altitude": s.altitude,
                   "time": s.time, "renders": s.renders})
        })
        .collect();
    let wind = seq.wind.map(|w| {
        json!([
            w.speed,
            w.direction_deg,
            w.top_speed.unwrap_or(w.speed),
            w.top_direction_deg.unwrap_or(w.direction_deg)
        ])
    });
    let spec = json!({
        "width": WIDTH, "height": HEIGHT, "upscale": seq.upscale, "accumulate": seq.accumulate,
        "seed": seq.seed, "wind": wind, "steps": steps,
    });
    let file = scratch.join("sequence.json");
    std::fs::write(&file, spec.to_string()).expect("writes the sequence");
    let out = Command::new("node")
        .arg(browser_dir().join("frame-sequence.mjs"))
        .arg(package)
        .arg(&file)
        .output()
        .expect("runs node");
    assert!(
        out.status.success(),
        "{}: node failed: {}",
        seq.name,
        text(&out.stderr)
    );
    let drawn: Vec<Value> = serde_json::from_slice(&out.stdout).expect("node prints JSON");
    drawn
        .iter()
        .map(|d| {
            let hex = d["hex"].as_str().expect("hex");
            let bytes = (0..hex.len() / 2)
                .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).expect("hex digit"))
                .collect();
            (d["pass"].as_str().expect("pass").to_string(), bytes)
        })
        .collect()
}

/// The block's members by path: type and words.
fn members(ty: Type, bytes: &[u8]) -> Vec<(String, Type, Vec<f64>)> {
    member_layout(ty, bytes)
        .into_iter()
        .map(|m| (m.path, m.ty, m.value))
        .collect()
}

fn matrix(words: &[f64]) -> Mat4 {
    let v: Vec<f32> = words.iter().map(|&w| w as f32).collect();
    Mat4::from_cols_slice(&v)
}

/// The largest angle (rad) between the rays two inverse view-projections give over the image.
fn ray_disagreement(a: Mat4, b: Mat4) -> f32 {
    let mut worst = 0.0f32;
    for (x, y) in [
        (-1.0, -1.0),
        (1.0, -1.0),
        (-1.0, 1.0),
        (1.0, 1.0),
        (0.0, 0.0),
        (0.3, -0.7),
    ] {
        let ray = |m: Mat4| {
            let c = m * Vec4::new(x, y, 1.0, 1.0);
            (c.truncate() / c.w).normalize()
        };
        // The sine from the cross product: an arc cosine of an f32 dot product near 1 cannot
        // tell angles under 3e-4 rad apart.
        worst = worst.max(ray(a).cross(ray(b)).length().asin());
    }
    worst
}

/// Compares one block member by member; returns the differences found.
fn compare(what: &str, ty: Type, runtime: &[u8], package: &[u8]) -> Vec<String> {
    let mut problems = Vec::new();
    let (r, p) = (members(ty, runtime), members(ty, package));
    for ((path, mty, rv), (_, _, pv)) in r.iter().zip(&p) {
        let leaf = path.rsplit('.').next().unwrap_or(path);
        if matches!(mty, Type::Matrix(4)) && path.contains("view_projection") {
            // The inverse gives rays; the previous frame's is a forward view-projection.
            let (a, b) = (matrix(rv), matrix(pv));
            let angle = if path.starts_with("inverse") {
                ray_disagreement(a, b)
            } else {
                ray_disagreement(a.inverse(), b.inverse())
            };
            if angle > 2e-5 {
                problems.push(format!("{what}.{path}: rays {angle:.2e} rad apart"));
            }
        } else if path == "cloud_shift" {
            if rv
                .iter()
                .zip(pv)
                .any(|(a, b)| (a - b).abs() > SHIFT_TOLERANCE_M)
            {
                problems.push(format!("{what}.{path}: runtime {rv:?}, package {pv:?}"));
            }
        } else if SEQUENCE_MEMBERS.contains(&leaf) && !path.contains('.') {
            if rv != pv {
                problems.push(format!("{what}.{path}: runtime {rv:?}, package {pv:?}"));
            }
        } else {
            // What the sun decides at the camera's altitude comes from the JavaScript twin of
            // `sun_light`, which agrees with its CPU twin to 5.7e-6 (tests/host_js.rs).
            let tolerance = if path.starts_with("light.") || path.starts_with("shadow.") {
                1e-5
            } else {
                2e-6
            };
            for (a, b) in rv.iter().zip(pv) {
                let scale = a.abs().max(b.abs()).max(1e-3);
                if (a - b).abs() / scale > tolerance {
                    problems.push(format!("{what}.{path}: runtime {rv:?}, package {pv:?}"));
                    break;
                }
            }
        }
    }
    problems
}

#[test]
fn the_package_writes_what_the_runtime_writes_for_every_frame() {
    if !browser_tools_present(
        "the_package_writes_what_the_runtime_writes_for_every_frame",
        node_missing().or_else(|| {
            (!browser_dir().join("node_modules/three").is_dir())
                .then(|| "browser/node_modules is missing: run `npm ci` in browser/".into())
        }),
    ) || !have_gpu()
    {
        return;
    }
    let gpu = Gpu::new().expect("adapter");
    println!("runtime on {}", gpu.info());
    let dir = tempfile::tempdir().expect("temp dir");
    let package = dir.path().join("pkg");
    emit_package("three", "cumulus", "low", &[], &package);
    // The package's `import 'three'` resolves from a node_modules beside it.
    #[cfg(unix)]
    std::os::unix::fs::symlink(
        browser_dir().join("node_modules"),
        package.join("node_modules"),
    )
    .expect("links node_modules");

    let mut report = Vec::new();
    let mut frames = 0;
    for seq in sequences() {
        let runtime = runtime_blocks(&gpu, &seq);
        let drawn = package_blocks(&package, &seq, dir.path());
        // The package's draws, grouped into frames: a clouds draw, then its resolve draw.
        let mut js: Vec<(Vec<u8>, Option<Vec<u8>>)> = Vec::new();
        for (pass, bytes) in drawn {
            match pass.as_str() {
                "clouds" => js.push((bytes, None)),
                _ => js.last_mut().expect("a clouds draw first").1 = Some(bytes),
            }
        }
        assert_eq!(
            runtime.len(),
            js.len(),
            "{}: the runtime drew {} frames, the package {}",
            seq.name,
            runtime.len(),
            js.len()
        );
        for (i, (r, (pc, pr))) in runtime.iter().zip(&js).enumerate() {
            let what = format!("{} frame {i}", seq.name);
            report.extend(compare(
                &format!("{what}: clouds"),
                CloudUniforms::shader_type(),
                &r.clouds,
                pc,
            ));
            match (&r.resolve, pr) {
                (Some(a), Some(b)) => report.extend(compare(
                    &format!("{what}: resolve"),
                    ResolveParams::shader_type(),
                    a,
                    b,
                )),
                (None, None) => {}
                (a, b) => report.push(format!(
                    "{what}: resolved by the runtime {}, by the package {}",
                    a.is_some(),
                    b.is_some()
                )),
            }
        }
        frames += runtime.len();
        println!("{}: {} frames compared", seq.name, runtime.len());
    }
    assert!(frames >= 4 * 64, "{frames} frames compared");
    assert!(
        report.is_empty(),
        "{} differences between the runtime's and the package's blocks, e.g.:\n{}",
        report.len(),
        report[..report.len().min(25)].join("\n")
    );
}
