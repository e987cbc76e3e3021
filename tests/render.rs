//! The wgpu runtime renders a cloud variant: finite pixels, clouds present, deterministic for a
//! fixed frame, and pipelines reused from the cache when a preset comes back.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn frame(quality: Quality) -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        quality,
        96,
        54,
    )
}

#[test]
fn renders_clouds_deterministically_and_caches_pipelines() {
    let Some(gpu) = common::gpu() else { return };
    let sizes = TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    };
    let mut r = Renderer::new(gpu, sizes);
    let a = r.render(&frame(Quality::Low)).expect("render");
    assert_eq!(a.pixels.len(), 96 * 54);
    assert!(
        a.pixels.iter().flatten().all(|v| v.is_finite()),
        "non-finite pixel"
    );
    assert!(
        a.pixels.iter().all(|p| (0.0..=1.0).contains(&p[3])),
        "alpha outside [0, 1]"
    );
    let cloudy = a.pixels.iter().filter(|p| p[3] > 0.05).count();
    println!(
        "{cloudy} of {} pixels show cloud, on {}",
        a.pixels.len(),
        gpu.info()
    );
    assert!(cloudy > 20, "no clouds in the frame");
    let b = r.render(&frame(Quality::Low)).expect("render again");
    assert_eq!(a.pixels, b.pixels, "same frame, same pixels");
    // Low: the shadow atlas and the clouds.
    assert_eq!(r.pipeline_count(), 2, "{:?}", r.stats().pipelines);
    r.render(&frame(Quality::Medium)).expect("medium");
    assert_eq!(r.pipeline_count(), 4, "{:?}", r.stats().pipelines);
    r.render(&frame(Quality::Low)).expect("low again");
    assert_eq!(
        r.pipeline_count(),
        4,
        "switching back reuses the cached pipelines"
    );
}

#[test]
fn a_bad_resolution_is_an_error_not_a_panic() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(
        gpu,
        TextureSizes {
            weather: 16,
            shape: 8,
            detail: 8,
            turbulence: 8,
        },
    );
    for (w, h) in [(0, 90), (100_000, 90)] {
        let mut f = frame(Quality::Low);
        f.width = w;
        f.height = h;
        let err = r.render(&f).expect_err("refused");
        assert!(err.to_string().contains(&format!("{w}x{h}")), "{err}");
    }
}
