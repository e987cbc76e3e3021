//! A scene over time: the sun follows the clock, the clouds drift with the wind (sheared with
//! height), and weather states take over without popping.

mod common;

use std::path::Path;

use glam::{Vec2, Vec3};
use nimbus_clouds::clock::{Clock, solar_position};
use nimbus_clouds::model::density::layer_density;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::wind::{TOP_ALTITUDE, Wind};
use nimbus_clouds::{CloudLibrary, Quality, ScenePreset, parse_scene};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::{Renderer, TextureSizes};
use nimbus_runtime::scene_time::frames_at;

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

fn clock(start: &str, utc_offset_hours: f64, latitude_deg: f64, longitude_deg: f64) -> Clock {
    let text = format!(
        "name = \"c\"\ndescription = \"\"\ngenus = \"cumulus\"\n[clock]\nstart = \"{start}\"\n\
         utc_offset_hours = {utc_offset_hours}\nlatitude_deg = {latitude_deg}\n\
         longitude_deg = {longitude_deg}\n"
    );
    parse_scene(Path::new("c.toml"), &text)
        .expect("scene")
        .clock
        .expect("clock")
}

/// The highest sun of the day (one-minute steps) and when it stands there.
fn noon(c: &Clock) -> (f64, f64, f64) {
    (0..1440)
        .map(|m| {
            let s = c.sun_at(f64::from(m) * 60.0);
            (s.elevation_deg, s.azimuth_deg, f64::from(m) * 60.0)
        })
        .fold((f64::MIN, 0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
}

#[test]
fn the_sun_stands_where_the_sky_puts_it() {
    // June solstice at Zurich: the noon sun is 90° − latitude + obliquity (23.44°) high, due
    // south, at about 13:30 local summer time (longitude 8.54° E is 34 min before the zone's
    // 15° E, plus the equation of time of −1.7 min).
    let zurich = clock("2026-06-21T00:00", 2.0, 47.37, 8.54);
    let (elevation, azimuth, at) = noon(&zurich);
    println!(
        "Zurich, 21 June: noon sun {elevation:.3}° at {azimuth:.2}°, {:.0} min after midnight",
        at / 60.0
    );
    assert!(
        (elevation - (90.0 - 47.37 + 23.44)).abs() < 0.05,
        "noon elevation {elevation}"
    );
    assert!((azimuth - 180.0).abs() < 0.5, "noon azimuth {azimuth}");
    assert!(
        (at / 60.0 - 13.0 * 60.0 - 28.0).abs() <= 3.0,
        "solar noon at {} min",
        at / 60.0
    );
    // Equinox at the equator and Greenwich: nearly overhead at noon, rising in the east.
    let equator = clock("2026-03-20T00:00", 0.0, 0.0, 0.0);
    let (elevation, _, _) = noon(&equator);
    assert!(elevation > 89.5, "equinox noon at the equator {elevation}");
    let rising = equator.sun_at(6.0 * 3600.0 + 10.0 * 60.0);
    assert!(
        rising.elevation_deg.abs() < 1.0 && (rising.azimuth_deg - 90.0).abs() < 1.0,
        "{rising:?}"
    );
    // Southern winter: the sun stands in the north at noon, low.
    let sydney = clock("2026-06-21T00:00", 10.0, -33.87, 151.21);
    let (elevation, azimuth, _) = noon(&sydney);
    assert!(
        (elevation - (90.0 - 33.87 - 23.44)).abs() < 0.05,
        "Sydney noon {elevation}"
    );
    assert!(
        !(1.0..359.0).contains(&azimuth),
        "Sydney noon azimuth {azimuth}"
    );
    // The same instant given in two time zones is the same sun.
    let a = solar_position(1_782_043_200.0, 47.37, 8.54);
    let b = clock("2026-06-21T14:00", 2.0, 47.37, 8.54).sun_at(0.0);
    assert!(
        (a.elevation_deg - b.elevation_deg).abs() < 1e-9,
        "{a:?} {b:?}"
    );
}

/// The clouds drift with the wind, each altitude with its own: the density at a point after
/// `t` seconds is the density `drift` upwind of it at the start, exactly.
#[test]
fn clouds_drift_with_the_wind_at_their_altitude() {
    let lib = library();
    let genus = lib.genus("cumulus").expect("genus").clone();
    let textures = generate_cpu_textures(TextureSizes {
        weather: 64,
        shape: 16,
        detail: 8,
        turbulence: 16,
    });
    let q = Quality::High;
    let key = nimbus_clouds::model::clouds::CloudVariant::new(&genus, q, q.features()).key;
    let still = CloudUniforms::for_genus(&genus, q, Vec3::new(0.3, 0.8, 0.2).normalize(), 2.0);
    let wind = Wind {
        speed: 8.0,
        direction_deg: 250.0,
        top_speed: Some(30.0),
        top_direction_deg: Some(290.0),
    };
    let seconds = 900.0;
    let drift = wind.drift(seconds);
    let mut moving = still;
    moving.media.wind_drift = drift.ground;
    moving.media.wind_shear_drift = drift.per_metre;
    let mut worst = 0.0f32;
    let mut cloudy = 0;
    for i in 0..400 {
        let x = (i % 20) as f32 * 731.0 - 7000.0;
        let z = (i / 20) as f32 * 617.0 - 6000.0;
        let h = 600.0 + (i % 7) as f32 * 300.0;
        let p = Vec3::new(x, h - 2.0, z);
        let now = {
            let _b = textures.bind(moving);
            layer_density(p, h, 0, 0.0, key)
        };
        // Where that air was: upwind by the wind at its altitude times the time.
        let v = wind.velocity_at(h) * seconds as f32;
        let before = {
            let _b = textures.bind(still);
            layer_density(p - Vec3::new(v.x, 0.0, v.y), h, 0, 0.0, key)
        };
        worst = worst.max((now - before).abs().max_element());
        if now.max_element() > 0.0 {
            cloudy += 1;
        }
    }
    println!("{cloudy} of 400 points cloudy; largest difference {worst:e}");
    assert!(
        cloudy > 20,
        "too few cloudy points to mean anything: {cloudy}"
    );
    assert!(
        worst < 1e-4,
        "the drifted density is not the upwind density: {worst}"
    );
    // The shear: at 10 km the drift is the top wind's.
    let top = wind.velocity_at(TOP_ALTITUDE) * seconds as f32;
    let shear = drift.ground + drift.per_metre * TOP_ALTITUDE;
    assert!((top - shear).length() < 1e-2, "{top} vs {shear}");
    let westerly = nimbus_clouds::wind::wind_velocity(10.0, 270.0);
    assert!(
        (westerly - Vec2::new(10.0, 0.0)).length() < 1e-5,
        "a westerly blows east: {westerly}"
    );
}

/// A scene with wind and `states` (TOML `[[weather]]` tables).
fn scene(states: &str) -> ScenePreset {
    let text = format!(
        "name = \"t\"\ndescription = \"\"\ngenus = \"cumulus\"\ncoverage = 0.25\n\
         camera_pitch_deg = 35.0\nsun_elevation_deg = 40.0\nsun_azimuth_deg = 200.0\n\
         quality = \"low\"\n[wind]\nspeed = 3.0\ndirection_deg = 270.0\n{states}"
    );
    parse_scene(Path::new("t.toml"), &text).expect("scene")
}

/// Mean absolute difference of consecutive pictures (display levels) at `times`.
fn changes(scene: &ScenePreset, times: &[f64], renderer: &mut Renderer<'_>) -> Vec<f64> {
    let lib = library();
    let genus_of = |name: &str| lib.genus(name).cloned();
    let pictures: Vec<Vec<u8>> = times
        .iter()
        .map(|&t| {
            let frames = frames_at(scene, &genus_of, t, 96, 54).expect("frames");
            renderer
                .render_blend(&frames)
                .expect("render")
                .to_rgba8(8.0)
                .into_raw()
        })
        .collect();
    pictures
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .map(|(a, b)| f64::from(a.abs_diff(*b)))
                .sum::<f64>()
                / w[0].len() as f64
        })
        .collect()
}

/// How far a sequence's steps stand out from their neighbours: the largest ratio of a step's
/// change to the median of the six steps around it (at least `floor`). A ramp, however fast,
/// changes like its neighbours (about 1); a switch is a spike.
fn spike(steps: &[f64], floor: f64) -> f64 {
    (0..steps.len())
        .map(|k| {
            let mut around: Vec<f64> = (k.saturating_sub(3)..(k + 4).min(steps.len()))
                .filter(|&j| j != k)
                .map(|j| steps[j])
                .collect();
            around.sort_by(f64::total_cmp);
            steps[k] / around[around.len() / 2].max(floor)
        })
        .fold(0.0, f64::max)
}

/// Weather states take over without popping. Frame-to-frame change (mean display levels,
/// 96 × 54, looking up at the clouds, a 3 m/s wind: 225 m between pictures) over the 20
/// pictures of a 25-minute transition: no step may stand out from the steps around it, as one
/// does at a switch (the control: the same change at once).
#[test]
fn weather_changes_without_popping() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let times: Vec<f64> = (0..=20).map(|k| f64::from(k) * 75.0).collect();
    let median = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        s[s.len() / 2]
    };
    // Ordinary frames: the wind alone.
    let ordinary = median(&changes(&scene(""), &times, &mut renderer));
    // Coverage 0.25 → 0.4 within the genus by 1500 s: uniforms only, one pipeline.
    let grow = scene("[[weather]]\nat = 1500.0\ncoverage = 0.4\n");
    let lib = library();
    let genus_of = |name: &str| lib.genus(name).cloned();
    let keys: Vec<_> = times
        .iter()
        .map(|&t| frames_at(&grow, &genus_of, t, 96, 54).expect("frames"))
        .map(|f| {
            assert_eq!(f.len(), 1, "a change within a genus is one picture");
            f[0].0.variant().key
        })
        .collect();
    assert!(
        keys.windows(2).all(|w| w[0] == w[1]),
        "the pipeline changed within a genus"
    );
    let within = changes(&grow, &times, &mut renderer);
    // Cumulus → stratocumulus by 1500 s: two pictures blended.
    let genus = changes(
        &scene("[[weather]]\nat = 1500.0\ngenus = \"stratocumulus\"\ncoverage = 0.4\n"),
        &times,
        &mut renderer,
    );
    // The control: coverage 0.25 → 0.4 at once, at 750 s.
    let abrupt = changes(
        &scene(
            "[[weather]]\nat = 750.0\ncoverage = 0.25\n[[weather]]\nat = 750.0\ncoverage = 0.4\n",
        ),
        &times,
        &mut renderer,
    );
    let largest = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let pop = |v: &[f64]| spike(v, ordinary);
    println!(
        "frame-to-frame change (display levels): ordinary (the wind alone) {ordinary:.3}; \
         largest step and its ratio to the steps around it: coverage growth {:.3} ({:.2}), \
         change of genus {:.3} ({:.2}), abrupt (control) {:.3} ({:.2})",
        largest(&within),
        pop(&within),
        largest(&genus),
        pop(&genus),
        largest(&abrupt),
        pop(&abrupt),
    );
    assert!(
        pop(&abrupt) > 3.0,
        "the measure does not see a switch: {:.2}",
        pop(&abrupt)
    );
    for (what, v) in [("coverage growth", &within), ("change of genus", &genus)] {
        assert!(
            pop(v) < 2.0,
            "{what} pops: a step changes {:.2} × as much as the steps around it",
            pop(v)
        );
    }
}

/// `over` starts a state's transition that many seconds before its time, as a JavaScript
/// host's `setWeather(c, { at, over })` does (both call `weather_progress`); without it the
/// transition spans the whole interval from the state before. A negative `over` is refused,
/// naming the field.
#[test]
fn a_weather_state_can_be_reached_over_its_last_seconds() {
    let coverage = |states: &str, t: f64| -> f32 {
        let s = scene(states);
        let layers = s.at(t, &|_| 0.35).layers;
        assert_eq!(layers.len(), 1, "one genus");
        layers[0].coverage
    };
    let whole = "[[weather]]\nat = 7200.0\ncoverage = 0.75\n";
    let last = "[[weather]]\nat = 7200.0\ncoverage = 0.75\nover = 600.0\n";
    // Halfway through the whole interval the ramp is halfway; with `over` nothing has moved.
    assert!((coverage(whole, 3600.0) - 0.5).abs() < 1e-6);
    assert_eq!(coverage(last, 3600.0), 0.25);
    assert_eq!(coverage(last, 6600.0), 0.25);
    // Halfway through the last 600 s: halfway (smoothstep is 0.5 at 0.5).
    assert!(
        (coverage(last, 6900.0) - 0.5).abs() < 1e-6,
        "{}",
        coverage(last, 6900.0)
    );
    assert_eq!(coverage(last, 7200.0), 0.75);
    // The control: `over` longer than the interval is the whole interval.
    let long = "[[weather]]\nat = 7200.0\ncoverage = 0.75\nover = 9000.0\n";
    assert_eq!(coverage(long, 3600.0), coverage(whole, 3600.0));
    // Refused with the field named.
    let text = "name = \"t\"\ndescription = \"\"\ngenus = \"cumulus\"\n\
                [[weather]]\nat = 60.0\ncoverage = 0.5\nover = -5.0\n";
    let err = parse_scene(Path::new("t.toml"), text)
        .expect_err("a negative over")
        .to_string();
    assert!(
        err.contains("weather[].over") && err.contains("-5"),
        "{err}"
    );
}
