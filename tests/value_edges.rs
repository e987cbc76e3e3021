//! The accepted ranges (`nimbus_clouds::limits`) end where rendering stops being right, so each
//! edge is rendered here and checked: night and deep twilight are dark results, not errors; the
//! widest accepted field of view still puts each direction where a narrow camera looking
//! that way sees it; a camera straight up or down, at the top of the atmosphere, or at the
//! extreme exposure gives finite images. Values just past each edge are refused by
//! `Frame::validate` naming the field.

mod common;

use std::path::Path;

use nimbus_clouds::limits::{self, Limit};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::RuntimeError;
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

fn frame(width: u32, height: u32) -> Frame {
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
        .expect("examples");
    let mut f = Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::Low,
        width,
        height,
    );
    f.frames = 1;
    f
}

fn luminance(p: &[f32; 4]) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

fn mean_luminance(img: &Image) -> f64 {
    img.pixels.iter().map(luminance).sum::<f64>() / img.pixels.len() as f64
}

fn render(gpu: &Gpu, f: &Frame) -> Image {
    let mut r = Renderer::new(gpu, TextureSizes::default());
    let img = r.render(f).expect("renders");
    img.check().expect("finite");
    img
}

#[test]
fn night_and_twilight_are_dark_results_not_errors() {
    let Some(gpu) = common::gpu() else { return };
    let mut day = frame(48, 27);
    day.sun_elevation_deg = 30.0;
    let day_light = mean_luminance(&render(gpu, &day));
    assert!(day_light > 0.0);
    for elevation in [-10.0, -30.0, limits::SUN_ELEVATION.min as f32] {
        let mut night = day.clone();
        night.sun_elevation_deg = elevation;
        let light = mean_luminance(&render(gpu, &night));
        println!("sun {elevation}°: mean luminance {light:.3e} (day {day_light:.3e})");
        assert!(
            light < 0.05 * day_light,
            "a sun {elevation}° below the horizon leaves the sky dark"
        );
    }
}

/// The colour of the centre pixel of the top row (or the bottom row).
fn edge_centre(img: &Image, top: bool) -> [f32; 4] {
    let y = if top { 0 } else { img.height - 1 };
    img.pixels[(y * img.width + img.width / 2) as usize]
}

#[test]
fn the_widest_field_of_view_sees_each_direction_where_a_narrow_one_does() {
    let Some(gpu) = common::gpu() else { return };
    let fov = limits::FOV.max as f32;
    // The wide camera looks 10° up, so its top rows look past the zenith (where a projection
    // that loses the sign of w draws the ground); its edge rows look fov/2 above and below
    // that. A 20° camera pitched to put its own edge row there must see the same colour.
    // Clouds are off (coverage 0) so only the sky, the ground and the haze are compared.
    let mut wide = frame(33, 19);
    wide.fov_deg = fov;
    wide.camera_pitch_deg = 10.0;
    wide.genus.coverage = 0.0;
    let wide_img = render(gpu, &wide);
    for top in [true, false] {
        let mut narrow = wide.clone();
        narrow.fov_deg = 20.0;
        let half_pixel = |f: f32, n: u32| {
            // The centre of the edge row is half a pixel inside the edge.
            ((f / 2.0).to_radians().tan() * (1.0 - 1.0 / n as f32))
                .atan()
                .to_degrees()
        };
        let wide_angle = half_pixel(fov, wide.height);
        let narrow_angle = half_pixel(narrow.fov_deg, narrow.height);
        narrow.camera_pitch_deg = wide.camera_pitch_deg
            + if top {
                wide_angle - narrow_angle
            } else {
                narrow_angle - wide_angle
            };
        let narrow_img = render(gpu, &narrow);
        let (a, b) = (edge_centre(&wide_img, top), edge_centre(&narrow_img, top));
        let (la, lb) = (luminance(&a), luminance(&b));
        println!(
            "fov {fov}° {} edge (elevation {:+.2}°): {a:?} vs {b:?}",
            if top { "top" } else { "bottom" },
            wide.camera_pitch_deg + if top { wide_angle } else { -wide_angle }
        );
        assert!(
            (la - lb).abs() <= TOLERANCE * la.max(lb) + 1e-6,
            "the {} edge of a {fov}° view sees {a:?} where a narrow camera sees {b:?}",
            if top { "top" } else { "bottom" }
        );
    }
    // Control: the sky above and the ground below differ by far more than the tolerance, so a
    // projection that swapped them (the ground drawn above the sky) would fail the check.
    let (top, bottom) = (
        luminance(&edge_centre(&wide_img, true)),
        luminance(&edge_centre(&wide_img, false)),
    );
    assert!(
        (top - bottom).abs() > 10.0 * TOLERANCE * top.max(bottom),
        "sky {top} and ground {bottom} must differ for the check to mean anything"
    );
}

/// Relative luminance difference allowed between two cameras seeing the same direction.
const TOLERANCE: f64 = 0.01;

#[test]
fn extreme_cameras_and_exposures_render_finite_images() {
    let Some(gpu) = common::gpu() else { return };
    let base = frame(32, 18);
    let mut cases: Vec<(String, Frame)> = Vec::new();
    for pitch in [limits::CAMERA_PITCH.min, limits::CAMERA_PITCH.max] {
        let mut f = base.clone();
        f.camera_pitch_deg = pitch as f32;
        cases.push((format!("pitch {pitch}°"), f));
    }
    // From the highest camera the limb is 30° below the horizon: look down at the planet.
    let mut f = base.clone();
    f.camera_altitude = limits::CAMERA_ALTITUDE.max as f32;
    f.camera_pitch_deg = -60.0;
    cases.push(("the highest camera, looking down".into(), f));
    let mut f = base.clone();
    f.sun_azimuth_deg = limits::SUN_AZIMUTH.max as f32;
    f.camera_yaw_deg = limits::CAMERA_YAW.min as f32;
    cases.push(("azimuth and yaw at their limits".into(), f));
    let mut f = base.clone();
    f.fov_deg = limits::FOV.min as f32;
    cases.push(("the narrowest field of view".into(), f));
    for (what, f) in &cases {
        let img = render(gpu, f);
        let light = mean_luminance(&img);
        println!("{what}: mean luminance {light:.3e}");
        assert!(
            light.is_finite() && light > 0.0,
            "{what}: a lit, finite image"
        );
        for exposure in [limits::EXPOSURE.min, limits::EXPOSURE.max] {
            let rgba = img.to_rgba8(exposure as f32);
            assert_eq!(rgba.len(), (img.width * img.height * 4) as usize);
        }
    }
}

#[test]
fn values_past_each_edge_are_refused_naming_the_field() {
    let Some(gpu) = common::gpu() else { return };
    let base = frame(16, 9);
    let past = |l: &Limit| [l.min - (l.max - l.min) * 0.01 - 1e-3, l.max * 1.01 + 1e-3];
    type Set = fn(&mut Frame, f64);
    let fields: [(&Limit, Set); 6] = [
        (&limits::SUN_ELEVATION, |f, v| {
            f.sun_elevation_deg = v as f32
        }),
        (&limits::CAMERA_ALTITUDE, |f, v| {
            f.camera_altitude = v as f32
        }),
        (&limits::CAMERA_PITCH, |f, v| f.camera_pitch_deg = v as f32),
        (&limits::FOV, |f, v| f.fov_deg = v as f32),
        (&limits::HAZE_DENSITY, |f, v| f.haze_density = v as f32),
        (&limits::TURBULENCE_DISPLACEMENT, |f, v| {
            f.turbulence_displacement = v as f32
        }),
    ];
    let mut r = Renderer::new(gpu, TextureSizes::default());
    for (limit, set) in fields {
        for v in past(limit).into_iter().chain([f64::NAN]) {
            let mut f = base.clone();
            set(&mut f, v);
            match r.render(&f) {
                Err(RuntimeError::Value(e)) => {
                    let msg = e.to_string();
                    assert!(msg.contains(&format!("Frame::{}", limit.field)), "{msg}");
                }
                other => panic!("{} = {v}: expected a refusal, got {other:?}", limit.field),
            }
        }
    }
}
