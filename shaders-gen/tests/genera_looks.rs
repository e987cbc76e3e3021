//! Per-genus checks on the gallery's views, as a person would judge them, each with a control
//! that a real regression fails: an overcast stratus base is grey and about as bright as the
//! clear sky it hides (the octaves without the diffusion make it a dark blue-grey, failing
//! both);
//! cirrostratus shows the 22° halo around the sun (a plain Henyey–Greenstein veil does not);
//! altostratus shows the sun as a bright patch, as through ground glass (a nimbostratus in its
//! place hides it).
//!
//! The renders are the gallery scenes' own (`examples/gallery/`), small and in display space
//! (the PNG `nimbus render` writes), so the checks judge what a viewer sees.

mod common;

use std::path::{Path, PathBuf};

use common::{examples, have_gpu, nimbus, rgb, text};

const SIZE: (u32, u32) = (192, 108);

/// Renders `scene` (a gallery scene, or a file) with `extra` flags into `dir`.
fn render(dir: &Path, name: &str, scene: &str, extra: &[&str]) -> image::RgbImage {
    let out = dir.join(format!("{name}.png"));
    let res = format!("{}x{}", SIZE.0, SIZE.1);
    let mut args = vec![
        "render",
        scene,
        "-r",
        &res,
        "-f",
        "2",
        "-o",
        out.to_str().expect("utf8"),
    ];
    args.extend_from_slice(extra);
    let o = nimbus(&args);
    assert!(
        o.status.success(),
        "{name}: {}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    rgb(&out)
}

fn gallery(genus: &str) -> String {
    examples(&format!("gallery/{genus}.toml"))
}

/// Display luminance (Rec. 709 weights on the 8-bit values, 0..1).
fn luminance(p: &image::Rgb<u8>) -> f64 {
    (0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])) / 255.0
}

/// Mean colour (0..1) of the rows `rows` (fractions of the height, from the top).
fn mean_colour(img: &image::RgbImage, rows: (f64, f64)) -> [f64; 3] {
    let (y0, y1) = (
        (rows.0 * f64::from(img.height())) as u32,
        (rows.1 * f64::from(img.height())) as u32,
    );
    let mut sum = [0.0f64; 3];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in 0..img.width() {
            let p = img.get_pixel(x, y);
            for c in 0..3 {
                sum[c] += f64::from(p[c]) / 255.0;
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// What a viewer calls an overcast base: its colour's saturation `(max − min) / max` and its
/// luminance over the clear sky's in the same rows.
fn overcast(base: &image::RgbImage, clear: &image::RgbImage) -> (f64, f64) {
    // The sky above 10° or so: the top half of a 70° view pitched 12° up.
    let rows = (0.0, 0.45);
    let c = mean_colour(base, rows);
    let max = c.iter().copied().fold(0.0, f64::max);
    let min = c.iter().copied().fold(1.0, f64::min);
    let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    (
        (max - min) / max.max(1e-6),
        lum(c) / lum(mean_colour(clear, rows)),
    )
}

/// Grey (saturation under 0.2, where the clear sky is over 0.4) and at least half as bright
/// as the clear sky: a stratus base lit from within, not a blue-black ceiling.
fn is_overcast_grey((saturation, brightness): (f64, f64)) -> bool {
    saturation < 0.2 && brightness > 0.5
}

#[test]
fn a_stratus_base_is_grey_and_lit_from_within() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let scene = gallery("stratus");
    let base = render(tmp.path(), "stratus", &scene, &[]);
    let clear = render(tmp.path(), "clear", &scene, &["--coverage", "0"]);
    let look = overcast(&base, &clear);
    let clear_saturation = overcast(&clear, &clear).0;
    println!(
        "stratus: saturation {:.3} (clear sky {clear_saturation:.3}), brightness over the clear sky {:.2}",
        look.0, look.1
    );
    assert!(
        clear_saturation > 0.4,
        "the clear sky is not blue: {clear_saturation}"
    );
    assert!(is_overcast_grey(look), "stratus base {look:?}");
    // Control: the octaves alone (no diffusion) leave the deck's base dark and blue.
    let octaves = render(tmp.path(), "octaves", &scene, &["--disable", "diffusion"]);
    let control = overcast(&octaves, &clear);
    println!(
        "control (no diffusion): saturation {:.3}, brightness {:.2}",
        control.0, control.1
    );
    assert!(
        !is_overcast_grey(control),
        "the control passes: {control:?}"
    );
}

/// Pinhole direction of pixel (x, y) in camera space for a vertical field of view `fov`.
fn ray(x: f64, y: f64, fov_deg: f64) -> [f64; 3] {
    let f = 0.5 * f64::from(SIZE.1) / (0.5 * fov_deg.to_radians()).tan();
    let d = [
        x + 0.5 - 0.5 * f64::from(SIZE.0),
        0.5 * f64::from(SIZE.1) - (y + 0.5),
        f,
    ];
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    d.map(|v| v / n)
}

/// Mean display luminance in rings of 1° around `centre` (camera space), from 0° to 40°.
fn radial_profile(img: &image::RgbImage, centre: [f64; 3], fov_deg: f64) -> Vec<f64> {
    let mut sum = vec![0.0f64; 40];
    let mut n = vec![0.0f64; 40];
    for (x, y, p) in img.enumerate_pixels() {
        let d = ray(f64::from(x), f64::from(y), fov_deg);
        let cos = d[0] * centre[0] + d[1] * centre[1] + d[2] * centre[2];
        let deg = cos.clamp(-1.0, 1.0).acos().to_degrees();
        if deg < 40.0 {
            sum[deg as usize] += luminance(p);
            n[deg as usize] += 1.0;
        }
    }
    sum.iter().zip(&n).map(|(s, n)| s / n.max(1.0)).collect()
}

/// The sun's direction in camera space for a camera facing its azimuth, pitched `pitch` up.
fn sun_in_view(sun_elevation: f64, pitch: f64) -> [f64; 3] {
    let a = (sun_elevation - pitch).to_radians();
    [0.0, a.sin(), a.cos()]
}

/// The field of view of a gallery scene that faces the sun, and the sun's direction in its
/// camera space, read from the scene file itself.
fn sun_view(genus: &str) -> (f64, [f64; 3]) {
    let text = std::fs::read_to_string(gallery(genus)).expect("scene");
    let scene: nimbus_clouds::ScenePreset = toml::from_str(&text).expect("a gallery scene");
    assert_eq!(
        scene.camera_yaw_deg, scene.sun_azimuth_deg,
        "{genus}: the gallery view no longer faces the sun"
    );
    (
        f64::from(scene.fov_deg),
        sun_in_view(
            f64::from(scene.sun_elevation_deg),
            f64::from(scene.camera_pitch_deg),
        ),
    )
}

/// A halo: the ring where the radial profile rises most above the sky 3° inside and 4°
/// outside it lies at 22° ± 1°, by at least 0.02 (the light inside a halo, nearer the sun, is
/// brighter still: a ring, not the brightest part of the sky).
fn halo_at(profile: &[f64]) -> Option<usize> {
    let bump = |i: usize| profile[i] - 0.5 * (profile[i - 3] + profile[i + 4]);
    let peak = (15..=30).max_by(|a, b| bump(*a).total_cmp(&bump(*b)))?;
    ((21..=23).contains(&peak) && bump(peak) > 0.02).then_some(peak)
}

/// A data folder that is the repository's examples with the genus `name` rewritten by `edit`.
fn data_with(dir: &Path, name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let data = dir.join("data");
    for sub in ["genera", "scenes", "gallery"] {
        std::fs::create_dir_all(data.join(sub)).expect("data folder");
        for entry in std::fs::read_dir(examples(sub)).expect("examples") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "toml") {
                let body = std::fs::read_to_string(&path).expect("read");
                let file = path.file_name().expect("name");
                std::fs::write(data.join(sub).join(file), body).expect("write");
            }
        }
    }
    let genus = data.join("genera").join(format!("{name}.toml"));
    let body = std::fs::read_to_string(&genus).expect("genus");
    std::fs::write(&genus, edit(&body)).expect("write genus");
    data
}

#[test]
fn cirrostratus_shows_the_22_degree_halo() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let (fov, sun) = sun_view("cirrostratus");
    let veil = render(tmp.path(), "cirrostratus", &gallery("cirrostratus"), &[]);
    let profile = radial_profile(&veil, sun, fov);
    println!(
        "cirrostratus, luminance by degrees from the sun: {:?}",
        profile
            .iter()
            .map(|v| (v * 1000.0).round() / 1000.0)
            .collect::<Vec<_>>()
    );
    assert!(halo_at(&profile).is_some(), "no halo: {profile:?}");
    // Control: the same veil of plain Henyey–Greenstein droplets has no ring.
    let data = data_with(tmp.path(), "cirrostratus", |body| {
        body.replace(
            r#"phase = { model = "ice-crystal", g = 0.85, halo = 0.1 }"#,
            r#"phase = { model = "henyey-greenstein", g = 0.85 }"#,
        )
    });
    let data = data.to_str().expect("utf8");
    let plain = render(
        tmp.path(),
        "plain",
        &gallery("cirrostratus"),
        &["--data", data],
    );
    let control = radial_profile(&plain, sun, fov);
    assert!(
        halo_at(&control).is_none(),
        "the control shows a halo: {control:?}"
    );
    assert!(
        (profile[22] - control[22]).abs() > 0.01,
        "the control did not change the veil"
    );
}

/// Least contrast of the sun's patch: the sky within 2° of the sun a fifth brighter than the
/// sheet 8–15° from it.
const PATCH: f64 = 1.2;

/// The sun through a sheet: the luminance within 2° of it over the sheet's 8–15° from it.
fn sun_patch(img: &image::RgbImage, sun: [f64; 3], fov: f64) -> f64 {
    let p = radial_profile(img, sun, fov);
    let near = p[..2].iter().sum::<f64>() / 2.0;
    let far = p[8..15].iter().sum::<f64>() / 7.0;
    near / far.max(1e-6)
}

#[test]
fn altostratus_shows_the_sun_as_through_ground_glass() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let (fov, sun) = sun_view("altostratus");
    let sheet = render(tmp.path(), "altostratus", &gallery("altostratus"), &[]);
    let patch = sun_patch(&sheet, sun, fov);
    // Control: a nimbostratus (75 optical depths) in the same view hides the sun.
    let view = std::fs::read_to_string(gallery("altostratus"))
        .expect("scene")
        .replace(r#"genus = "altostratus""#, r#"genus = "nimbostratus""#);
    let hidden_dir = tmp.path().join("hidden");
    std::fs::create_dir_all(&hidden_dir).expect("folder");
    let scene = hidden_dir.join("altostratus.toml");
    std::fs::write(&scene, view).expect("write scene");
    let hidden = render(tmp.path(), "hidden", scene.to_str().expect("utf8"), &[]);
    let control = sun_patch(&hidden, sun, fov);
    println!(
        "altostratus: the sun's patch {patch:.2} times the sheet 8-15° from it; nimbostratus (control) {control:.2}"
    );
    assert!(patch > PATCH, "no patch: {patch:.2}");
    assert!(control < PATCH, "the control shows a patch: {control:.2}");
}
