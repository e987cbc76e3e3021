//! The three.js engine package in a real browser: headless Chromium (Debian's, WebGL2 through
//! SwiftShader) driven by playwright-core renders the package with three.js from npm, and each
//! frame is compared with `nimbus render` of the same scene: two sun positions (a package per
//! scene), one camera move, and the sun moved at run time by the package's own JavaScript
//! (`setSun`, no Nimbus code); the shader logs must be empty. The baked paths too (`slices`,
//! `blob2d`, `impostor`, `mesh`): each path's bake drawn in the browser, and for the slices and
//! the 2D map drawn again when `setSun` moves the sun. A third test drives the wind, a
//! weather state and the clock through the package's `setWind`, `setWeather` and `setTime`
//! against `nimbus render --time`. The screenshots stay in a folder the test prints.
//!
//! Needs `node`, `browser/node_modules` (`npm ci` in browser/) and Chromium; without them the
//! test says what is missing and passes, except under NIMBUS_REQUIRE_BROWSER=1 (CI), where it
//! fails.

mod common;

use nimbus_testkit::skip::browser_tools_present;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{
    browser_dir, mean_difference, missing_browser as missing, nimbus, render_page, rgb, text,
};
use image_compare::rgb_hybrid_compare;

/// Frames a JavaScript host in rotation takes to redraw every cascade tile of `quality`'s
/// atlas after a move (`cascadeRotation`: each tile in bands, `tile_bands`), by the rule the
/// host's printed twin follows: the last of them draws the last band and shows the whole
/// redraw's atlas. The page's `settle` is one less (the published frame is the last).
fn rotation_frames(quality: nimbus_clouds::Quality) -> u32 {
    let s = quality.settings();
    s.shadow_cascade_count * nimbus_clouds::model::tile_bands::tile_bands(s.shadow_map_size)
}

/// Perceptual similarity (SSIM on luma, RMS on chroma; 1 = identical) a browser frame must
/// reach against Nimbus's own render of the scene, and the mean absolute difference (of 255) it
/// must stay under. One frame each (no accumulation), so the march's noise and SwiftShader's
/// arithmetic differ from lavapipe's at cloud edges: measured 0.46/255 mean here.
const MIN_SCORE: f64 = 0.95;
const MAX_MEAN: f64 = 2.0;
/// No row of a frame may differ from Nimbus's by more than this mean (of 255): a band of a few
/// rows (the distant ground lit in one and shadowed in the other, 24 levels over three rows)
/// hides in a whole frame's mean. The horizon row, where clouds meet the ground at grazing
/// angles, differs by up to 7.
const MAX_ROW_MEAN: f64 = 10.0;

struct View {
    name: &'static str,
    quality: &'static str,
    /// The scene's coverage (the genus' own, 0.35, shows the ground between cloud shadows).
    coverage: f32,
    sun_elevation: f32,
    sun_azimuth: f32,
    pitch: f32,
    yaw: f32,
    /// The path the scene draws its clouds by (`volume`, or a baked one).
    path: &'static str,
}

const VIEWS: [View; 12] = [
    View {
        name: "sun-high",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "volume",
    },
    View {
        name: "sun-low",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "volume",
    },
    // The first scene, seen after a camera move.
    View {
        name: "camera-moved",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 25.0,
        yaw: 60.0,
        path: "volume",
    },
    // `medium` (shape detail, the ground bounce) with a low sun over the ground between the
    // clouds' shadows: the distant ground's shadow-map lookups straddle cloudy and empty
    // texels.
    View {
        name: "sun-low-medium",
        quality: "medium",
        coverage: 0.35,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 12.0,
        yaw: 0.0,
        path: "volume",
    },
    // `ultra`: three shadow cascades of 1,024 texels, in a 2×2 grid of tiles (side by side
    // they were 3,072 wide, past WebGL2's 2,048); a low sun over a broken field reads the
    // shadows of every cascade, the third from the grid's second row.
    View {
        name: "sun-low-ultra",
        quality: "ultra",
        coverage: 0.35,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 12.0,
        yaw: 0.0,
        path: "volume",
    },
    // The slices path (its slice pass baked in the browser, the march reading the stack), and
    // its scene with the sun low, which the package's setSun must rebake the stack for.
    View {
        name: "slices",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "slices",
    },
    View {
        name: "slices-sun-low",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "slices",
    },
    // The 2D path (its map pass baked in the browser, the cloud pass reading the map alone),
    // and its scene with the sun low, for the host's rebake after setSun.
    View {
        name: "blob2d",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "blob2d",
    },
    View {
        name: "blob2d-sun-low",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "blob2d",
    },
    // The impostor path (its octahedral map baked in the browser by the volume's own march
    // per direction, the cloud pass reading its ray's texel), and its scene with the sun low
    // (`the_impostor_follows_a_moved_sun_through_rotating_cascades`).
    View {
        name: "impostor",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "impostor",
    },
    View {
        name: "impostor-sun-low",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 8.0,
        sun_azimuth: 230.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "impostor",
    },
    // The mesh path (its cluster table fitted in the browser, the cloud pass drawing the
    // puffs in closed form).
    View {
        name: "mesh",
        quality: "low",
        coverage: 0.6,
        sun_elevation: 35.0,
        sun_azimuth: 150.0,
        pitch: 10.0,
        yaw: 0.0,
        path: "mesh",
    },
];

fn scene(dir: &Path, v: &View) -> PathBuf {
    let file = dir.join(format!("browser-{}.toml", v.name));
    let toml = format!(
        "name = \"browser-{name}\"\n\
         description = \"The browser test's view {name}.\"\n\
         genus = \"cumulus\"\n\
         quality = \"{quality}\"\n\
         coverage = {coverage}\n\
         sun_elevation_deg = {el}\n\
         sun_azimuth_deg = {az}\n\
         camera_altitude = 2.0\n\
         camera_pitch_deg = {pitch}\n\
         camera_yaw_deg = {yaw}\n\
         [features]\n\
         path = \"{path}\"\n",
        name = v.name,
        path = v.path,
        quality = v.quality,
        coverage = v.coverage,
        el = v.sun_elevation,
        az = v.sun_azimuth,
        pitch = v.pitch,
        yaw = v.yaw,
    );
    std::fs::write(&file, toml).expect("write scene");
    file
}

/// The row whose mean difference (of 255) is largest, and that mean.
fn worst_row(a: &image::RgbImage, b: &image::RgbImage) -> (u32, f64) {
    (0..a.height())
        .map(|y| {
            let sum: u64 = (0..a.width())
                .flat_map(|x| {
                    let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
                    (0..3).map(move |c| u64::from(p[c].abs_diff(q[c])))
                })
                .sum();
            (y, sum as f64 / f64::from(a.width() * 3))
        })
        .fold((0, 0.0), |w, r| if r.1 > w.1 { r } else { w })
}

/// The page's query for a `w` × `h` frame seen as view `v` is (its camera, a 60° field).
fn view_args(w: u32, h: u32, v: &View) -> Vec<String> {
    vec![
        format!("width={w}"),
        format!("height={h}"),
        format!("pitch={}", v.pitch),
        format!("yaw={}", v.yaw),
        "fov=60".to_string(),
    ]
}

/// Renders `package` in Chromium (`render.mjs`, its query `args`) into `png` and returns the
/// frame; the test fails, with the page's log, when the page fails or logs anything.
fn browser_frame(package: &Path, png: &Path, args: &[String]) -> image::RgbImage {
    render_page(package, png, args);
    rgb(png)
}

/// Compares a browser's frame `got` with `nimbus render`'s `want`: prints the similarity, the
/// mean difference and the worst row's under `name`, and fails the test, pointing at the
/// screenshots in `out`, unless all three are within the bounds.
fn assert_same_frame(name: &str, want: &image::RgbImage, got: &image::RgbImage, out: &Path) {
    let score = rgb_hybrid_compare(want, got).expect("same size").score;
    let mean = mean_difference(want, got);
    let (row, row_mean) = worst_row(want, got);
    println!(
        "{name}: similarity {score:.4}, mean difference {mean:.2}/255, worst row {row} \
         {row_mean:.2}/255"
    );
    assert!(
        score >= MIN_SCORE && mean <= MAX_MEAN && row_mean <= MAX_ROW_MEAN,
        "{name}: the browser frame differs from nimbus render (similarity {score:.4} < \
         {MIN_SCORE}, mean {mean:.2} > {MAX_MEAN} or row {row} {row_mean:.2} > \
         {MAX_ROW_MEAN}); see {}",
        out.display()
    );
}

/// One browser frame: the package of scene `package`, seen as scene `view` is (its camera,
/// and its sun through `setSun` when `move_sun`), against `nimbus render` of scene `view`.
struct Case {
    name: &'static str,
    package: usize,
    view: usize,
    move_sun: bool,
    /// Frames drawn (accumulated at full resolution, or upscaled), as `render -f`.
    frames: u32,
    upscale: bool,
}

const CASES: [Case; 14] = [
    Case {
        name: "sun-high",
        package: 0,
        view: 0,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "sun-low",
        package: 1,
        view: 1,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "camera-moved",
        package: 0,
        view: 2,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    // The sun-high package, its sun moved to the sun-low scene's in the browser.
    Case {
        name: "sun-moved",
        package: 0,
        view: 1,
        move_sun: true,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "sun-low-medium",
        package: 3,
        view: 3,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "sun-low-ultra",
        package: 4,
        view: 4,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    // The temporal resolve pass: four accumulated frames, and sixteen upscaled ones.
    Case {
        name: "accumulated",
        package: 0,
        view: 0,
        move_sun: false,
        frames: 4,
        upscale: false,
    },
    Case {
        name: "upscaled",
        package: 0,
        view: 0,
        move_sun: false,
        frames: 16,
        upscale: true,
    },
    // The slices path, and its sun moved in the browser (the stack rebaked by the host).
    Case {
        name: "slices",
        package: 5,
        view: 5,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "slices-sun-moved",
        package: 5,
        view: 6,
        move_sun: true,
        frames: 1,
        upscale: false,
    },
    // The 2D path, and its sun moved in the browser (the map rebaked by the host).
    Case {
        name: "blob2d",
        package: 7,
        view: 7,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "blob2d-sun-moved",
        package: 7,
        view: 8,
        move_sun: true,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "impostor",
        package: 9,
        view: 9,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
    Case {
        name: "mesh",
        package: 11,
        view: 11,
        move_sun: false,
        frames: 1,
        upscale: false,
    },
];

#[test]
fn the_three_package_renders_in_chromium_what_nimbus_renders() {
    if !browser_tools_present("the browser test", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-test");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("screenshot folder");
    let (w, h) = (160u32, 90u32);
    let mut frames = Vec::new();
    for case in &CASES {
        let (pv, v) = (&VIEWS[case.package], &VIEWS[case.view]);
        let package = out.join(format!("package-{}", pv.name));
        if !package.exists() {
            let scene_file = scene(&out, pv);
            let o = nimbus(&[
                "emit",
                "--engine",
                "three",
                "--scene",
                scene_file.to_str().expect("utf8"),
                "-o",
                package.to_str().expect("utf8"),
            ]);
            assert!(o.status.success(), "emit: {}", text(&o.stderr));
        }
        let nimbus_png = out.join(format!(
            "{}-f{}{}-nimbus.png",
            v.name,
            case.frames,
            if case.upscale { "-upscaled" } else { "" }
        ));
        if !nimbus_png.exists() {
            let scene_file = scene(&out, v);
            let frames = case.frames.to_string();
            let size = format!("{w}x{h}");
            let mut args = vec![
                "render",
                scene_file.to_str().expect("utf8"),
                "-r",
                &size,
                "-f",
                &frames,
                "-o",
                nimbus_png.to_str().expect("utf8"),
            ];
            if case.upscale {
                args.push("--upscale");
            }
            let o = nimbus(&args);
            assert!(o.status.success(), "render: {}", text(&o.stderr));
        }
        let browser_png = out.join(format!("{}-chromium.png", case.name));
        let mut args = view_args(w, h, v);
        if case.move_sun {
            args.push(format!("sun={},{}", v.sun_elevation, v.sun_azimuth));
        }
        args.push(format!("frames={}", case.frames));
        if case.upscale {
            args.push("upscale=1".to_string());
        }
        let got = browser_frame(&package, &browser_png, &args);
        frames.push((case.name, rgb(&nimbus_png), got));
    }
    println!("screenshots: {}", out.display());
    for (name, want, got) in &frames {
        assert_same_frame(name, want, got, &out);
    }
    // Control: the metric tells the two sun positions apart, so a package that ignored its
    // uniforms, or drew the wrong scene, would fail.
    let score = rgb_hybrid_compare(&frames[0].1, &frames[1].2)
        .expect("same size")
        .score;
    let mean = mean_difference(&frames[0].1, &frames[1].2);
    println!("control (sun-high vs sun-low): similarity {score:.4}, mean {mean:.2}/255");
    assert!(
        score < MIN_SCORE || mean > MAX_MEAN,
        "the comparison cannot fail"
    );
}

/// The wind and weather of the timeline test's scene: a westerly strengthening and veering with
/// height, and the cumulus thinning from 0.6 to 0.4 by second 1800 (one genus: only uniforms
/// change), seen at second 900, halfway through the thinning (coverage 0.5, drift 10.8 km).
const WIND: [f32; 4] = [12.0, 250.0, 25.0, 280.0];
const THINNING: (f32, f64) = (0.4, 1800.0);
const TIME: f64 = 900.0;

/// The browser test's first view with `wind` (`[wind]`) and the thinning (`[[weather]]`) when
/// asked, as a scene file.
fn timeline_scene(dir: &Path, name: &str, wind: bool, weather: bool) -> PathBuf {
    let v = &VIEWS[0];
    let mut toml = std::fs::read_to_string(scene(dir, v)).expect("scene");
    toml = toml.replace(&format!("browser-{}", v.name), &format!("browser-{name}"));
    if wind {
        toml.push_str(&format!(
            "[wind]\nspeed = {}\ndirection_deg = {}\ntop_speed = {}\ntop_direction_deg = {}\n",
            WIND[0], WIND[1], WIND[2], WIND[3]
        ));
    }
    if weather {
        toml.push_str(&format!(
            "[[weather]]\nat = {}\ncoverage = {}\n",
            THINNING.1, THINNING.0
        ));
    }
    let file = dir.join(format!("browser-{name}.toml"));
    std::fs::write(&file, toml).expect("write scene");
    file
}

/// Clouds that change in the browser: the three.js package of the first view, given the wind
/// (`setWind`), a weather state (`setWeather`) and a time (`setTime`) by its own JavaScript,
/// draws what `nimbus render --time` draws of the scene with that `[wind]` and `[[weather]]`,
/// after a frame drawn at second 0 (so a shadow atlas left stale by the clock's move fails).
/// Controls: the same scene at second 0 (neither the drift nor the thinning applied), and at
/// the same time without its wind (the thinning alone) or without its weather state (the
/// drift alone), must each fail the comparison. The atlas is redrawn a band of a tile per frame
/// (`cascadeRotation`): once every band is redrawn the frame is the one a
/// whole redraw draws, and the frame right after the clock's move (a band drawn into the back
/// atlas, none copied yet) is not.
#[test]
fn the_three_package_drifts_and_changes_its_weather_as_nimbus_renders_it() {
    if !browser_tools_present("the browser timeline test", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-timeline");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("folder");
    let (w, h) = (160u32, 90u32);
    let v = &VIEWS[0];
    let timed = timeline_scene(&out, "timeline", true, true);
    let package = out.join("package");
    let o = nimbus(&[
        "emit",
        "--engine",
        "three",
        "--scene",
        timed.to_str().expect("utf8"),
        "-o",
        package.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
    let render = |scene: &Path, time: f64, png: &str| {
        let png = out.join(png);
        let (size, time) = (format!("{w}x{h}"), time.to_string());
        let o = nimbus(&[
            "render",
            scene.to_str().expect("utf8"),
            "--time",
            &time,
            "-r",
            &size,
            "-f",
            "1",
            "-o",
            png.to_str().expect("utf8"),
        ]);
        assert!(o.status.success(), "render: {}", text(&o.stderr));
        rgb(&png)
    };
    let want = render(&timed, TIME, "at-time-nimbus.png");
    let at_start = render(&timed, 0.0, "at-start-nimbus.png");
    let still = timeline_scene(&out, "still", false, true);
    let without_wind = render(&still, TIME, "without-wind-nimbus.png");
    let steady = timeline_scene(&out, "steady", true, false);
    let without_weather = render(&steady, TIME, "without-weather-nimbus.png");
    // The page: a frame at second 0 first (the clock's move must redraw the shadow atlas),
    // then the clock moved, `extra` frames drawn, and the next one published.
    let page = |png: &str, extra: &[&str]| {
        let mut args = view_args(w, h, v);
        args.extend([
            format!("wind={},{},{},{}", WIND[0], WIND[1], WIND[2], WIND[3]),
            format!("weather={},{}", THINNING.0, THINNING.1),
            format!("time={TIME}"),
            "first=1".to_string(),
        ]);
        args.extend(extra.iter().map(|s| s.to_string()));
        browser_frame(&package, &out.join(png), &args)
    };
    // The cascades redraw a band of a tile per frame: the frame compared draws the last.
    let browser_png = out.join("at-time-chromium.png");
    let settle = format!(
        "settle={}",
        rotation_frames(nimbus_clouds::Quality::Low) - 1
    );
    assert_eq!(v.quality, "low");
    let got = page("at-time-chromium.png", &[&settle]);
    // Cascades in rotation end where a whole redraw does; the frame right after the move,
    // its coarser tiles still those of second 0, does not (the control).
    let whole = page("at-time-whole-chromium.png", &["rotation=0"]);
    let first = page("at-time-first-frame-chromium.png", &[]);
    let (settled, unsettled) = (
        mean_difference(&whole, &got),
        mean_difference(&whole, &first),
    );
    println!(
        "cascades in rotation against a whole redraw: {settled:.3}/255 once every tile is \
         redrawn, {unsettled:.3}/255 the frame after the clock moved"
    );
    assert!(
        settled <= 0.1,
        "the rotation did not end at the whole atlas: {settled}"
    );
    assert!(
        unsettled > 0.3,
        "the control: one tile redrawn already looked whole ({unsettled})"
    );
    println!("screenshots: {}", browser_png.display());
    let compare = |a: &image::RgbImage, b: &image::RgbImage| {
        (
            rgb_hybrid_compare(a, b).expect("same size").score,
            mean_difference(a, b),
        )
    };
    let (score, mean) = compare(&want, &got);
    println!(
        "at {TIME} s: similarity {score:.4}, mean difference {mean:.2}/255 against nimbus render \
         --time {TIME}"
    );
    assert!(
        score >= MIN_SCORE && mean <= MAX_MEAN,
        "the browser frame differs from nimbus render --time {TIME} (similarity {score:.4} < \
         {MIN_SCORE} or mean {mean:.2} > {MAX_MEAN}); see {}",
        out.display()
    );
    for (name, control) in [
        ("second 0", &at_start),
        ("the same time without wind", &without_wind),
        ("the same time without the thinning", &without_weather),
    ] {
        let (score, mean) = compare(control, &got);
        println!("control ({name}): similarity {score:.4}, mean difference {mean:.2}/255");
        assert!(
            score < MIN_SCORE || mean > MAX_MEAN,
            "the comparison cannot tell {name} from the frame at {TIME} s"
        );
    }
}

/// The example page a three.js package ships (`example.html`, where the sun moves) runs in
/// Chromium from the package alone (three.js answered from node_modules in place of its CDN):
/// no message is logged, the clouds are drawn, and they change as the sun moves.
#[test]
fn the_three_package_example_page_runs_and_its_sun_moves() {
    if !browser_tools_present("the example-page test", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-example");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("folder");
    let package = out.join("package");
    let o = nimbus(&[
        "emit",
        "--engine",
        "three",
        "-g",
        "cumulus",
        "-q",
        "low",
        "-o",
        package.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
    let prefix = out.join("example");
    let o = Command::new("node")
        .current_dir(browser_dir())
        .arg("example.mjs")
        .arg(&package)
        .arg(&prefix)
        .output()
        .expect("run node");
    assert!(
        o.status.success(),
        "the example page failed or logged: {}{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    let shot = |i: u32| rgb(&out.join(format!("example-{i}.png")));
    let (a, b) = (shot(1), shot(2));
    // Below and right of the control panel: sky, clouds and ground only.
    let region = |img: &image::RgbImage| {
        image::imageops::crop_imm(
            img,
            img.width() / 2,
            img.height() / 2,
            img.width() / 2,
            img.height() / 2,
        )
        .to_image()
    };
    let (a, b) = (region(&a), region(&b));
    let brightest = a
        .pixels()
        .map(|p| p.0.iter().copied().max().unwrap_or(0))
        .max()
        .unwrap_or(0);
    let moved = mean_difference(&a, &b);
    println!(
        "{}; brightest {brightest}/255, change as the sun moved {moved:.2}/255; screenshots in {}",
        text(&o.stdout).trim(),
        out.display()
    );
    assert!(brightest > 100, "the example page drew nothing");
    assert!(moved > 0.2, "the clouds did not change as the sun moved");
}

/// The webgpu package drawn by its own host module (`nimbus-webgpu.js`: pipelines from the
/// package's WGSL, entry points and bind-group layouts as the API takes them) on Chromium's
/// WebGPU (SwiftShader's Vulkan): one frame and sixteen upscaled ones against `nimbus render`
/// of the same scene, and the one frame against the three.js package's frame in the same
/// browser. The control: the low-sun scene's render against this frame. Its cascades in
/// rotation end, band by band, at the frame a whole redraw of the atlas gives.
#[test]
fn the_webgpu_package_draws_with_its_host_module_what_nimbus_renders() {
    if !browser_tools_present("the WebGPU browser test", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-webgpu");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("screenshot folder");
    let (w, h) = (160u32, 90u32);
    let v = &VIEWS[0];
    let scene_file = scene(&out, v);
    // A baked path (the 2D map) from the same camera, for the same host.
    let baked = &VIEWS[7];
    assert_eq!(
        (baked.pitch, baked.yaw, baked.path),
        (v.pitch, v.yaw, "blob2d")
    );
    let baked_scene = scene(&out, baked);
    let mut packages = Vec::new();
    for (engine, scene, name) in [
        ("webgpu", &scene_file, "webgpu"),
        ("three", &scene_file, "three"),
        ("webgpu", &baked_scene, "webgpu-blob2d"),
    ] {
        let package = out.join(format!("package-{name}"));
        let o = nimbus(&[
            "emit",
            "--engine",
            engine,
            "--scene",
            scene.to_str().expect("utf8"),
            "-o",
            package.to_str().expect("utf8"),
        ]);
        assert!(o.status.success(), "emit {name}: {}", text(&o.stderr));
        packages.push(package);
    }
    let render = |name: &str, scene: &Path, extra: &[&str]| -> image::RgbImage {
        let png = out.join(format!("{name}-nimbus.png"));
        let size = format!("{w}x{h}");
        let mut args = vec![
            "render",
            scene.to_str().expect("utf8"),
            "-r",
            &size,
            "-o",
            png.to_str().expect("utf8"),
        ];
        args.extend(extra);
        let o = nimbus(&args);
        assert!(o.status.success(), "render: {}", text(&o.stderr));
        rgb(&png)
    };
    let browse = |name: &str, package: &Path, extra: &[&str]| -> image::RgbImage {
        let mut args = view_args(w, h, v);
        args.extend(extra.iter().map(|s| s.to_string()));
        browser_frame(package, &out.join(format!("{name}.png")), &args)
    };
    let one = browse("webgpu-f1", &packages[0], &["page=webgpu", "frames=1"]);
    let upscaled = browse(
        "webgpu-upscaled",
        &packages[0],
        &["page=webgpu", "frames=16", "upscale=1"],
    );
    let three = browse("three-f1", &packages[1], &["frames=1"]);
    let want_one = render("f1", &scene_file, &["-f", "1"]);
    let want_upscaled = render("upscaled", &scene_file, &["-f", "16", "--upscale"]);
    for (name, want, got) in [
        ("one frame", &want_one, &one),
        ("16 upscaled frames", &want_upscaled, &upscaled),
    ] {
        assert_same_frame(&format!("WebGPU {name}"), want, got, &out);
    }
    let same = mean_difference(&one, &three);
    println!("WebGPU against three.js in the same browser: mean difference {same:.3}/255");
    assert!(
        same <= 0.1,
        "the two JavaScript hosts differ by {same:.3}/255"
    );
    // Control: another scene's render fails the comparison.
    let low = render("sun-low", &scene(&out, &VIEWS[1]), &["-f", "1"]);
    let mean = mean_difference(&low, &one);
    println!("control (sun-low render vs this frame): mean {mean:.2}/255");
    assert!(mean > MAX_MEAN, "the comparison cannot fail");
    // The same host's cascades in rotation: a frame at the package's sun, then the sun moved
    // (VIEWS[1]'s), each tile redrawn in bands into the back atlas and copied in when done;
    // once every band is drawn, the frame a whole redraw gives. Control: the frame right
    // after the move (one band drawn, nothing copied in yet).
    let moved = &VIEWS[1];
    assert_eq!(v.quality, "low");
    let sun = format!("sun={},{}", moved.sun_elevation, moved.sun_azimuth);
    let frames = rotation_frames(nimbus_clouds::Quality::Low);
    let settle = format!("settle={}", frames - 1);
    let rotated = ["page=webgpu", "first=1", &sun];
    let settled = browse(
        "webgpu-settled",
        &packages[0],
        &[&rotated[..], &[&settle]].concat(),
    );
    // One frame short: the last tile's last band not drawn, its tile still the old sun's.
    let short = format!("settle={}", frames - 2);
    let unsettled = browse(
        "webgpu-short",
        &packages[0],
        &[&rotated[..], &[&short]].concat(),
    );
    let whole = browse(
        "webgpu-whole",
        &packages[0],
        &[&rotated[..], &["rotation=0"]].concat(),
    );
    let first = browse("webgpu-first", &packages[0], &rotated);
    let (after, short, before) = (
        mean_difference(&whole, &settled),
        mean_difference(&whole, &unsettled),
        mean_difference(&whole, &first),
    );
    println!(
        "WebGPU cascades in rotation against a whole redraw: {after:.3}/255 once every band is \
         drawn ({frames} frames), {short:.3}/255 a frame short, {before:.3}/255 the frame after \
         the sun moved"
    );
    assert!(
        after <= 0.1,
        "the rotation did not end at the whole atlas: {after}"
    );
    assert!(
        short > 0.1 && before > 0.3,
        "the controls: a frame short ({short}) or one band drawn ({before}) already looked whole"
    );
    // The baked path by the same host: its bake pass drawn because the block it depends on is
    // new, then the clouds read it.
    let got = browse("webgpu-blob2d", &packages[2], &["page=webgpu", "frames=1"]);
    let want = render("blob2d", &baked_scene, &["-f", "1"]);
    assert_same_frame("WebGPU blob2d", &want, &got, &out);
    let volume = mean_difference(&one, &got);
    println!("control (the volume's frame vs the blob2d frame): mean {volume:.2}/255");
    assert!(volume > MAX_MEAN, "the blob2d frame is the volume's");
}

/// The impostor's bake reads the shadow cascades, which the three.js host redraws a band a
/// frame after the sun moves: each tile copied in must bake the impostor again, so that once
/// every tile is the new sun's the frame is the one a whole redraw gives. A frame at the
/// package's sun first, then `setSun` to the low sun; compared after as many more frames as
/// the atlas has bands with
/// the frame of a host that redraws every tile at once. Control: the frame right after the
/// move, its coarser tiles still the old sun's.
#[test]
fn the_impostor_follows_a_moved_sun_through_rotating_cascades() {
    if !browser_tools_present("the impostor's rotation test", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-impostor-rotation");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("screenshot folder");
    let (pv, v) = (&VIEWS[9], &VIEWS[10]);
    assert_eq!((pv.path, v.path), ("impostor", "impostor"));
    let package = out.join("package");
    let o = nimbus(&[
        "emit",
        "--engine",
        "three",
        "--scene",
        scene(&out, pv).to_str().expect("utf8"),
        "-o",
        package.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "emit: {}", text(&o.stderr));
    let page = |png: &str, extra: &[&str]| {
        let mut args = view_args(160, 90, v);
        args.extend([
            format!("sun={},{}", v.sun_elevation, v.sun_azimuth),
            "first=1".to_string(),
        ]);
        args.extend(extra.iter().map(|s| s.to_string()));
        browser_frame(&package, &out.join(png), &args)
    };
    assert_eq!(v.quality, "low");
    let settle = format!(
        "settle={}",
        rotation_frames(nimbus_clouds::Quality::Low) - 1
    );
    let settled = page("settled-chromium.png", &[&settle]);
    let whole = page("whole-chromium.png", &["rotation=0"]);
    let first = page("first-frame-chromium.png", &[]);
    let (after, before) = (
        mean_difference(&whole, &settled),
        mean_difference(&whole, &first),
    );
    println!(
        "impostor, cascades in rotation against a whole redraw: {after:.3}/255 once every tile \
         is redrawn, {before:.3}/255 the frame after the sun moved; screenshots: {}",
        out.display()
    );
    assert!(
        after <= 0.1,
        "the impostor kept a bake of the half-redrawn cascades: {after}"
    );
    assert!(
        before > 0.3,
        "the control: one tile redrawn already looked whole ({before})"
    );
}

/// Cascades in rotation at `high`, in both JavaScript hosts: three 512-texel tiles in a 2 × 2
/// grid, each in eight bands, so bands land in the atlas's second row of tiles and the copies
/// come from it too (WebGL counts rows from the bottom, WebGPU from the top). After a frame at
/// the package's sun, the sun moved: once every band is drawn the frame is the one a whole
/// redraw gives; a frame short (the last tile's last band not drawn) it is not.
#[test]
fn both_hosts_rotate_high_cascades_in_bands_to_the_whole_redraw() {
    if !browser_tools_present("the browser test of high's bands", missing()) {
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-high-bands");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("folder");
    let v = View {
        name: "high-bands",
        quality: "high",
        ..VIEWS[0]
    };
    let moved = &VIEWS[1];
    let scene_file = scene(&out, &v);
    let frames = rotation_frames(nimbus_clouds::Quality::High);
    let sun = format!("sun={},{}", moved.sun_elevation, moved.sun_azimuth);
    for engine in ["three", "webgpu"] {
        let package = out.join(engine);
        common::emit_scene(engine, &scene_file, &package);
        let page = |name: &str, extra: &[String]| {
            let mut args = view_args(160, 90, &v);
            if engine == "webgpu" {
                args.push("page=webgpu".to_string());
            }
            args.extend(["first=1".to_string(), sun.clone()]);
            args.extend(extra.iter().cloned());
            browser_frame(&package, &out.join(format!("{engine}-{name}.png")), &args)
        };
        let whole = page("whole", &["rotation=0".to_string()]);
        let settled = page("settled", &[format!("settle={}", frames - 1)]);
        let short = page("short", &[format!("settle={}", frames - 2)]);
        let (after, before) = (
            mean_difference(&whole, &settled),
            mean_difference(&whole, &short),
        );
        println!(
            "{engine}, high in bands ({frames} frames): {after:.3}/255 from a whole redraw once \
             every band is drawn, {before:.3}/255 a frame short"
        );
        assert!(
            after <= 0.1,
            "{engine}: the rotation did not end at the whole atlas: {after}"
        );
        assert!(
            before > 0.1,
            "{engine}: the control: a frame short already looked whole ({before})"
        );
    }
}
