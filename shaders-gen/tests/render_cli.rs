//! `nimbus render` as a user runs it: a picture on success, and on bad input a clear error
//! naming what is wrong, no panic, and no PNG left behind.

mod common;

use std::path::Path;

use common::{examples, have_gpu, nimbus_env as nimbus, text};

fn scene() -> String {
    examples("scenes/default.toml")
}

/// Runs a render that must fail; returns stderr after checking nothing was written.
fn fails(args: &[&str], env: &[(&str, &str)]) -> String {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("clouds.png");
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().expect("utf8")]);
    let o = nimbus(&all, env);
    let err = text(&o.stderr);
    assert!(
        !o.status.success(),
        "must fail: {all:?}\n{}",
        text(&o.stdout)
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        std::fs::read_dir(tmp.path()).expect("dir").next().is_none(),
        "nothing may be written on error"
    );
    err
}

#[test]
fn render_writes_a_png_of_clouds_over_a_sky_and_names_the_adapter() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("clouds.png");
    let o = nimbus(
        &[
            "render",
            &scene(),
            "-r",
            "96x54",
            "-q",
            "low",
            "-o",
            out.to_str().expect("utf8"),
        ],
        &[],
    );
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}\n{stdout}", text(&o.stderr));
    assert!(stdout.contains("adapter: "), "{stdout}");
    assert!(stdout.contains("takram-default.low"), "{stdout}");
    let img = image::open(&out).expect("a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (96, 54));
    // Sky pixels are blue (b > r); cloud pixels are bright and grey (r ≈ b).
    let blue = img.pixels().filter(|p| p[2] > p[0] + 20).count();
    let white = img
        .pixels()
        .filter(|p| p[0] > 150 && p[0].abs_diff(p[2]) < 40)
        .count();
    println!("{blue} sky pixels, {white} cloud pixels of {}", 96 * 54);
    assert!(
        blue > 200 && white > 100,
        "{blue} sky, {white} cloud pixels"
    );
}

#[test]
fn no_adapter_says_what_to_install() {
    // No DX12 on Linux (and no Vulkan or GL allowed): no adapter at all.
    let err = fails(&[&scene()], &[("WGPU_BACKEND", "dx12")]);
    assert!(err.contains("mesa-vulkan-drivers"), "{err}");
}

#[test]
fn a_missing_scene_file_is_named() {
    let err = fails(&["/nonexistent/sky.toml"], &[]);
    assert!(err.contains("/nonexistent/sky.toml"), "{err}");
}

#[test]
fn a_malformed_scene_names_file_and_line() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let file = tmp.path().join("broken.toml");
    std::fs::write(&file, "name = \"broken\"\ngenus = [unclosed\n").expect("write");
    let err = fails(&[file.to_str().expect("utf8")], &[]);
    assert!(
        err.contains("broken.toml") && err.contains("line 2"),
        "{err}"
    );
}

#[test]
fn resolutions_outside_the_limits_are_refused_before_any_gpu_work() {
    for (r, side) in [("0x90", "0"), ("100000x90", "100000"), ("64x0", "0")] {
        let err = fails(&[&scene(), "-r", r], &[]);
        assert!(
            err.contains("--resolution") && err.contains(side) && err.contains("out of range"),
            "{err}"
        );
    }
    let err = fails(&[&scene(), "-r", "wide"], &[]);
    assert!(err.contains("WIDTHxHEIGHT"), "{err}");
}

#[test]
fn unreadable_textures_are_named_with_the_reason() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let garbage = tmp.path().join("weather.png");
    std::fs::write(&garbage, b"not a png at all").expect("write");
    let err = fails(
        &[
            &scene(),
            "--weather-texture",
            garbage.to_str().expect("utf8"),
        ],
        &[],
    );
    assert!(err.contains("weather.png"), "{err}");
    let err = fails(&[&scene(), "--weather-texture", "/nonexistent/w.png"], &[]);
    assert!(err.contains("/nonexistent/w.png"), "{err}");
    let odd = tmp.path().join("shape.raw");
    std::fs::write(&odd, vec![0u8; 1000]).expect("write");
    let err = fails(
        &[&scene(), "--shape-texture", odd.to_str().expect("utf8")],
        &[],
    );
    assert!(
        err.contains("shape.raw") && err.contains("1000 bytes"),
        "{err}"
    );
}

#[test]
fn bad_flags_are_refused_before_any_gpu_work() {
    let err = fails(&[&scene(), "--sun-elevation", "120"], &[]);
    assert!(err.contains("--sun-elevation"), "{err}");
    let err = fails(&[&scene(), "-q", "extreme"], &[]);
    assert!(err.contains("extreme") && err.contains("ultra"), "{err}");
    let err = fails(&[&scene(), "--disable", "fog"], &[]);
    assert!(err.contains("fog"), "{err}");
}

/// Renders the default scene at low quality looking up, with `weather` as the weather map, at
/// coverage 0.3: with the layers' filter width 0.6, a weather signal of 0 then makes no cloud
/// anywhere (the remap needs a shape factor above 1.33) and one of 1 makes cloud everywhere.
fn render_with_weather(dir: &Path, name: &str, texel: u8) -> image::RgbImage {
    let weather = dir.join(format!("{name}.png"));
    image::RgbaImage::from_pixel(8, 8, image::Rgba([texel; 4]))
        .save(&weather)
        .expect("write");
    let out = dir.join(format!("{name}-render.png"));
    let o = nimbus(
        &[
            "render",
            &scene(),
            "-r",
            "64x36",
            "-q",
            "low",
            "--pitch",
            "30",
            "--coverage",
            "0.3",
            "--weather-texture",
            weather.to_str().expect("utf8"),
            "-o",
            out.to_str().expect("utf8"),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    image::open(&out).expect("png").to_rgb8()
}

#[test]
fn a_user_texture_replaces_the_procedural_one() {
    if !have_gpu() {
        return;
    }
    // An empty weather map leaves clear blue sky; a full one an overcast, grey or dim one.
    let tmp = tempfile::tempdir().expect("tempdir");
    let clear_blue = |img: &image::RgbImage| {
        img.pixels()
            .filter(|p| u16::from(p[2]) > u16::from(p[0]) + 50)
            .count()
    };
    let empty = clear_blue(&render_with_weather(tmp.path(), "empty", 0));
    let full = clear_blue(&render_with_weather(tmp.path(), "full", 255));
    println!(
        "clear-blue pixels: empty map {empty}, full map {full} of {}",
        64 * 36
    );
    assert!(
        empty > 64 * 36 / 2,
        "an empty weather map should leave blue sky: {empty}"
    );
    assert!(
        full < empty / 4,
        "a full weather map should cover the sky: {full} vs {empty}"
    );
}
