//! One test per failure found by trying Nimbus as a careless and a hostile user would (issue
//! 14), named after it. The broad sweep is `error_catalogue.rs`; the kills are
//! `interrupted_writes.rs`; the rendering edges are `tests/value_edges.rs`.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{examples, have_gpu, text};

/// Runs nimbus in `dir` without NIMBUS_DATA (and with `env`).
fn run_in(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_nimbus"));
    c.args(args).current_dir(dir).env_remove("NIMBUS_DATA");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run nimbus")
}

fn refused(o: &Output, wants: &[&str]) -> String {
    let err = text(&o.stderr);
    assert!(!o.status.success(), "must fail; stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for w in wants {
        assert!(err.contains(w), "stderr lacks `{w}`: {err}");
    }
    err
}

const SCENE: &str =
    "name = \"scene\"\ndescription = \"x\"\ngenus = \"cumulus\"\nquality = \"low\"\n";

fn write(dir: &Path, rel: &str, text: &str) {
    let p = dir.join(rel);
    std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
    std::fs::write(p, text).expect("write");
}

#[test]
fn render_with_exposure_zero_nan_inf_or_huge_keeps_the_users_file() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let photo = b"\x89PNG\r\n\x1a\nthe user's picture".to_vec();
    std::fs::write(tmp.path().join("out.png"), &photo).expect("write");
    for exposure in ["0", "nan", "inf", "1e30", "-inf"] {
        let o = run_in(
            tmp.path(),
            &["render", "-o", "out.png", "--exposure", exposure],
            &[],
        );
        refused(&o, &["--exposure"]);
        assert_eq!(
            std::fs::read(tmp.path().join("out.png")).expect("read"),
            photo
        );
    }
    // A valid exposure still does not overwrite a PNG Nimbus did not write.
    let o = run_in(tmp.path(), &["render", "-o", "out.png"], &[]);
    refused(&o, &["out.png", "not written by Nimbus", "--force"]);
    assert_eq!(
        std::fs::read(tmp.path().join("out.png")).expect("read"),
        photo
    );
}

#[test]
fn tradeoff_never_overwrites_a_users_tradeoff_md() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(tmp.path(), "study/tradeoff.md", "# my notes\n");
    write(tmp.path(), "tradeoff.md", "# my other notes\n");
    for out in ["study", "."] {
        let o = run_in(tmp.path(), &["tradeoff", "-o", out], &[]);
        refused(&o, &["tradeoff.md", "not written by Nimbus", "--force"]);
    }
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("study/tradeoff.md")).expect("read"),
        "# my notes\n"
    );
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("tradeoff.md")).expect("read"),
        "# my other notes\n"
    );
}

#[test]
fn scene_file_values_are_blamed_on_the_file_and_field_not_a_flag() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(
        tmp.path(),
        "scenes/scene.toml",
        &format!("{SCENE}fov_deg = 179.5\n"),
    );
    let o = run_in(
        tmp.path(),
        &["render", "scenes/scene.toml", "-o", "x.png"],
        &[],
    );
    let err = refused(&o, &["scenes/scene.toml: fov_deg", "179.5", "1° to 179°"]);
    assert!(!err.contains("--fov"), "{err}");
    write(
        tmp.path(),
        "scenes/scene.toml",
        &format!("{SCENE}camera_altitude = -20.0\n"),
    );
    let o = run_in(
        tmp.path(),
        &["render", "scenes/scene.toml", "-o", "x.png"],
        &[],
    );
    let err = refused(&o, &["scenes/scene.toml: camera_altitude", "-20"]);
    assert!(!err.contains("--camera-altitude"), "{err}");
    // The flag that overrides it is blamed as the flag.
    let o = run_in(
        tmp.path(),
        &["render", "-o", "x.png", "--camera-altitude", "-3"],
        &[],
    );
    refused(&o, &["--camera-altitude", "-3"]);
}

#[test]
fn explain_emit_and_export_density_refuse_what_render_refuses() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for line in [
        "fov_deg = 0.5",
        "fov_deg = 179.9",
        "camera_altitude = 1500000.0",
    ] {
        write(tmp.path(), "scenes/scene.toml", &format!("{SCENE}{line}\n"));
        let field = line.split(' ').next().expect("field");
        for args in [
            vec!["render", "scenes/scene.toml", "-o", "x.png"],
            vec!["explain", "scenes/scene.toml"],
            vec!["emit", "--scene", "scenes/scene.toml", "-o", "out"],
            vec!["export-density", "scenes/scene.toml", "-o", "x.vol"],
        ] {
            let o = run_in(tmp.path(), &args, &[]);
            refused(&o, &[&format!("scene.toml: {field}")]);
        }
    }
}

#[test]
fn a_zero_resolution_and_a_zero_frame_study_are_the_users_mistakes() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run_in(tmp.path(), &["render", "-o", "x.png", "-r", "0x0"], &[]);
    let err = refused(&o, &["--resolution", "0"]);
    assert!(!err.contains("adapter"), "{err}");
    let o = run_in(tmp.path(), &["tradeoff", "-o", "study", "-f", "0"], &[]);
    let err = refused(&o, &["--frames", "0"]);
    assert!(!err.contains("adapter"), "{err}");
    assert!(!tmp.path().join("study").exists(), "nothing created");
}

#[test]
fn yaw_nan_is_refused_before_rendering() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run_in(tmp.path(), &["render", "-o", "x.png", "--yaw", "nan"], &[]);
    let err = refused(&o, &["--yaw", "NaN"]);
    assert!(!err.contains("pixel"), "refused before any pixel: {err}");
    assert!(!text(&o.stdout).contains("adapter"), "no GPU was opened");
}

#[test]
fn an_output_path_that_is_a_file_or_a_folder_is_named_before_any_work() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(tmp.path(), "notes.txt", "mine");
    let o = run_in(
        tmp.path(),
        &["emit", "-g", "cumulus", "-o", "notes.txt"],
        &[],
    );
    refused(&o, &["notes.txt", "is a file"]);
    std::fs::create_dir(tmp.path().join("pictures")).expect("mkdir");
    let o = run_in(tmp.path(), &["render", "-o", "pictures"], &[]);
    let err = refused(&o, &["pictures", "is a folder"]);
    assert!(!err.contains("does not exist"), "{err}");
    assert!(!text(&o.stdout).contains("adapter"), "no GPU was opened");
}

#[test]
fn the_sun_far_below_the_horizon_renders_a_night_sky() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    for sun in ["-10", "-35", "-90"] {
        let o = run_in(
            tmp.path(),
            &[
                "render",
                "-o",
                "night.png",
                "-r",
                "64x36",
                "-q",
                "low",
                "-f",
                "1",
                "--sun-elevation",
                sun,
            ],
            &[],
        );
        assert!(o.status.success(), "sun {sun}°: {}", text(&o.stderr));
        let img = image::open(tmp.path().join("night.png"))
            .expect("png")
            .to_rgba8();
        let mean: f64 = img
            .pixels()
            .map(|p| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]))
            .sum::<f64>()
            / (3.0 * f64::from(img.width() * img.height()));
        assert!(mean < 40.0, "sun {sun}°: a dark image (mean {mean:.1}/255)");
    }
}

#[test]
fn fov_179_keeps_the_sky_above_the_ground() {
    // The edge rows against narrow cameras: tests/value_edges.rs. Here, as the user saw it: the
    // default scene (camera 10° up) at 179°, the top rows sky and the bottom rows ground.
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run_in(
        tmp.path(),
        &[
            "render", "-o", "wide.png", "-r", "64x36", "-q", "low", "-f", "1", "--fov", "179",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let img = image::open(tmp.path().join("wide.png"))
        .expect("png")
        .to_rgba8();
    let blue = |y: u32| {
        (0..img.width())
            .map(|x| {
                let p = img.get_pixel(x, y);
                f64::from(p[2]) - f64::from(p[0])
            })
            .sum::<f64>()
            / f64::from(img.width())
    };
    let (top, bottom) = (blue(0), blue(img.height() - 1));
    assert!(
        top > 5.0 && bottom < 0.0,
        "sky (blue) on top: {top:.1}, ground below: {bottom:.1}"
    );
    // Past the widest a pinhole camera can see, the flag is refused with the reason.
    let o = run_in(
        tmp.path(),
        &["render", "-o", "x.png", "--fov", "179.5"],
        &[],
    );
    refused(&o, &["--fov", "179.5", "179°", "fisheye"]);
}

#[test]
fn tradeoff_with_zero_frames_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for flag in ["-f", "--reference-frames", "-n"] {
        let o = run_in(tmp.path(), &["tradeoff", "-o", "study", flag, "0"], &[]);
        refused(&o, &["0", "out of range"]);
    }
}

#[test]
fn weather_offset_with_three_values_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(
        tmp.path(),
        "scenes/scene.toml",
        &format!("{SCENE}weather_offset = [1.0, 2.0, 3.0]\n"),
    );
    let o = run_in(tmp.path(), &["explain", "scenes/scene.toml"], &[]);
    refused(
        &o,
        &[
            "scene.toml",
            "weather_offset",
            "expected 2 numbers",
            "got 3",
        ],
    );
}

#[test]
fn a_density_profile_that_overflows_f32_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let genus = std::fs::read_to_string(examples("genera/cumulus.toml"))
        .expect("cumulus")
        .replace(
            "density_profile = { a = 0.0, b = 0.0, c = 0.75, d = 0.25 }",
            "density_profile = { a = 1e38, b = 80.0, c = 0.75, d = 0.25 }",
        );
    write(tmp.path(), "genera/cumulus.toml", &genus);
    let o = run_in(
        tmp.path(),
        &["render", "-g", "genera/cumulus.toml", "-o", "x.png"],
        &[],
    );
    refused(&o, &["cumulus.toml", "density_profile.a", "1e38"]);
}

#[test]
fn a_capitalised_file_name_says_to_rename_the_file() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(
        tmp.path(),
        "scenes/Sunset.toml",
        &SCENE.replace("\"scene\"", "\"sunset\""),
    );
    let o = run_in(tmp.path(), &["explain", "scenes/Sunset.toml"], &[]);
    refused(&o, &["Sunset.toml", "rename the file to `sunset.toml`"]);
}

#[test]
fn one_bad_genus_file_does_not_block_the_others() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let data = tmp.path().join("data");
    for g in ["cumulus", "stratus"] {
        write(
            &data,
            &format!("genera/{g}.toml"),
            &std::fs::read_to_string(examples(&format!("genera/{g}.toml"))).expect("genus"),
        );
    }
    write(
        &data,
        "genera/broken.toml",
        "name = \"broken\"\ncoverage = ",
    );
    let d = data.to_str().expect("utf8");
    let o = run_in(tmp.path(), &["--data", d, "list"], &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("broken.toml"),
        "the bad file is reported"
    );
    assert!(text(&o.stdout).contains("stratus"), "the others are listed");
    let o = run_in(
        tmp.path(),
        &[
            "--data", d, "emit", "-g", "stratus", "-q", "low", "-o", "out",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = run_in(
        tmp.path(),
        &["--data", d, "emit", "-g", "broken", "-o", "out2"],
        &[],
    );
    refused(&o, &["broken.toml", "line 2"]);
}

#[test]
fn a_bad_data_folder_is_blamed_on_the_flag_or_variable_that_chose_it() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run_in(tmp.path(), &["--data", "nowhere", "list"], &[]);
    refused(&o, &["nowhere", "--data"]);
    let o = run_in(tmp.path(), &["list"], &[("NIMBUS_DATA", "nowhere")]);
    refused(&o, &["nowhere", "$NIMBUS_DATA"]);
}

#[test]
fn an_installed_binary_finds_its_built_in_examples() {
    // A fresh user: no source tree to look at, no data folder named, an empty home.
    let home = tempfile::tempdir().expect("tempdir");
    let h = home.path().to_str().expect("utf8");
    let env = [("HOME", h), ("XDG_DATA_HOME", "")];
    let o = run_in(home.path(), &["list"], &env);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.contains("the examples built into nimbus"), "{out}");
    assert!(
        out.contains(
            &home
                .path()
                .join(".local/share/nimbus")
                .display()
                .to_string()
        )
    );
    for g in ["cumulus", "stratocumulus", "takram-default"] {
        assert!(out.contains(g), "{g} listed");
    }
    let o = run_in(home.path(), &["explain", "--help"], &env);
    assert!(o.status.success());
    // A second run reuses the written copy.
    let o = run_in(home.path(), &["list"], &env);
    assert!(o.status.success(), "{}", text(&o.stderr));
}
