//! `nimbus render --format exr`: a linear OpenEXR with the composited image and the clouds'
//! radiance, transmittance and front depth, read back by a different library — the reference
//! OpenEXR implementation through its Python bindings (`tools/exr_channels.py`), not the Rust
//! `exr` crate that wrote it. The layers must agree with each other (they are separate renders
//! of one frame), and verification mode must leave nothing but the clouds' own light.

mod common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use common::{examples, have_gpu, nimbus, text};

/// The reference OpenEXR reader, through its Python bindings.
fn have_openexr() -> bool {
    common::have_python("import OpenEXR, numpy", "the OpenEXR bindings and numpy")
}

struct Channels {
    width: usize,
    height: usize,
    software: String,
    values: BTreeMap<String, Vec<f32>>,
}

/// Renders the default scene to an EXR with `extra` flags and reads it back through OpenEXR.
fn render_and_read(extra: &[&str]) -> Channels {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("clouds.exr");
    let mut args = vec![
        "render",
        "-r",
        "64x36",
        "-q",
        "low",
        "-f",
        "1",
        "-o",
        out.to_str().expect("utf8"),
    ];
    let scene = examples("scenes/default.toml");
    args.push(&scene);
    args.extend_from_slice(extra);
    let o = nimbus(&args);
    assert!(
        o.status.success(),
        "{}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    let folder = tmp.path().join("channels");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/exr_channels.py");
    let py = Command::new("python3")
        .arg(&script)
        .arg(&out)
        .arg(&folder)
        .output()
        .expect("run python3");
    assert!(py.status.success(), "{}", text(&py.stderr));
    let meta: serde_json::Value =
        serde_json::from_slice(&std::fs::read(folder.join("channels.json")).expect("json"))
            .expect("parse");
    let mut values = BTreeMap::new();
    for name in meta["channels"].as_array().expect("channels") {
        let name = name.as_str().expect("name");
        let bytes = std::fs::read(folder.join(format!("{name}.f32"))).expect("channel");
        let v = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
            .collect();
        values.insert(name.to_string(), v);
    }
    Channels {
        width: meta["width"].as_u64().expect("width") as usize,
        height: meta["height"].as_u64().expect("height") as usize,
        software: meta["software"].as_str().unwrap_or_default().to_string(),
        values,
    }
}

#[test]
fn render_writes_an_exr_whose_layers_another_library_reads_and_that_agree() {
    if !have_gpu() || !have_openexr() {
        return;
    }
    let c = render_and_read(&[]);
    assert_eq!((c.width, c.height), (64, 36));
    assert!(c.software.starts_with("Nimbus"), "software: {}", c.software);
    let names: Vec<&str> = c.values.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "A",
            "B",
            "G",
            "R",
            "clouds.B",
            "clouds.G",
            "clouds.R",
            "clouds.transmittance",
            "depth.Z"
        ]
    );
    let ch = |n: &str| &c.values[n];
    let n = c.width * c.height;
    assert!(
        c.values
            .values()
            .all(|v| v.len() == n && v.iter().all(|x| x.is_finite()))
    );
    // The composite's alpha is the clouds' opacity; the clouds layer's alpha their
    // transmittance: two renders of one frame, so they must sum to 1 (to the half-float
    // targets' rounding, 2⁻¹¹ each).
    let worst = (0..n)
        .map(|i| (ch("A")[i] + ch("clouds.transmittance")[i] - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-3, "opacity + transmittance off 1 by {worst}");
    // Depth where there is cloud, −1 where there is none.
    let (mut cloudy, mut clear) = (0, 0);
    for i in 0..n {
        let (t, z) = (ch("clouds.transmittance")[i], ch("depth.Z")[i]);
        if t < 0.999 {
            assert!(z > 100.0, "pixel {i}: transmittance {t} but depth {z}");
            cloudy += 1;
        } else if t == 1.0 {
            assert_eq!(z, -1.0, "pixel {i}: no cloud but depth {z}");
            clear += 1;
        }
    }
    println!("{cloudy} cloudy and {clear} clear pixels of {n}");
    assert!(
        cloudy > n / 10 && clear > 0,
        "{cloudy} cloudy, {clear} clear"
    );
    // Outside verification mode the composite has the sky behind and the air in front: it is
    // not the clouds' own light (the control for the next test).
    let differs = (0..n)
        .filter(|&i| (ch("R")[i] - ch("clouds.R")[i]).abs() > 1e-3 * ch("R")[i].abs().max(1e-3))
        .count();
    assert!(differs > n / 2, "only {differs} pixels differ");
}

#[test]
fn verification_mode_leaves_only_the_clouds_single_scattering() {
    if !have_gpu() || !have_openexr() {
        return;
    }
    let c = render_and_read(&["--verification"]);
    let ch = |n: &str| &c.values[n];
    let n = c.width * c.height;
    let mut lit = 0;
    for i in 0..n {
        for (composite, clouds) in [("R", "clouds.R"), ("G", "clouds.G"), ("B", "clouds.B")] {
            let (a, b) = (ch(composite)[i], ch(clouds)[i]);
            assert!(
                (a - b).abs() <= 1e-6 * b.abs().max(1e-3),
                "pixel {i} {composite}: composite {a} is not the clouds' own {b}"
            );
        }
        // A grey sun of irradiance 1 and no sky: the clouds' light is grey.
        let (r, g, b) = (ch("clouds.R")[i], ch("clouds.G")[i], ch("clouds.B")[i]);
        assert!(
            (r - g).abs() <= 1e-6 && (r - b).abs() <= 1e-6,
            "pixel {i}: {r} {g} {b}"
        );
        if ch("clouds.transmittance")[i] == 1.0 {
            assert_eq!(r, 0.0, "pixel {i}: light without cloud");
        } else if r > 0.0 {
            lit += 1;
        }
    }
    assert!(lit > n / 10, "{lit} lit cloud pixels");
}
