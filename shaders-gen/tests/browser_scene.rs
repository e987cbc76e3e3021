//! Clouds in the user's own three.js scene, in a real browser: a grey tower 4 km tall and 8 km
//! away pierces the cumulus layer; three.js draws it into a render target with a depth texture
//! and the package (built with `--enable scene-depth`, at `medium`, sun 8° high at azimuth
//! 230°) draws the clouds over it, stopped by its depth. Each frame is compared with Nimbus's
//! own render of the same scene given the tower's depth (computed here, ray by ray), pixel
//! class by pixel class: the tower below the clouds, in them and above them, and the sky. With
//! a perspective depth buffer, three's logarithmic one, and a camera climbing through the layer.
//! The control: the same page with a package that cannot read depth draws the clouds over the
//! tower, and fails the comparison.
//!
//! Needs node, `browser/node_modules`, Chromium and a GPU adapter (lavapipe in CI).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::{Mat4, Vec3, Vec4};
use image::RgbImage;
use nimbus_clouds::model::scene_depth::SceneDepthParams;
use nimbus_clouds::model::tonemap::tonemap;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};
use nimbus_runtime::scene_depth::SceneDepth;
use nimbus_testkit::skip::browser_tools_present;

use common::{
    browser_dir, emit_package, have_gpu, mean_difference, missing_browser, nimbus, render_page,
    rgb, text,
};

const W: u32 = 160;
const H: u32 = 90;
const PITCH: f32 = 10.0;
const FOV: f32 = 60.0;
const SUN: (f32, f32) = (8.0, 230.0);
const COVERAGE: f32 = 0.6;
/// The tower's colour on the canvas (sRGB level of its grey, as three draws a
/// `MeshBasicMaterial` of that colour): the clouds' alpha must leave exactly that much of it.
const TOWER_GREY: u8 = 0x80;
/// The tower: centre x and z, side and height (m), as the page's `tower=` takes them.
const TOWER: [f32; 4] = [0.0, -8000.0, 1500.0, 4000.0];
const NEAR: f32 = 1.0;
/// The orthographic case's view: 4 km top to bottom (from 200 m to 4.2 km, level).
const ORTHO_EXTENT: f32 = 4000.0;
const FAR: f32 = 1e6;
/// A class of pixels must stay under this mean difference (of 255) from Nimbus's render.
const MAX_MEAN: f64 = 2.0;
/// The same inside the cloud layer, where SwiftShader's and lavapipe's arithmetic part over
/// whole regions of the march: without any scene, the plain package at 2,200 m against
/// `nimbus render` differs by 1.0/255 on average and by 3.4/255 in its worst 12 × 12 block.
const MAX_MEAN_IN_CLOUD: f64 = 3.5;
/// Frames accumulated on both sides, so that the march's noise is not what is compared.
const FRAMES: u32 = 4;

/// An orthographic view is drawn one frame at a time (the resolve reprojects rays from one
/// point); the others accumulate [`FRAMES`].
fn frames_for(orthographic: Option<f32>) -> u32 {
    if orthographic.is_some() { 1 } else { FRAMES }
}

/// What a pixel of the frame shows of the tower.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Sky,
    /// The tower where it stands below the cloud layer's base, in it, and above its top.
    TowerBelow,
    TowerInside,
    TowerAbove,
    /// A pixel beside a tower edge: rasterisation and a ray through its centre may disagree.
    Edge,
}

fn frame(altitude: f32, orthographic: Option<f32>, pitch: f32) -> Frame {
    let lib = CloudLibrary::load(Path::new(&common::examples(""))).expect("library");
    let mut genus = lib.genus("cumulus").expect("cumulus").clone();
    genus.coverage = COVERAGE;
    let mut f = Frame::new(genus, Quality::Medium, W, H);
    f.sun_elevation_deg = SUN.0;
    f.sun_azimuth_deg = SUN.1;
    f.camera_altitude = altitude;
    f.camera_pitch_deg = pitch;
    f.fov_deg = FOV;
    f.orthographic = orthographic;
    f
}

/// Distance along `dir` from `origin` to the tower's box, if the ray meets it.
fn hit_tower(origin: Vec3, dir: Vec3) -> Option<f32> {
    let [x, z, side, tall] = TOWER;
    let lo = Vec3::new(x - side / 2.0, 0.0, z - side / 2.0);
    let hi = Vec3::new(x + side / 2.0, tall, z + side / 2.0);
    let inv = dir.recip();
    let (a, b) = ((lo - origin) * inv, (hi - origin) * inv);
    let near = a.min(b).max_element();
    let far = a.max(b).min_element();
    (far >= near.max(0.0)).then_some(near.max(0.0))
}

/// The tower's depth buffer as three.js writes it for the page's camera (OpenGL perspective,
/// near 1 m, far 1,000 km), and each pixel's class.
fn tower_depth(f: &Frame) -> (SceneDepth, Vec<Class>) {
    let (forward, up) = f.camera_basis();
    let right = forward.cross(up);
    let aspect = W as f32 / H as f32;
    let half = (FOV.to_radians() * 0.5).tan();
    let camera = Vec3::new(0.0, f.camera_altitude, 0.0);
    let projection = match f.orthographic {
        Some(h) => {
            let (x, y) = (0.5 * h * aspect, 0.5 * h);
            Mat4::orthographic_rh_gl(-x, x, -y, y, NEAR, FAR)
        }
        None => Mat4::perspective_rh_gl(FOV.to_radians(), aspect, NEAR, FAR),
    };
    let (base, top) = (1500.0, 3000.0);
    let mut texels = Vec::new();
    let mut hits = Vec::new();
    for y in 0..H {
        for x in 0..W {
            let nx = (x as f32 + 0.5) / W as f32 * 2.0 - 1.0;
            let ny = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
            // A perspective ray leaves the camera; an orthographic one its point of the plane.
            let (origin, dir) = match f.orthographic {
                Some(h) => (
                    camera + right * (nx * 0.5 * h * aspect) + up * (ny * 0.5 * h),
                    forward,
                ),
                None => (
                    camera,
                    (forward + right * (nx * half * aspect) + up * (ny * half)).normalize(),
                ),
            };
            match hit_tower(origin, dir) {
                Some(t) => {
                    let z = t * dir.dot(forward);
                    let clip = projection * Vec4::new(0.0, 0.0, -z, 1.0);
                    texels.push(clip.z / clip.w * 0.5 + 0.5);
                    let h = origin.y + dir.y * t;
                    hits.push(Some(h));
                }
                None => {
                    texels.push(1.0);
                    hits.push(None);
                }
            }
        }
    }
    let at = |x: i32, y: i32| -> Option<Option<f32>> {
        (x >= 0 && y >= 0 && x < W as i32 && y < H as i32)
            .then(|| hits[(y as u32 * W + x as u32) as usize])
    };
    let mut classes = Vec::new();
    for y in 0..H as i32 {
        for x in 0..W as i32 {
            let me = at(x, y).flatten();
            let mixed = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| at(x + dx, y + dy).is_some_and(|n| n.is_some() != me.is_some()))
            });
            classes.push(match me {
                _ if mixed => Class::Edge,
                None => Class::Sky,
                Some(h) if h < base => Class::TowerBelow,
                Some(h) if h <= top => Class::TowerInside,
                Some(_) => Class::TowerAbove,
            });
        }
    }
    let params = SceneDepthParams::opengl(projection, Mat4::IDENTITY, Vec3::Z, W, H);
    (
        SceneDepth {
            width: W,
            height: H,
            texels,
            params,
        },
        classes,
    )
}

/// Nimbus's own render of the scene with the tower's depth, as the display pass draws it over
/// the engine's picture: its tonemapped colour, plus what its alpha leaves of the tower (grey,
/// [`TOWER_GREY`] on the canvas) or of the cleared background (black).
fn reference(
    gpu: &Gpu,
    altitude: f32,
    orthographic: Option<f32>,
    pitch: f32,
) -> (RgbImage, Vec<Class>, Option<Vec<f32>>) {
    let mut f = frame(altitude, orthographic, pitch);
    let (depth, classes) = tower_depth(&f);
    let tower: Vec<bool> = depth.texels.iter().map(|&d| d < 1.0).collect();
    f.scene_depth = Some(depth);
    f.frames = frames_for(orthographic);
    let mut r = Renderer::new(gpu, TextureSizes::default());
    let img = r.render(&f).expect("renders");
    // The clouds' shadow on the tower (perspective keys with a shadow atlas).
    let shadow = r
        .scene_shadow()
        .expect("the scene shadow pass runs")
        .map(|m| m.pixels.iter().map(|p| p[0]).collect());
    let rgb = RgbImage::from_fn(W, H, |x, y| {
        let i = (y * W + x) as usize;
        let p = img.pixels[i];
        let shown = tonemap(Vec3::new(p[0], p[1], p[2]), 8.0);
        let behind = if tower[i] {
            f32::from(TOWER_GREY) / 255.0
        } else {
            0.0
        };
        let c = (shown + Vec3::splat(behind * (1.0 - p[3]))) * 255.0;
        image::Rgb([c.x, c.y, c.z].map(|v| v.round().clamp(0.0, 255.0) as u8))
    });
    (rgb, classes, shadow)
}

/// The scene as a scene file (for `nimbus emit --scene`).
fn scene_file(dir: &Path) -> PathBuf {
    let file = dir.join("tower-scene.toml");
    let toml = format!(
        "name = \"tower-scene\"\n\
         description = \"The browser scene test: cumulus around a tower.\"\n\
         genus = \"cumulus\"\n\
         quality = \"medium\"\n\
         coverage = {COVERAGE}\n\
         sun_elevation_deg = {}\n\
         sun_azimuth_deg = {}\n\
         camera_altitude = 2.0\n\
         camera_pitch_deg = {PITCH}\n",
        SUN.0, SUN.1
    );
    std::fs::write(&file, toml).expect("writes the scene");
    file
}

fn emit(dir: &Path, name: &str, toggles: &[&str]) -> PathBuf {
    emit_for("three", dir, name, toggles)
}

fn emit_for(engine: &str, dir: &Path, name: &str, toggles: &[&str]) -> PathBuf {
    let package = dir.join(name);
    let scene = scene_file(dir);
    let mut args = vec![
        "emit",
        "--engine",
        engine,
        "--scene",
        scene.to_str().expect("utf-8"),
        "-o",
        package.to_str().expect("utf-8"),
    ];
    for t in toggles {
        args.extend(["--enable", t]);
    }
    let o = nimbus(&args);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
    package
}

fn browser(package: &Path, png: &Path, extra: &[String]) -> RgbImage {
    browser_page("scene", package, png, extra)
}

/// The tower scene on `page`: `scene` (three.js) or `webgpu` (the WebGPU host module, the
/// page drawing the tower with WebGPU itself).
fn browser_page(page: &str, package: &Path, png: &Path, extra: &[String]) -> RgbImage {
    let mut args = vec![
        format!("page={page}"),
        format!("width={W}"),
        format!("height={H}"),
        format!("fov={FOV}"),
        format!("tower={},{},{},{}", TOWER[0], TOWER[1], TOWER[2], TOWER[3]),
        format!("color={TOWER_GREY:02x}{TOWER_GREY:02x}{TOWER_GREY:02x}"),
    ];
    args.extend(extra.iter().cloned());
    render_page(package, png, &args);
    rgb(png)
}

/// Mean difference (of 255) per pixel class, and the classes' pixel counts.
fn by_class(a: &RgbImage, b: &RgbImage, classes: &[Class]) -> Vec<(Class, usize, f64)> {
    let mut out = Vec::new();
    for class in [
        Class::Sky,
        Class::TowerBelow,
        Class::TowerInside,
        Class::TowerAbove,
    ] {
        let idx: Vec<usize> = (0..classes.len())
            .filter(|&i| classes[i] == class)
            .collect();
        let sum: u64 = idx
            .iter()
            .flat_map(|&i| {
                let (x, y) = (i as u32 % W, i as u32 / W);
                let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
                (0..3).map(move |c| u64::from(p[c].abs_diff(q[c])))
            })
            .sum();
        let mean = if idx.is_empty() {
            0.0
        } else {
            sum as f64 / (idx.len() * 3) as f64
        };
        out.push((class, idx.len(), mean));
    }
    out
}

#[test]
fn clouds_stand_in_a_three_js_scene_as_nimbus_draws_them() {
    if !browser_tools_present("the browser scene test", missing_browser()) || !have_gpu() {
        return;
    }
    let gpu = Gpu::new().expect("adapter");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-scene");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("screenshot folder");
    let with_depth = emit(&out, "package-depth", &["scene-depth"]);
    let orthographic = emit(
        &out,
        "package-orthographic",
        &["scene-depth", "orthographic"],
    );
    let sun = format!("sun={},{}", SUN.0, SUN.1);

    // (name, camera altitude, logarithmic depth, orthographic view's height, pitch): on the
    // ground, then climbing into and through the layer (base 1.5 km, top 3 km), and a level
    // orthographic camera at 2.2 km seeing 4 km top to bottom (the layer edge-on across the
    // tower).
    let cases = [
        ("perspective", 2.0, false, None, PITCH),
        ("logarithmic", 2.0, true, None, PITCH),
        ("climbing-2200m", 2200.0, false, None, PITCH),
        ("climbing-3600m", 3600.0, false, None, PITCH),
        ("orthographic", 2200.0, false, Some(ORTHO_EXTENT), 0.0),
    ];
    let mut references = Vec::new();
    let mut failures = Vec::new();
    for (name, altitude, log, ortho, pitch) in cases {
        let (want, classes, shadow) = reference(&gpu, altitude, ortho, pitch);
        want.save(out.join(format!("{name}-nimbus.png")))
            .expect("saves");
        let mut extra = vec![
            format!("frames={}", frames_for(ortho)),
            format!("pitch={pitch}"),
            format!("altitude={altitude}"),
            format!("log={}", u8::from(log)),
            sun.clone(),
        ];
        let package = match ortho {
            Some(h) => {
                extra.push(format!("ortho={h}"));
                &orthographic
            }
            None => &with_depth,
        };
        let got = browser(package, &out.join(format!("{name}-chromium.png")), &extra);
        let classes_seen = by_class(&want, &got, &classes);
        println!(
            "{name}: mean difference {:.2}/255; by class {classes_seen:?}",
            mean_difference(&want, &got)
        );
        let limit = if (1500.0..=3000.0).contains(&altitude) {
            MAX_MEAN_IN_CLOUD
        } else {
            MAX_MEAN
        };
        for (class, count, mean) in &classes_seen {
            if *count > 0 && *mean > limit {
                failures.push(format!(
                    "{name}: {class:?} ({count} pixels) differs by {mean:.2}/255 from Nimbus's render"
                ));
            }
        }
        references.push((want, classes, got, shadow));
    }
    assert!(
        failures.is_empty(),
        "{}; see {}",
        failures.join("; "),
        out.display()
    );
    // On the ground the tower shows below, inside and above the layer.
    let ground = by_class(&references[0].0, &references[0].2, &references[0].1);
    for (class, count, _) in &ground[1..] {
        assert!(*count >= 20, "{class:?}: only {count} pixels");
    }
    // Control 1: the clouds drawn over everything (a package that cannot read depth) hide the
    // tower where clouds are in front of it and also where they are behind it.
    let without = emit(&out, "package-no-depth", &[]);
    let erased = browser(
        &without,
        &out.join("no-depth-chromium.png"),
        &[
            format!("frames={FRAMES}"),
            format!("pitch={PITCH}"),
            "altitude=2".to_string(),
            "depth=0".to_string(),
            sun.clone(),
        ],
    );
    let control = by_class(&references[0].0, &erased, &references[0].1);
    println!("control (no scene depth): {control:?}");
    assert!(
        control[1..]
            .iter()
            .any(|(_, _, mean)| *mean > MAX_MEAN * 4.0),
        "the comparison cannot tell a tower from clouds drawn over it: {control:?}"
    );
    // The WebGPU host module draws the same scene: the page draws the tower with WebGPU into
    // its target and a depth32float buffer, and the package reads that depth.
    let webgpu = emit_for("webgpu", &out, "package-webgpu-depth", &["scene-depth"]);
    let ground_case = [
        format!("frames={FRAMES}"),
        format!("pitch={PITCH}"),
        "altitude=2".to_string(),
        sun.clone(),
    ];
    let mut with_shadow = ground_case.to_vec();
    with_shadow.push("shadow=1".to_string());
    let png = out.join("webgpu-chromium.png");
    let drawn = browser_page("webgpu", &webgpu, &png, &with_shadow);
    let by = by_class(&references[0].0, &drawn, &references[0].1);
    println!(
        "webgpu: mean difference {:.2}/255; by class {by:?}",
        mean_difference(&references[0].0, &drawn)
    );
    for (class, count, mean) in &by {
        assert!(
            *count == 0 || *mean <= MAX_MEAN,
            "webgpu: {class:?} ({count} pixels) differs by {mean:.2}/255"
        );
    }
    // And the clouds' shadow on the tower, from its own host's scene_shadow pass, against the
    // runtime's: over the tower's pixels (their edges left out); the control, no shadow at all.
    let log: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(format!("{}.log.json", png.display())).expect("the page's log"),
    )
    .expect("JSON");
    let mask: Vec<f32> = log["values"]["mask"]
        .as_array()
        .expect("the page published the shadow")
        .iter()
        .map(|v| v.as_f64().unwrap_or(f64::NAN) as f32)
        .collect();
    let expected = references[0]
        .3
        .as_ref()
        .expect("the runtime's scene shadow");
    let tower: Vec<usize> = (0..mask.len())
        .filter(|&i| {
            matches!(
                references[0].1[i],
                Class::TowerBelow | Class::TowerInside | Class::TowerAbove
            )
        })
        .collect();
    let mean = |of: &dyn Fn(usize) -> f32| -> f32 {
        tower.iter().map(|&i| (mask[i] - of(i)).abs()).sum::<f32>() / tower.len() as f32
    };
    let against_runtime = mean(&|i| expected[i]);
    let against_none = mean(&|_| 1.0);
    let shade: f32 = tower.iter().map(|&i| expected[i]).sum::<f32>() / tower.len() as f32;
    println!(
        "webgpu scene shadow over {} tower pixels (mean light {shade:.3}): against the runtime \
         {against_runtime:.4}; against no shadow {against_none:.3}",
        tower.len()
    );
    assert!(against_runtime < 0.02, "{against_runtime}");
    assert!(against_none > 0.05, "the control: {against_none}");
    // Its control: the same page with the depth left out draws over the tower.
    let webgpu_plain = emit_for("webgpu", &out, "package-webgpu", &[]);
    let mut no_depth = ground_case.to_vec();
    no_depth.push("depth=0".to_string());
    let erased = browser_page(
        "webgpu",
        &webgpu_plain,
        &out.join("webgpu-no-depth-chromium.png"),
        &no_depth,
    );
    let control = by_class(&references[0].0, &erased, &references[0].1);
    println!("webgpu control (no scene depth): {control:?}");
    assert!(
        control[1..]
            .iter()
            .any(|(_, _, mean)| *mean > MAX_MEAN * 4.0),
        "webgpu: the comparison cannot tell a tower from clouds drawn over it: {control:?}"
    );
    // Control 2: the climb changes the picture: the frame at 2,200 m is not the ground's.
    let moved = mean_difference(&references[0].0, &references[2].2);
    println!("control (ground vs 2,200 m): mean {moved:.2}/255");
    assert!(
        moved > MAX_MEAN * 4.0,
        "the altitude changes nothing: {moved:.2}"
    );
    println!("screenshots: {}", out.display());
}

/// The README's page (`tower.html`, shipped in three packages built with `--enable scene-depth`)
/// runs as a user opens it: three.js from its CDN (answered from node_modules), nothing logged,
/// frames drawn, and its tower standing out of the ground beside it where the clouds do not
/// hide it. The package's `example.html` runs on the same package (an empty scene's depth).
#[test]
fn the_readme_tower_page_runs_from_the_package() {
    if !browser_tools_present("the README tower page test", missing_browser()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-tower");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("screenshot folder");
    let package = out.join("package");
    emit_package("three", "cumulus", "medium", &["scene-depth"], &package);
    for page in ["tower", "example"] {
        let prefix = out.join(page);
        let o = Command::new("node")
            .current_dir(browser_dir())
            .arg("example.mjs")
            .arg(&package)
            .arg(&prefix)
            .arg(format!("{page}.html"))
            .output()
            .expect("runs node");
        assert!(
            o.status.success(),
            "{page}.html failed or logged: {}{}",
            text(&o.stdout),
            text(&o.stderr)
        );
        println!("{page}.html: {}", text(&o.stdout).trim());
    }
    let shot = rgb(&out.join("tower-2.png"));
    let (w, h) = shot.dimensions();
    // The tower's foot (below the clouds' base, 8 km north of a camera 300 m up, pitched 8.6°
    // up: the middle column just above the horizon), cool grey against the warm haze either
    // side of it: blue minus red.
    let coolness = |x0: u32, x1: u32| -> f64 {
        let (y0, y1) = (h * 58 / 100, h * 64 / 100);
        let mut sum = 0.0;
        for y in y0..y1 {
            for x in x0..x1 {
                let p = shot.get_pixel(x, y);
                sum += f64::from(p[2]) - f64::from(p[0]);
            }
        }
        sum / f64::from((x1 - x0) * (y1 - y0))
    };
    let tower = coolness(w / 2 - 6, w / 2 + 6);
    let beside = (coolness(w / 2 - 60, w / 2 - 40) + coolness(w / 2 + 40, w / 2 + 60)) / 2.0;
    println!(
        "blue minus red at the tower's foot {tower:.1}, beside it {beside:.1}; screenshots in {}",
        out.display()
    );
    assert!(
        tower - beside > 15.0,
        "no tower where the page stands it: {tower:.1} against {beside:.1}"
    );
}
