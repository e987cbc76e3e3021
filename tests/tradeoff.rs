//! The accuracy–time study's parts on a real adapter: the instrumented variant counts density
//! samples (more for finer presets, far more for the reference), and the error metrics see a
//! worse image as worse.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Quality, load_scene};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};
use nimbus_testkit::metrics::image_error;
use nimbus_testkit::tradeoff::{StudyOptions, measure, reference, rows, samples_per_pixel};

fn view() -> Frame {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let lib = CloudLibrary::load(&root).expect("data");
    let scene = load_scene(&root.join("views/below-deck-noon.toml")).expect("view");
    Frame::from_scene(&scene, lib.genus(&scene.genus).expect("genus"), 48, 27)
}

fn sizes() -> TextureSizes {
    TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    }
}

#[test]
fn instrumented_variant_counts_more_samples_for_finer_presets() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, sizes());
    let mut counts = Vec::new();
    for q in [Quality::Low, Quality::High, Quality::Reference] {
        let mut f = view();
        f.quality = q;
        f.features = q.features();
        counts.push(samples_per_pixel(&mut r, &f).expect("count"));
    }
    println!(
        "density samples per pixel: low {}, high {}, reference {}",
        counts[0], counts[1], counts[2]
    );
    assert!(counts[0] > 0.0, "the view must meet clouds");
    assert!(
        counts[0] < counts[1] && counts[1] * 5.0 < counts[2],
        "{counts:?}"
    );
    // The counter does not change the picture's colour.
    let f = view();
    let plain = r.render(&f).expect("plain");
    let mut g = f.clone();
    g.output = nimbus_clouds::PixelOutput::Samples;
    let counted = r.render(&g).expect("counted");
    assert!(
        plain
            .pixels
            .iter()
            .zip(&counted.pixels)
            .all(|(a, b)| a[..3] == b[..3])
    );
}

#[test]
fn error_against_the_reference_ranks_presets() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, sizes());
    let options = StudyOptions {
        frames: 2,
        reference_frames: 4,
        exposure: 8.0,
        repeats: 3,
    };
    let v = view();
    let reference = reference(&mut r, &v, &options).expect("reference");
    let same = image_error(&reference.image, &reference.image, 8.0).expect("self");
    assert!(same.rmse == 0.0 && same.psnr_db.is_infinite() && (same.ssim - 1.0).abs() < 1e-9);
    assert!(same.flip == 0.0 && same.linear == 0.0);
    let specs = rows();
    let get = |label: &str| {
        specs
            .iter()
            .find(|s| s.label == label)
            .expect("row")
            .clone()
    };
    let (high, _) = measure(&mut r, "v", &v, &get("high"), &reference, &options).expect("high");
    let (flat, _) = measure(
        &mut r,
        "v",
        &v,
        &get("high - multiple-scattering"),
        &reference,
        &options,
    )
    .expect("one octave");
    println!("high: {:?}\none octave: {:?}", high.error, flat.error);
    assert!(high.error.rmse > 0.0 && high.ms_per_frame > 0.0);
    assert!(
        flat.error.rmse > high.error.rmse
            && flat.error.ssim < high.error.ssim
            && flat.error.flip > high.error.flip,
        "dropping multiple scattering must cost accuracy"
    );
    // One octave loses light: the luminance ratio shows the darkening, and it is bias (more
    // frames would not bring it back), not noise.
    assert!(
        flat.error.luminance_ratio < high.error.luminance_ratio - 0.05,
        "one octave must read darker: {} against {}",
        flat.error.luminance_ratio,
        high.error.luminance_ratio
    );
    assert!(flat.split.bias > high.split.bias && flat.split.bias > flat.split.noise);
    assert_eq!(flat.split.seeds, 3);
}
