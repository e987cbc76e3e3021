//! `nimbus animate` and `nimbus render --time` as a user runs them: a scene's timeline as
//! numbered frames, a GIF and an index; the sun moving by the clock; a folder Nimbus did not
//! write left alone; bad times refused before anything is written.

mod common;

use common::{examples, have_gpu, nimbus, refuses_a_foreign_folder, text};

#[test]
fn animate_writes_the_timeline_as_frames_a_gif_and_an_index() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("anim");
    let scene = examples("scenes/day-with-wind.toml");
    let args = [
        "animate",
        scene.as_str(),
        "--from",
        "0",
        "--to",
        "14400",
        "--fps",
        "1",
        "--speed",
        "7200",
        "-r",
        "48x27",
        "-f",
        "1",
        "-o",
    ];
    let o = nimbus(&[&args[..], &[out.to_str().expect("utf8")]].concat());
    assert!(
        o.status.success(),
        "{}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    // 0, 7200 and 14400 s: three frames, the last a stratocumulus deck, the sun lower each time.
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("animation.json")).expect("index"))
            .expect("json");
    let frames = index["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), 3, "{index}");
    let elevations: Vec<f64> = frames
        .iter()
        .map(|f| f["sun_elevation_deg"].as_f64().expect("sun"))
        .collect();
    assert!(
        elevations.windows(2).all(|w| w[1] < w[0] - 5.0),
        "the sun does not go down: {elevations:?}"
    );
    assert_eq!(frames[2]["weather"][0]["genus"], "stratocumulus", "{index}");
    let mut pictures = Vec::new();
    for k in 0..3 {
        let img = image::open(out.join(format!("frame-{k:05}.png")))
            .expect("png")
            .to_rgb8();
        assert_eq!(img.dimensions(), (48, 27));
        pictures.push(img);
    }
    assert_ne!(
        pictures[0], pictures[1],
        "the timeline does not change the picture"
    );
    let gif = std::fs::read(out.join("animation.gif")).expect("gif");
    assert!(gif.starts_with(b"GIF89a"), "not a GIF");

    // A folder the user made is not replaced without --force, and is left as it was.
    refuses_a_foreign_folder(&args, tmp.path());
}

#[test]
fn bad_times_are_refused_naming_the_flag() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("anim");
    let scene = examples("scenes/day-with-wind.toml");
    let scene = scene.as_str();
    let cases: [(&[&str], &str); 4] = [
        (&["--from", "100", "--to", "50"], "--to"),
        (&["--to", "-5"], "--to"),
        (&["--to", "100", "--fps", "0"], "--fps"),
        (&["--to", "1e9", "--speed", "0.001"], "--to"),
    ];
    for (flags, named) in cases {
        let o = nimbus(
            &[
                &["animate", scene][..],
                flags,
                &["-o", out.to_str().expect("utf8")],
            ]
            .concat(),
        );
        let err = text(&o.stderr);
        assert!(!o.status.success(), "{flags:?} was accepted");
        assert!(err.contains(named), "{flags:?}: {err}");
        assert!(!out.exists(), "{flags:?}: something was written");
    }
    let png = tmp.path().join("t.png");
    let o = nimbus(&[
        "render",
        scene,
        "--time",
        "-1",
        "-o",
        png.to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(!o.status.success() && err.contains("--time"), "{err}");
    assert!(!png.exists());
}

/// Pixels (of 255 per channel) where two PNGs differ by more than 30 in some channel, as a
/// share of all.
fn changed_share(a: &std::path::Path, b: &std::path::Path) -> f64 {
    let a = image::open(a).expect("png").to_rgb8();
    let b = image::open(b).expect("png").to_rgb8();
    let changed = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 30))
        .count();
    changed as f64 / f64::from(a.width() * a.height())
}

#[test]
fn render_time_grows_clouds_where_the_scene_forms_them() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let scene = examples("scenes/clouds-forming.toml");
    // The same scene without its [formation] table: the control that the automaton gates.
    let text_of = std::fs::read_to_string(&scene).expect("scene");
    let plain = tmp.path().join("plain.toml");
    let cut = text_of.find("[formation]").expect("a [formation] table");
    std::fs::write(
        &plain,
        text_of[..cut].replace("name = \"clouds-forming\"", "name = \"plain\""),
    )
    .expect("write");
    let render = |scene: &str, time: &str, name: &str| {
        let out = tmp.path().join(name);
        let o = nimbus(&[
            "render",
            scene,
            "--time",
            time,
            "-r",
            "96x54",
            "-f",
            "1",
            "-o",
            out.to_str().expect("utf8"),
        ]);
        assert!(
            o.status.success(),
            "{}\n{}",
            text(&o.stdout),
            text(&o.stderr)
        );
        (out, text(&o.stdout))
    };
    let (clear, said) = render(&scene, "0", "t0.png");
    assert!(said.contains("formation: step 0"), "{said}");
    let (formed, said) = render(&scene, "1500", "t1500.png");
    assert!(said.contains("formation: step 75"), "{said}");
    let (ungated, _) = render(plain.to_str().expect("utf8"), "0", "plain.png");
    let (grown, gated) = (
        changed_share(&clear, &formed),
        changed_share(&clear, &ungated),
    );
    println!(
        "pixels changed: second 0 → 1500 {:.1} %; second 0 with and without formation {:.1} %",
        grown * 100.0,
        gated * 100.0
    );
    assert!(grown > 0.01, "no cloud formed by second 1500: {grown}");
    assert!(
        gated > 0.01,
        "the automaton did not gate the weather: {gated}"
    );
    // The automaton gates the procedural weather: a user's weather texture is refused with it.
    let weather = tmp.path().join("w.png");
    image::RgbaImage::from_pixel(8, 8, image::Rgba([128, 128, 128, 255]))
        .save(&weather)
        .expect("png");
    let out = tmp.path().join("refused.png");
    let o = nimbus(&[
        "render",
        &scene,
        "--weather-texture",
        weather.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--weather-texture") && err.contains("[formation]"),
        "{err}"
    );
    assert!(!out.exists(), "a refused render wrote {}", out.display());
}
