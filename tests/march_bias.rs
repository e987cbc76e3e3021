//! The marches against a fine numerical integral of the same density along the same path: the
//! reference preset's secondary (sun and ground) marches and its primary march must be unbiased
//! (|bias| ≤ 0.5 %), so that the accuracy study measures the presets against the truth and not
//! against the reference's own error.
//!
//! Bias is `Σ march / Σ fine − 1` over a few hundred points inside the clouds, each marched at
//! eight evenly spaced offsets (the expectation over the jitter the reference uses, without
//! its noise). The control puts each sample at the start of its interval, as the march did
//! before: the test must see that as biased.
//!
//! The real-time presets' sun march is checked where no shadow map can finish it: above every
//! shadow-casting layer it must follow the whole path out of the slab, and a preset that takes
//! no sun step below the casters (`low`) must take one where the map fades out at its edge.

mod common;

use std::path::Path;

use common::Rng;
use glam::Vec3;
use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::march::{
    CloudUniforms, altitude_along, cloud_range, march_clouds, secondary_optical_depth,
    secondary_reach, shadow_optical_depth, slab_exit, sun_optical_depth, total_density,
};
use nimbus_clouds::model::shadow::shadow_read;
use nimbus_clouds::{CloudLibrary, Quality, key::CloudKey};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::TextureSizes;

fn textures() -> CloudTextures {
    generate_cpu_textures(TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    })
}

/// Optical depth from `p` along `dir` over `[0, length]` by 1 m midpoint steps.
fn fine_optical_depth(
    u: &CloudUniforms,
    key: CloudKey,
    p: Vec3,
    h: f32,
    dir: Vec3,
    length: f32,
) -> f64 {
    let sigma = f64::from(u.light.scattering_coefficient + u.light.absorption_coefficient);
    let n = length.ceil().max(1.0) as u32;
    let dt = length / n as f32;
    (0..n)
        .map(|i| {
            let t = (i as f32 + 0.5) * dt;
            let ht = altitude_along(h, dir.y, t, u.march.radius);
            f64::from(total_density(p + dir * t, ht, 0.0, key)) * sigma * f64::from(dt)
        })
        .sum()
}

struct Bias {
    march: f64,
    fine: f64,
    points: usize,
}

impl Bias {
    fn relative(&self) -> f64 {
        self.march / self.fine - 1.0
    }
}

/// A genus at a quality under a sun `elevation_deg` high, bound for the CPU twins.
struct Setup {
    u: CloudUniforms,
    key: CloudKey,
    sun: Vec3,
}

fn setup(genus: &str, quality: Quality, elevation_deg: f32) -> Setup {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let genus = lib.genus(genus).expect("genus");
    let key = CloudVariant::new(genus, quality, quality.features()).key;
    let (s, c) = elevation_deg.to_radians().sin_cos();
    let sun = Vec3::new(c, s, 0.0);
    let u = CloudUniforms::for_genus(genus, quality, sun, 0.0);
    Setup { u, key, sun }
}

/// `points` random points inside the clouds (density > 0), with their altitudes; the textures
/// must be bound.
fn cloudy_points(s: &Setup, seed: u64, points: usize) -> Vec<(Vec3, f32)> {
    let m = s.u.march;
    let mut rng = Rng::new(seed);
    let mut found = Vec::with_capacity(points);
    let mut tries = 0;
    while found.len() < points && tries < 200_000 {
        tries += 1;
        let h = rng.range(m.min_height, m.max_height);
        let p = Vec3::new(
            rng.range(-20_000.0, 20_000.0),
            h,
            rng.range(-20_000.0, 20_000.0),
        );
        if total_density(p, h, 0.0, s.key) > 0.0 {
            found.push((p, h));
        }
    }
    assert_eq!(found.len(), points, "found too few cloudy points");
    found
}

/// Marches from `points` random cloudy points towards `dir` with `steps` steps at each of
/// `offsets`, against the 1 m integral over the span the march covers.
fn measure(
    genus: &str,
    quality: Quality,
    elevation_deg: f32,
    down: bool,
    offsets: &[f32],
    points: usize,
    textures: &CloudTextures,
) -> Bias {
    let s = setup(genus, quality, elevation_deg);
    let _bound = textures.bind(s.u);
    let m = s.u.march;
    let (dir, steps) = if down {
        (Vec3::NEG_Y, m.ground_steps)
    } else {
        (s.sun, m.sun_steps)
    };
    let mut bias = Bias {
        march: 0.0,
        fine: 0.0,
        points: 0,
    };
    for (p, h) in cloudy_points(&s, 7 + elevation_deg as u64, points) {
        let full = down || m.secondary_full_path > 0;
        let length = if full {
            slab_exit(h, dir.y)
        } else {
            secondary_reach(steps, m.min_secondary_step, m.secondary_step_scale)
        };
        bias.fine += fine_optical_depth(&s.u, s.key, p, h, dir, length);
        bias.march += offsets
            .iter()
            .map(|&o| {
                f64::from(secondary_optical_depth(
                    p, h, dir, steps, o, full, 0.0, s.key,
                ))
            })
            .sum::<f64>()
            / offsets.len() as f64;
        bias.points += 1;
    }
    assert!(bias.fine > 0.0, "the paths cross cloud");
    bias
}

fn stratified(n: usize) -> Vec<f32> {
    (0..n).map(|i| (i as f32 + 0.5) / n as f32).collect()
}

#[test]
fn reference_secondary_marches_are_unbiased() {
    let t = textures();
    let mut worst: f64 = 0.0;
    for genus in ["cumulus", "stratocumulus"] {
        for (elevation, down) in [(15.0, false), (40.0, false), (75.0, false), (0.0, true)] {
            let b = measure(
                genus,
                Quality::Reference,
                elevation,
                down,
                &stratified(8),
                150,
                &t,
            );
            let control = measure(genus, Quality::Reference, elevation, down, &[0.0], 150, &t);
            let what = if down {
                "ground".to_string()
            } else {
                format!("sun {elevation}°")
            };
            println!(
                "{genus:14} {what:8}: reference {:+.3} % over {} points; samples at interval starts {:+.2} %",
                100.0 * b.relative(),
                b.points,
                100.0 * control.relative()
            );
            assert!(
                control.relative() > 0.01,
                "{genus} {what}: the control (samples at interval starts) must read as biased, got {:+.3} %",
                100.0 * control.relative()
            );
            worst = worst.max(b.relative().abs());
        }
    }
    println!("worst |bias| of the reference: {:.3} %", 100.0 * worst);
    assert!(
        worst <= 0.005,
        "reference secondary march biased by {:.3} %",
        100.0 * worst
    );
}

#[test]
fn real_time_secondary_marches_sample_interval_midpoints() {
    // The real-time presets hand the rest of the path to the shadow map; over their own short
    // reach a midpoint per interval is far closer to the integral than the interval's start.
    // A preset that leaves the whole way to the map (`low`) has no reach to check.
    let t = textures();
    let marching: Vec<Quality> = Quality::ALL
        .into_iter()
        .filter(|q| q.settings().max_iteration_count_to_sun > 0)
        .collect();
    assert!(!marching.is_empty(), "some preset marches towards the sun");
    for quality in marching {
        let mid = measure("cumulus", quality, 40.0, false, &[0.5], 150, &t);
        let start = measure("cumulus", quality, 40.0, false, &[0.0], 150, &t);
        println!(
            "cumulus {:6} sun 40°: midpoints {:+.2} %, interval starts {:+.2} %",
            quality.name(),
            100.0 * mid.relative(),
            100.0 * start.relative()
        );
        assert!(
            mid.relative().abs() < 0.5 * start.relative().abs(),
            "{}: midpoints {:+.3} % not clearly better than starts {:+.3} %",
            quality.name(),
            100.0 * mid.relative(),
            100.0 * start.relative()
        );
    }
}

#[test]
fn sun_march_above_every_shadow_caster_spans_the_whole_path() {
    // High layers cast no shadow: no map carries their sun path on where the real-time presets'
    // short march (150 m at high) stops. The sun's optical depth as the primary march takes it
    // (`sun_optical_depth`, midpoints) must then follow the whole path out of the slab; the
    // control is the short march alone, as it was, which reads most of the path as clear
    // (measured: cirrus at high -8 %, control -60 %; cirrostratus +11 %, control -83 %).
    let t = textures();
    let mut failures = Vec::new();
    for genus in ["cirrus", "cirrostratus"] {
        for quality in Quality::ALL {
            let s = setup(genus, quality, 35.0);
            let _bound = t.bind(s.u);
            let m = s.u.march;
            let (mut fine, mut marched, mut short) = (0.0f64, 0.0f64, 0.0f64);
            for (p, h) in cloudy_points(&s, 11, 150) {
                assert!(
                    h > m.shadow_top_height,
                    "{genus}: a layer that casts a shadow"
                );
                fine += fine_optical_depth(&s.u, s.key, p, h, s.sun, slab_exit(h, s.sun.y));
                marched += f64::from(sun_optical_depth(p, h, 0.5, 0.0, s.key));
                short += f64::from(secondary_optical_depth(
                    p,
                    h,
                    s.sun,
                    m.sun_steps,
                    0.5,
                    false,
                    0.0,
                    s.key,
                ));
            }
            let (bias, control) = (marched / fine - 1.0, short / fine - 1.0);
            println!(
                "{genus:12} {:6} sun 35°: whole path {:+.1} %, short march alone (control) {:+.1} %",
                quality.name(),
                100.0 * bias,
                100.0 * control
            );
            if control > -0.5 {
                failures.push(format!(
                    "{genus} {}: the control must miss most of the path, got {:+.1} %",
                    quality.name(),
                    100.0 * control
                ));
            }
            // One midpoint over kilometres is crude (the one step a full path takes at `low`,
            // whose preset leaves the sun to the map below the shadow casters: measured -58 %
            // for cirrus, +29 % for cirrostratus), but must still see the path's cloud (none
            // read is -100 %) and beat the short march; two or more steps must follow the path.
            let allowed = if m.sun_steps >= 2 {
                0.15
            } else {
                control.abs().min(0.7)
            };
            if bias.abs() > allowed {
                failures.push(format!(
                    "{genus} {}: the sun's optical depth is off the whole path's by {:+.1} % \
                     (allowed {:.0} %)",
                    quality.name(),
                    100.0 * bias,
                    100.0 * allowed
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn reference_primary_march_is_unbiased() {
    // Optical depth of the whole view ray, -ln T, against the 1 m integral over the same range,
    // for rays from the ground up through the layer; rays the integral finds opaque (τ > 30,
    // where f32 transmittance has no digits left) are left out.
    let t = textures();
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut rng = Rng::new(5);
    for genus in ["cumulus", "stratocumulus"] {
        let genus = lib.genus(genus).expect("genus");
        let quality = Quality::Reference;
        let key = CloudVariant::new(genus, quality, quality.features()).key;
        let u = CloudUniforms::for_genus(genus, quality, Vec3::new(0.5, 0.8, 0.3), 0.0);
        let _bound = t.bind(u);
        let (mut march, mut fine, mut rays) = (0.0f64, 0.0f64, 0);
        let offsets = stratified(8);
        while rays < 24 {
            let elevation = rng.range(8.0, 85.0).to_radians();
            let azimuth = rng.range(0.0, std::f32::consts::TAU);
            let dir = Vec3::new(
                elevation.cos() * azimuth.cos(),
                elevation.sin(),
                elevation.cos() * azimuth.sin(),
            );
            let range = cloud_range(dir.y);
            // The march's own origin: a ray from the camera (here on the ground).
            let sigma = f64::from(u.light.scattering_coefficient + u.light.absorption_coefficient);
            let n = (range.y - range.x).ceil().max(1.0) as u32;
            let dt = (range.y - range.x) / n as f32;
            let tau: f64 = (0..n)
                .map(|i| {
                    let s = range.x + (i as f32 + 0.5) * dt;
                    let h = altitude_along(0.0, dir.y, s, u.march.radius);
                    f64::from(total_density(dir * s, h, 0.0, key)) * sigma * f64::from(dt)
                })
                .sum();
            if !(0.05..30.0).contains(&tau) {
                continue;
            }
            let marched = offsets
                .iter()
                .map(|&j| -f64::from(march_clouds(dir, j, 0.0, key).transmittance).ln())
                .sum::<f64>()
                / offsets.len() as f64;
            march += marched;
            fine += tau;
            rays += 1;
        }
        let bias = march / fine - 1.0;
        println!(
            "{:14} primary: {:+.3} % over {rays} rays (mean τ {:.2})",
            genus.name,
            100.0 * bias,
            fine / f64::from(rays)
        );
        assert!(
            bias.abs() <= 0.005,
            "{}: primary march biased by {:+.3} %",
            genus.name,
            100.0 * bias
        );
    }
}

/// The reference's sun march before this check, kept here as the "before" figure: 16 steps from
/// 100/16 m growing ×1.25 (862 m in all, the shadow map beyond), each sample half the
/// *previous* step past its interval's start.
fn old_reference_optical_depth(
    u: &CloudUniforms,
    key: CloudKey,
    p: Vec3,
    h: f32,
    dir: Vec3,
) -> f64 {
    let sigma = f64::from(u.light.scattering_coefficient + u.light.absorption_coefficient);
    let mut step = 100.0f32 / 16.0;
    let mut t = 0.5 * step;
    let mut tau = 0.0f64;
    for _ in 0..16 {
        let ht = altitude_along(h, dir.y, t, u.march.radius);
        tau += f64::from(total_density(p + dir * t, ht, 0.0, key)) * sigma * f64::from(step);
        t += step;
        step *= 1.25;
    }
    tau
}

#[test]
fn the_old_reference_sun_march_was_biased() {
    // Before and after on the same points: the old scheme against a 1 m integral over its own
    // 862 m reach.
    let t = textures();
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let genus = lib.genus("cumulus").expect("cumulus");
    let quality = Quality::Reference;
    let key = CloudVariant::new(genus, quality, quality.features()).key;
    let u = CloudUniforms::for_genus(genus, quality, Vec3::new(0.6, 0.64, 0.48), 0.0);
    let _bound = t.bind(u);
    let dir = u.light.sun_direction;
    let reach = 100.0 / 16.0 * (1.25f32.powi(16) - 1.0) / 0.25;
    let mut rng = Rng::new(3);
    let (mut old, mut fine, mut n) = (0.0f64, 0.0f64, 0);
    while n < 150 {
        let h = rng.range(u.march.min_height, u.march.max_height);
        let p = Vec3::new(
            rng.range(-20_000.0, 20_000.0),
            h,
            rng.range(-20_000.0, 20_000.0),
        );
        if total_density(p, h, 0.0, key) <= 0.0 {
            continue;
        }
        old += old_reference_optical_depth(&u, key, p, h, dir);
        fine += fine_optical_depth(&u, key, p, h, dir, reach);
        n += 1;
    }
    let bias = old / fine - 1.0;
    println!(
        "before: the old reference sun march {:+.2} % over {n} points ({reach:.0} m reach)",
        100.0 * bias
    );
    assert!(bias > 0.05, "the old scheme read {:+.2} %", 100.0 * bias);
}

#[test]
fn a_preset_without_sun_steps_takes_one_where_the_map_fades() {
    // `low` takes no sun step below the shadow casters: the map carries the whole way to the
    // sun. Towards the map's edge the map fades out (`ShadowRead::held` from 1 to 0) and one
    // short step fades in, as much as the map fades; beyond it the step is all. Cascades as a
    // frame of the runtime places them; the map's texels (the CPU textures hold an empty map)
    // read as clear sky, so what the map adds is the texel's own (zero) and the rest is the
    // step. Controls: the map alone (no step anywhere) reads nothing beyond the map, and a step
    // everywhere reads it inside the map too.
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let genus = lib.genus("cumulus").expect("cumulus");
    assert_eq!(Quality::Low.settings().max_iteration_count_to_sun, 0);
    let mut frame = nimbus_runtime::render::Frame::new(genus.clone(), Quality::Low, 320, 180);
    frame.sun_elevation_deg = 35.0;
    let u = nimbus_runtime::render::Renderer::uniforms(&frame);
    let key = CloudVariant::new(genus, Quality::Low, Quality::Low.features()).key;
    assert!(key.uses_shadow_map(), "low samples the shadow map");
    let t = textures();
    let _bound = t.bind(u);
    let sun = u.light.sun_direction;
    let m = u.march;
    let mut rng = Rng::new(23);
    let (mut inside, mut fading, mut beyond) = (0usize, 0usize, 0usize);
    let mut step_beyond = 0.0f64;
    // Points at which each control departs from the model: beyond the map with cloud in the
    // step (the map alone reads less there), inside it with cloud in the step (a step
    // everywhere reads more there).
    let (mut tells_map_alone, mut tells_step_everywhere) = (0usize, 0usize);
    let mut failures = Vec::new();
    let mut tries = 0;
    while (inside < 100 || fading < 20 || beyond < 100) && tries < 400_000 {
        tries += 1;
        let h = rng.range(m.min_height, m.shadow_top_height);
        let r = 150_000.0 * rng.range(0.0, 1.0).sqrt();
        let a = rng.range(0.0, std::f32::consts::TAU);
        let p = Vec3::new(r * a.cos(), h, r * a.sin());
        if total_density(p, h, 0.0, key) <= 0.0 {
            continue;
        }
        let map = shadow_read(p);
        let to_top = (m.shadow_top_height - h).max(0.0) / sun.y.max(0.01);
        let from_map = shadow_optical_depth(map.texel, to_top, 0.0);
        let step = secondary_optical_depth(p, h, sun, 1, 0.5, false, 0.0, key);
        let expected = from_map + (1.0 - map.held) * step;
        let got = sun_optical_depth(p, h, 0.5, 0.0, key);
        if (got - expected).abs() > 1e-4 * expected.max(1.0) {
            failures.push(format!(
                "at {p} (held {:.2}): {got} where the map gives {from_map} and the step {step}",
                map.held
            ));
        }
        if map.held >= 1.0 {
            inside += 1;
            tells_step_everywhere += usize::from(step > 1e-3);
        } else if map.held > 0.0 {
            fading += 1;
        } else {
            beyond += 1;
            step_beyond += f64::from(step);
            tells_map_alone += usize::from(step > 1e-3);
        }
    }
    println!(
        "low, cumulus: {inside} cloudy points inside the map, {fading} where it fades, {beyond} \
         beyond (one step there reads {:.3} on average); the map alone departs at \
         {tells_map_alone}, a step everywhere at {tells_step_everywhere}",
        step_beyond / beyond.max(1) as f64
    );
    assert!(
        inside >= 100 && fading >= 20 && beyond >= 100,
        "too few points in some part of the map ({inside} / {fading} / {beyond})"
    );
    assert!(
        tells_map_alone >= 50 && tells_step_everywhere >= 50,
        "the controls cannot be told apart here: the map alone departs at {tells_map_alone} \
         points, a step everywhere at {tells_step_everywhere}"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
