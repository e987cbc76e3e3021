//! The error catalogue: bad inputs across scene files, genus files, flags, textures, output
//! paths and data folders, each run through the `nimbus` binary in a fresh folder holding a
//! file of the user's. Every case must exit non-zero without panicking, name where the value
//! came from (the flag, or the file and field) and the value or reason, and leave the folder
//! exactly as it was: nothing written, nothing overwritten, no temporary left behind.

mod common;

use std::process::Command;

use common::{text, tree};

/// One bad input.
struct Case {
    name: String,
    args: Vec<String>,
    env: Vec<(String, String)>,
    /// Files to create in the case's folder first (relative path, contents).
    files: Vec<(String, Vec<u8>)>,
    /// What stderr must contain: the origin, the value or the reason.
    expect: Vec<String>,
}

fn case(name: &str, args: &[&str], expect: &[&str]) -> Case {
    Case {
        name: name.to_string(),
        args: args.iter().map(|s| s.to_string()).collect(),
        env: Vec::new(),
        files: Vec::new(),
        expect: expect.iter().map(|s| s.to_string()).collect(),
    }
}

impl Case {
    fn with_file(mut self, path: &str, contents: impl Into<Vec<u8>>) -> Case {
        self.files.push((path.to_string(), contents.into()));
        self
    }

    fn with_env(mut self, key: &str, value: &str) -> Case {
        self.env.push((key.to_string(), value.to_string()));
        self
    }
}

const SCENE: &str = "name = \"scene\"\ndescription = \"catalogue\"\ngenus = \"cumulus\"\n\
                     quality = \"low\"\n";

const GENUS: &str = "name = \"mine\"\ndescription = \"catalogue\"\ncoverage = 0.5\n\
                     [[layers]]\nchannel = \"r\"\naltitude = 1500.0\nheight = 1500.0\n\
                     density_scale = 0.2\n";

/// A scene file with `line` added (or replacing a field of the base).
fn scene_with(line: &str) -> String {
    format!("{SCENE}{line}\n")
}

fn cases() -> Vec<Case> {
    let mut all = Vec::new();

    // Scene-file values out of range, through every command that reads a scene: the error
    // names the file and field, and the value.
    let scene_values: &[(&str, &str, &str)] = &[
        ("sun_elevation_deg", "91.0", "91"),
        ("sun_elevation_deg", "-90.5", "-90.5"),
        ("sun_elevation_deg", "nan", "NaN"),
        ("sun_azimuth_deg", "inf", "inf"),
        ("camera_altitude", "-1.0", "-1"),
        ("camera_altitude", "2000000.0", "2000000"),
        ("camera_pitch_deg", "95.0", "95"),
        ("camera_yaw_deg", "nan", "NaN"),
        ("fov_deg", "0.0", "0"),
        ("fov_deg", "179.5", "179.5"),
        ("coverage", "1.5", "1.5"),
        ("coverage", "-0.1", "-0.1"),
        ("haze_density", "1.0", "1"),
        ("turbulence_displacement", "6000.0", "6000"),
        ("weather_offset", "[nan, 0.0]", "NaN"),
        ("features.path", "\"hologram\"", "hologram"),
    ];
    for (field, value, shown) in scene_values {
        let file = scene_with(&format!("{field} = {value}"));
        for (cmd, args) in [
            ("explain", vec!["explain", "scenes/scene.toml"]),
            (
                "emit",
                vec!["emit", "--scene", "scenes/scene.toml", "-o", "out"],
            ),
            (
                "render",
                vec!["render", "scenes/scene.toml", "-o", "out.png"],
            ),
            (
                "export-density",
                vec!["export-density", "scenes/scene.toml", "-o", "out.vol"],
            ),
        ] {
            all.push(
                case(
                    &format!("{cmd}: scene {field} = {value}"),
                    &args,
                    &[&format!("scene.toml: {field}"), shown],
                )
                .with_file("scenes/scene.toml", file.clone()),
            );
        }
    }

    // Render flags out of range: the error names the flag (not a scene field) and the value.
    let flags: &[(&str, &str, &str)] = &[
        ("--fov", "0", "0"),
        ("--fov", "180", "180"),
        ("--fov", "nan", "NaN"),
        ("--sun-elevation", "100", "100"),
        ("--pitch", "-91", "-91"),
        ("--camera-altitude", "-5", "-5"),
        ("--camera-altitude", "1e7", "1e7"),
        ("--yaw", "nan", "NaN"),
        ("--sun-azimuth", "inf", "inf"),
        ("--coverage", "2", "2"),
        ("--exposure", "0", "0"),
        ("--exposure", "nan", "NaN"),
        ("--exposure", "inf", "inf"),
        ("--exposure", "1e30", "1e30"),
        ("--exposure", "-1", "-1"),
        ("--frames", "0", "0"),
        ("--frames", "5000", "5000"),
        ("--resolution", "0x0", "0"),
        ("--resolution", "0x90", "0"),
        ("--resolution", "99999x10", "99999"),
        ("--resolution", "axb", "axb"),
        ("--resolution", "640", "640"),
        ("--octaves", "0", "0"),
        ("--octaves", "13", "13"),
        ("--path", "hologram", "hologram"),
    ];
    for (flag, value, shown) in flags {
        all.push(case(
            &format!("render {flag} {value}"),
            &["render", "-o", "out.png", flag, value],
            &[flag, shown],
        ));
    }
    // A baked path for an engine whose host does not draw its pass: the error names the
    // engine, the pair and the path, and writes nothing.
    all.push(case(
        "emit --engine vulkan --path blob2d",
        &[
            "emit",
            "--engine",
            "vulkan",
            "--genus",
            "cumulus",
            "--quality",
            "low",
            "--path",
            "blob2d",
            "-o",
            "pkg",
        ],
        &["--engine vulkan", "cumulus.low", "blob2d"],
    ));
    // The same limits hold for the benches and the study.
    all.push(case(
        "bench-frames --fov 185",
        &["bench-frames", "--fov", "185"],
        &["--fov", "185"],
    ));
    for (flag, value) in [
        ("-f", "0"),
        ("--reference-frames", "0"),
        ("-n", "0"),
        ("--exposure", "0"),
        ("--resolution", "0x0"),
    ] {
        let named = if flag == "-f" {
            "--frames"
        } else if flag == "-n" {
            "--repeats"
        } else {
            flag
        };
        let shown = value.split('x').next().unwrap_or(value);
        all.push(case(
            &format!("tradeoff {flag} {value}"),
            &["tradeoff", "-o", "study", flag, value],
            &[named, shown],
        ));
    }

    // Genus files: the error names the file and the field.
    let genus_edits: &[(&str, &str, &str)] = &[
        ("coverage = 0.5", "coverage = 2.0", "coverage"),
        (
            "density_scale = 0.2",
            "density_scale = 0.2\ndensity_profile = { a = 1e38, b = 80.0, c = 0.0, d = 0.0 }",
            "density_profile.a",
        ),
        (
            "density_scale = 0.2",
            "density_scale = 0.2\ndensity_profile = { a = 1.0, b = 200.0, c = 0.0, d = 0.0 }",
            "density_profile.b",
        ),
        ("height = 1500.0", "height = -3.0", "layers[0].height"),
        ("altitude = 1500.0", "altitude = nan", "layers[0].altitude"),
        (
            "density_scale = 0.2",
            "density_scale = 0.2\ncoverage_filter_width = 0.0",
            "coverage_filter_width",
        ),
        (
            "coverage = 0.5",
            "coverage = 0.5\nphase = { model = \"henyey-greenstein\", g = 1.5 }",
            "phase.g",
        ),
        ("channel = \"r\"", "channel = \"q\"", "layers[0].channel"),
        ("coverage = 0.5", "coverage = \"lots\"", "coverage"),
        ("coverage = 0.5", "coverage = 0.5\ncolour = 3", "colour"),
        ("name = \"mine\"", "name = \"other\"", "rename the file"),
        ("name = \"mine\"", "name = \"Mine\"", "name"),
    ];
    for (from, to, expect) in genus_edits {
        let text = GENUS.replace(from, to);
        assert_ne!(text, GENUS, "edit {from} → {to} applies");
        all.push(
            case(
                &format!("render -g genus with {to}"),
                &["render", "-g", "genera/mine.toml", "-o", "out.png"],
                &["mine.toml", expect],
            )
            .with_file("genera/mine.toml", text),
        );
    }
    all.push(
        case(
            "a capitalised genus file name says how to rename it",
            &["render", "-g", "genera/Sunny.toml", "-o", "out.png"],
            &["Sunny.toml", "rename the file to `sunny.toml`"],
        )
        .with_file("genera/Sunny.toml", GENUS.replace("\"mine\"", "\"sunny\"")),
    );

    // Scene files: structure and names.
    for (what, text, expect) in [
        (
            "weather_offset with three values",
            scene_with("weather_offset = [1.0, 2.0, 3.0]"),
            vec!["weather_offset", "expected 2 numbers"],
        ),
        (
            "an unknown field",
            scene_with("sun_colour = 3"),
            vec!["scene.toml", "sun_colour"],
        ),
        (
            "a wrong type",
            scene_with("fov_deg = \"wide\""),
            vec!["scene.toml", "fov_deg"],
        ),
        (
            "a budget of no time",
            scene_with("[budget]\nframe_ms = 0.0\nvolume_ms = 20.0"),
            vec!["scene.toml", "budget.frame_ms", "0"],
        ),
        (
            "a budget missing the volume's time",
            scene_with("[budget]\nframe_ms = 4.0"),
            vec!["scene.toml", "volume_ms"],
        ),
        (
            "an unknown genus",
            SCENE.replace("cumulus", "cumulonimbulus"),
            vec!["scene.toml", "cumulonimbulus"],
        ),
        (
            "a name that is not the file's",
            SCENE.replace("\"scene\"", "\"other\""),
            vec!["scene.toml", "set name = \"scene\""],
        ),
        (
            "a TOML syntax error",
            format!("{SCENE}fov_deg = = 3\n"),
            vec!["scene.toml", "line 5"],
        ),
    ] {
        all.push(
            case(
                &format!("explain: scene with {what}"),
                &["explain", "scenes/scene.toml"],
                &expect,
            )
            .with_file("scenes/scene.toml", text),
        );
    }
    all.push(
        case(
            "a capitalised scene file name says how to rename it",
            &["explain", "scenes/Sunset.toml"],
            &["Sunset.toml", "rename the file to `sunset.toml`"],
        )
        .with_file(
            "scenes/Sunset.toml",
            SCENE.replace("\"scene\"", "\"sunset\""),
        ),
    );
    all.push(case(
        "a scene file that does not exist",
        &["explain", "scenes/none.toml"],
        &["none.toml", "cannot read"],
    ));

    // Output paths: checked before any work, named, and never replaced unless Nimbus wrote
    // them (or --force).
    all.push(
        case(
            "render over a PNG Nimbus did not write",
            &["render", "-o", "photo.png"],
            &["photo.png", "not written by Nimbus", "--force"],
        )
        .with_file("photo.png", b"\x89PNG\r\n\x1a\nnot really".to_vec()),
    );
    all.push(
        case(
            "render -o a folder",
            &["render", "-o", "pictures"],
            &["pictures", "is a folder"],
        )
        .with_file("pictures/keep.txt", "mine"),
    );
    all.push(case(
        "render -o into a missing folder",
        &["render", "-o", "missing/out.png"],
        &["missing", "does not exist"],
    ));
    all.push(
        case(
            "emit -o a file",
            &["emit", "-g", "cumulus", "-q", "low", "-o", "notes.txt"],
            &["notes.txt", "is a file"],
        )
        .with_file("notes.txt", "mine"),
    );
    all.push(case(
        "emit -o . (a folder that cannot be replaced whole)",
        &["emit", "-g", "cumulus", "-q", "low", "-o", "."],
        &["needs a name of its own"],
    ));
    all.push(
        case(
            "emit -o a folder Nimbus did not write",
            &["emit", "-g", "cumulus", "-q", "low", "-o", "work"],
            &["work", "not written by Nimbus", "--force"],
        )
        .with_file("work/thesis.tex", "mine"),
    );
    all.push(
        case(
            "emit --engine -o a folder Nimbus did not write",
            &[
                "emit", "--engine", "wgpu", "-g", "cumulus", "-q", "low", "-o", "work",
            ],
            &["work", "not written by Nimbus"],
        )
        .with_file("work/thesis.tex", "mine"),
    );
    all.push(
        case(
            "export-density over an existing volume",
            &["export-density", "-o", "clouds.vol"],
            &["clouds.vol", "--force"],
        )
        .with_file("clouds.vol", "VOL mine"),
    );
    all.push(
        case(
            "tradeoff over a tradeoff.md of the user's",
            &["tradeoff", "-o", "study"],
            &["tradeoff.md", "not written by Nimbus"],
        )
        .with_file("study/tradeoff.md", "# my notes\n"),
    );
    all.push(
        case(
            "tradeoff -o . over a tradeoff.md of the user's",
            &["tradeoff", "-o", "."],
            &["tradeoff.md", "not written by Nimbus"],
        )
        .with_file("tradeoff.md", "# my notes\n"),
    );
    all.push(
        case(
            "tradeoff -o a file",
            &["tradeoff", "-o", "notes.txt"],
            &["notes.txt", "is a file"],
        )
        .with_file("notes.txt", "mine"),
    );

    // Textures: read and checked before the GPU; the error names the flag and the file.
    all.push(case(
        "a weather texture that does not exist",
        &["render", "-o", "out.png", "--weather-texture", "none.png"],
        &["--weather-texture", "none.png"],
    ));
    all.push(
        case(
            "a weather texture that is not a PNG",
            &["render", "-o", "out.png", "--weather-texture", "w.png"],
            &["--weather-texture", "w.png"],
        )
        .with_file("w.png", "not an image"),
    );
    all.push(
        case(
            "a shape volume of the wrong size",
            &["render", "-o", "out.png", "--shape-texture", "s.raw"],
            &["--shape-texture", "s.raw", "1000 bytes"],
        )
        .with_file("s.raw", vec![0u8; 1000]),
    );
    all.push(
        case(
            "a detail volume of a non-power-of-two side",
            &["render", "-o", "out.png", "--detail-texture", "d.raw"],
            &["--detail-texture", "d.raw", "27 bytes"],
        )
        .with_file("d.raw", vec![0u8; 27]),
    );

    // Data folders: the flag or variable that chose a bad one is named.
    all.push(case(
        "--data that does not exist",
        &["--data", "nowhere", "list"],
        &["nowhere", "--data"],
    ));
    all.push(
        case(
            "NIMBUS_DATA that does not exist",
            &["list"],
            &["elsewhere", "$NIMBUS_DATA"],
        )
        .with_env("NIMBUS_DATA", "elsewhere"),
    );
    all.push(
        case(
            "--data without genera/",
            &["--data", "data", "list"],
            &["data", "--data", "no genera/"],
        )
        .with_file("data/readme.txt", "mine"),
    );
    all.push(
        case(
            "a genus of a data folder that failed to load is named with its error",
            &["--data", "data", "emit", "-g", "broken", "-o", "out"],
            &["broken.toml", "coverage"],
        )
        .with_file(
            "data/genera/broken.toml",
            GENUS
                .replace("\"mine\"", "\"broken\"")
                .replace("coverage = 0.5", "coverage = 9.0"),
        )
        .with_file("data/genera/mine.toml", GENUS),
    );
    all
}

#[test]
fn every_bad_input_is_named_refused_and_leaves_nothing_behind() {
    let cases = cases();
    assert!(cases.len() >= 80, "the catalogue has {} cases", cases.len());
    let mut failures = Vec::new();
    for c in &cases {
        let dir = tempfile::tempdir().expect("tempdir");
        std::fs::write(dir.path().join("precious.txt"), "the user's file").expect("write");
        for (rel, bytes) in &c.files {
            let p = dir.path().join(rel);
            std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
            std::fs::write(&p, bytes).expect("write case file");
        }
        let before = tree(dir.path());
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_nimbus"));
        cmd.args(&c.args).current_dir(dir.path());
        cmd.env_remove("NIMBUS_DATA");
        for (k, v) in &c.env {
            cmd.env(k, v);
        }
        let out = cmd.output().expect("run nimbus");
        let err = text(&out.stderr);
        let mut problems = Vec::new();
        if out.status.success() {
            problems.push("exited 0".to_string());
        }
        if err.contains("panicked") {
            problems.push("panicked".to_string());
        }
        for want in &c.expect {
            if !err.contains(want.as_str()) {
                problems.push(format!("stderr lacks `{want}`"));
            }
        }
        let after = tree(dir.path());
        if after != before {
            let added: Vec<&String> = after.keys().filter(|k| !before.contains_key(*k)).collect();
            let changed: Vec<&String> = before
                .iter()
                .filter(|(k, v)| after.get(*k) != Some(v))
                .map(|(k, _)| k)
                .collect();
            problems.push(format!(
                "folder changed: added {added:?}, changed or removed {changed:?}"
            ));
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{}: {}\n  nimbus {}\n  stderr: {}",
                c.name,
                problems.join("; "),
                c.args.join(" "),
                err.trim()
            ));
        }
    }
    println!("error catalogue: {} cases", cases.len());
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
