//! Per-genus checks on the gallery's views, as a person would judge them, each with a control
//! that a real regression fails: an overcast stratus base is grey and about as bright as the
//! clear sky it hides (the octaves without the diffusion make it a dark blue-grey, failing
//! both);
//! cirrostratus shows the 22° halo around the sun (a plain Henyey–Greenstein veil does not);
//! altostratus shows the sun as a bright patch, as through ground glass (a nimbostratus in its
//! place hides it); cirrocumulus is made of grains under 1° and altocumulus of cells of 1° to
//! 5° (the WMO's line between them), where cirrocumulus drawn with the coarser cells of
//! stratocumulus, or altocumulus lowered to stratocumulus' height, fail; nimbostratus is grey,
//! brighter than the ground it lights (with the clouds' default dual lobe its base was darker
//! than its ground), darker than stratus (a tenth of its depth is not), with rain under it
//! that darkens the distance (a drizzle a tenth as dense does not).
//!
//! The renders are the gallery scenes' own (`examples/gallery/`), small and in display space
//! (the PNG `nimbus render` writes), so the checks judge what a viewer sees.

mod common;

use std::path::{Path, PathBuf};

use common::{examples, have_gpu, nimbus, rgb, text};

const SIZE: (u32, u32) = (192, 108);

/// Renders `scene` (a gallery scene, or a file) with `extra` flags into `dir`.
fn render(dir: &Path, name: &str, scene: &str, extra: &[&str]) -> image::RgbImage {
    render_at(dir, name, scene, SIZE, extra)
}

/// [`render`] at `size` pixels.
fn render_at(
    dir: &Path,
    name: &str,
    scene: &str,
    size: (u32, u32),
    extra: &[&str],
) -> image::RgbImage {
    let out = dir.join(format!("{name}.png"));
    let res = format!("{}x{}", size.0, size.1);
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

/// The gallery scene of `genus`, as its file holds it.
fn gallery_scene(genus: &str) -> nimbus_clouds::ScenePreset {
    let text = std::fs::read_to_string(gallery(genus)).expect("scene");
    toml::from_str(&text).expect("a gallery scene")
}

/// The field of view of a gallery scene that faces the sun, and the sun's direction in its
/// camera space, read from the scene file itself.
fn sun_view(genus: &str) -> (f64, [f64; 3]) {
    let scene = gallery_scene(genus);
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

/// Size of the cell renders: a narrow view, so that grains under a degree span several pixels;
/// the sizes are measured in degrees, which the field of view does not change.
const CELL_VIEW: (u32, u32) = (256, 144);
const CELL_FOV: f64 = 24.0;

/// The dominant cell size of a view, in degrees: the power-weighted mean wavelength of the
/// luminance over the central square of the image (Hann-windowed, the mean removed), from two
/// cycles across the square up, so the sky's gradient does not count. A cell and the gap to the
/// next make one wavelength.
fn cell_size(img: &image::RgbImage, fov_deg: f64) -> f64 {
    let n = img.height() as usize;
    let x0 = (img.width() - img.height()) / 2;
    let hann = |i: usize| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / (n - 1) as f64).cos();
    let mut field = vec![0.0f64; n * n];
    for y in 0..n {
        for x in 0..n {
            field[y * n + x] = luminance(img.get_pixel(x0 + x as u32, y as u32));
        }
    }
    let mean = field.iter().sum::<f64>() / (n * n) as f64;
    for y in 0..n {
        for x in 0..n {
            field[y * n + x] = (field[y * n + x] - mean) * hann(x) * hann(y);
        }
    }
    // Separable discrete Fourier transform: rows, then columns (n is small).
    let twiddle: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let a = -std::f64::consts::TAU * k as f64 / n as f64;
            (a.cos(), a.sin())
        })
        .collect();
    let mut rows = vec![(0.0f64, 0.0f64); n * n];
    for y in 0..n {
        for k in 0..n {
            let mut acc = (0.0, 0.0);
            for x in 0..n {
                let (c, s) = twiddle[(k * x) % n];
                acc.0 += field[y * n + x] * c;
                acc.1 += field[y * n + x] * s;
            }
            rows[y * n + k] = acc;
        }
    }
    let mut power_by_k = vec![0.0f64; n / 2];
    for kx in 0..n {
        for ky in 0..n {
            let mut acc = (0.0, 0.0);
            for y in 0..n {
                let (c, s) = twiddle[(ky * y) % n];
                let v = rows[y * n + kx];
                acc.0 += v.0 * c - v.1 * s;
                acc.1 += v.0 * s + v.1 * c;
            }
            let fx = if kx > n / 2 { n - kx } else { kx } as f64;
            let fy = if ky > n / 2 { n - ky } else { ky } as f64;
            let k = (fx * fx + fy * fy).sqrt().round() as usize;
            if k < n / 2 {
                power_by_k[k] += acc.0 * acc.0 + acc.1 * acc.1;
            }
        }
    }
    let (weighted, total) = power_by_k
        .iter()
        .enumerate()
        .skip(2)
        .fold((0.0, 0.0), |(w, t), (k, p)| (w + k as f64 * p, t + p));
    let mean_k = weighted / total.max(1e-30);
    let pixels_per_degree =
        0.5 * n as f64 / (0.5 * fov_deg.to_radians()).tan() * std::f64::consts::PI / 180.0;
    n as f64 / mean_k / pixels_per_degree
}

/// The cell size of the gallery view of `genus`, drawn from the data folder `data` (the
/// repository's examples when `None`).
fn gallery_cell_size(dir: &Path, name: &str, genus: &str, data: Option<&str>) -> f64 {
    let fov = CELL_FOV.to_string();
    let mut extra = vec!["--fov", fov.as_str()];
    if let Some(data) = data {
        extra.extend_from_slice(&["--data", data]);
    }
    let img = render_at(dir, name, &gallery(genus), CELL_VIEW, &extra);
    cell_size(&img, CELL_FOV)
}

#[test]
fn cirrocumulus_grains_are_under_a_degree_and_altocumulus_cells_one_to_five() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let grains = gallery_cell_size(tmp.path(), "cirrocumulus", "cirrocumulus", None);
    let cells = gallery_cell_size(tmp.path(), "altocumulus", "altocumulus", None);
    // Controls: cirrocumulus drawn with stratocumulus' cells, and altocumulus lowered to the
    // height of stratocumulus (its cells then look three or four times as large).
    let coarse = data_with(&tmp.path().join("coarse"), "cirrocumulus", |body| {
        body.replace("grain_weather", "cellular_weather")
    });
    let coarse = gallery_cell_size(
        tmp.path(),
        "coarse",
        "cirrocumulus",
        Some(coarse.to_str().expect("utf8")),
    );
    let low = data_with(&tmp.path().join("low"), "altocumulus", |body| {
        body.replace("altitude = 3000.0", "altitude = 800.0")
    });
    let low = gallery_cell_size(
        tmp.path(),
        "low",
        "altocumulus",
        Some(low.to_str().expect("utf8")),
    );
    println!(
        "cell size (degrees): cirrocumulus {grains:.2} (control, coarse cells: {coarse:.2}); \
         altocumulus {cells:.2} (control, at 800 m: {low:.2})"
    );
    assert!(grains < 1.0, "cirrocumulus grains of {grains:.2}°");
    assert!(
        (1.0..=5.0).contains(&cells),
        "altocumulus cells of {cells:.2}°"
    );
    assert!(coarse >= 1.0, "the control passes: {coarse:.2}°");
    assert!(!(1.0..=5.0).contains(&low), "the control passes: {low:.2}°");
}

/// Mean display luminance and saturation of the pixels whose elevation lies in `band` (degrees
/// above the horizon) in a view of field `fov` pitched `pitch` up.
fn band_look(img: &image::RgbImage, fov: f64, pitch: f64, band: (f64, f64)) -> (f64, f64) {
    let (s, c) = pitch.to_radians().sin_cos();
    let mut sum = [0.0f64; 3];
    let mut n = 0.0;
    for (x, y, p) in img.enumerate_pixels() {
        let d = ray(f64::from(x), f64::from(y), fov);
        let elevation = (d[1] * c + d[2] * s).clamp(-1.0, 1.0).asin().to_degrees();
        if (band.0..band.1).contains(&elevation) {
            for (k, v) in sum.iter_mut().enumerate() {
                *v += f64::from(p[k]) / 255.0;
            }
            n += 1.0;
        }
    }
    let m = sum.map(|v| v / f64::max(n, 1.0));
    let max = m.iter().copied().fold(0.0, f64::max);
    let min = m.iter().copied().fold(1.0, f64::min);
    (
        0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2],
        (max - min) / max.max(1e-6),
    )
}

/// The base of a deck seen from the ground: 20° to 45° above the horizon.
const BASE: (f64, f64) = (20.0, 45.0);
/// The ground under a deck, 5° to 20° below the horizon.
const GROUND: (f64, f64) = (-20.0, -5.0);
/// The distance under a deck: the first 4° above the horizon.
const DISTANCE: (f64, f64) = (0.0, 4.0);

#[test]
fn nimbostratus_is_dark_grey_with_rain_under_it() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let view = |genus: &str| {
        let scene = gallery_scene(genus);
        (f64::from(scene.fov_deg), f64::from(scene.camera_pitch_deg))
    };
    let (fov, pitch) = view("nimbostratus");
    let (st_fov, st_pitch) = view("stratus");
    let deck = render(tmp.path(), "nimbostratus", &gallery("nimbostratus"), &[]);
    let stratus = render(tmp.path(), "stratus", &gallery("stratus"), &[]);
    let (base, saturation) = band_look(&deck, fov, pitch, BASE);
    let (stratus_base, _) = band_look(&stratus, st_fov, st_pitch, BASE);
    let (distance, _) = band_look(&deck, fov, pitch, DISTANCE);
    // Controls: a tenth of the deck's depth; the deck without its rain.
    let thin = data_with(&tmp.path().join("thin"), "nimbostratus", |body| {
        body.replace("density_scale = 0.0375", "density_scale = 0.00375")
    });
    let thin = render(
        tmp.path(),
        "thin",
        &gallery("nimbostratus"),
        &["--data", thin.to_str().expect("utf8")],
    );
    let (thin_base, _) = band_look(&thin, fov, pitch, BASE);
    let dry = data_with(&tmp.path().join("dry"), "nimbostratus", |body| {
        body.split("\n# The rain under the base")
            .next()
            .unwrap_or(body)
            .to_string()
    });
    let dry = render(
        tmp.path(),
        "dry",
        &gallery("nimbostratus"),
        &["--data", dry.to_str().expect("utf8")],
    );
    let (dry_distance, _) = band_look(&dry, fov, pitch, DISTANCE);
    // A drizzle: the rain layer a tenth as dense.
    let drizzle = data_with(&tmp.path().join("drizzle"), "nimbostratus", |body| {
        body.replace("density_scale = 0.0012", "density_scale = 0.00012")
    });
    let drizzle = render(
        tmp.path(),
        "drizzle",
        &gallery("nimbostratus"),
        &["--data", drizzle.to_str().expect("utf8")],
    );
    let (drizzle_distance, _) = band_look(&drizzle, fov, pitch, DISTANCE);
    // The ground under the deck, lit by nothing but what comes through it; and the deck with
    // the clouds' default dual lobe, whose mean cosine 0.25 lets through a quarter of what
    // the droplets' 0.86 does (the ground's light always took the droplets').
    let (ground, _) = band_look(&deck, fov, pitch, GROUND);
    let dual = data_with(&tmp.path().join("dual"), "nimbostratus", |body| {
        body.lines()
            .filter(|l| !l.starts_with("phase = "))
            .collect::<Vec<_>>()
            .join("\n")
    });
    let dual = render(
        tmp.path(),
        "dual",
        &gallery("nimbostratus"),
        &["--data", dual.to_str().expect("utf8")],
    );
    let (dual_base, _) = band_look(&dual, fov, pitch, BASE);
    let (dual_ground, _) = band_look(&dual, fov, pitch, GROUND);
    println!(
        "nimbostratus base {base:.3} (saturation {saturation:.3}) over its ground {ground:.3}: \
         {:.2} (control, the default dual lobe: {:.2}); against the stratus base \
         {stratus_base:.3}: {:.2} (control, a tenth of the depth: {:.2}); the horizon through \
         the rain {:.2} of the dry deck's (control, a drizzle a tenth as dense: {:.2})",
        base / ground,
        dual_base / dual_ground,
        base / stratus_base,
        thin_base / stratus_base,
        distance / dry_distance,
        drizzle_distance / dry_distance
    );
    assert!(
        saturation < 0.2,
        "nimbostratus is not grey: {saturation:.3}"
    );
    // The base lights the ground under it (albedo 0.2): brighter than the ground, not the
    // near-black ceiling over a lighter ground it was.
    assert!(base > ground, "base {base:.3} under ground {ground:.3}");
    assert!(
        dual_base <= dual_ground,
        "the control passes: {dual_base:.3} over {dual_ground:.3}"
    );
    // Darker than stratus: 75 optical depths let through about half what stratus' 34 do
    // (two-stream, mean cosine 0.86: 0.113 against 0.219); the display's curve compresses that.
    assert!(base < 0.65 * stratus_base, "nimbostratus {base:.3}");
    assert!(
        thin_base >= 0.65 * stratus_base,
        "the control passes: {thin_base:.3}"
    );
    // Rain under the base: the distance, seen through kilometres of it, darker than without.
    // The line lies between the rain (0.71 of the dry deck's) and a drizzle a tenth as dense
    // (0.84): since the march ends a ray at a transmittance of 0.1 and takes its last tenth as
    // more of the same medium, a drizzle's long path to the horizon reads that much darker
    // (the line was 0.85 while rays went on to 0.01).
    assert!(
        distance < 0.8 * dry_distance,
        "no rain: {distance:.3} against {dry_distance:.3}"
    );
    assert!(
        drizzle_distance >= 0.8 * dry_distance,
        "the control passes: {drizzle_distance:.3} against {dry_distance:.3}"
    );
}
