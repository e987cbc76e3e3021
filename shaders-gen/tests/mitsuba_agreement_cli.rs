//! `tools/mitsuba_agreement.py` at a tiny size: `nimbus export-density --mitsuba` and
//! `nimbus render --verification --format exr` against Mitsuba 3 (scalar_rgb) on the same
//! clouds. The full-size figures are in the README; here the check is that the two renderers
//! agree about as well as Mitsuba agrees with itself, and that a 10 % error in the light (the
//! control) is seen.

mod common;

use std::path::Path;
use std::process::Command;

use common::{have_gpu, text};

/// Mitsuba 3 (scalar_rgb), the OpenEXR bindings and numpy.
fn have_mitsuba() -> bool {
    common::have_python(
        "import mitsuba, OpenEXR, numpy; mitsuba.set_variant('scalar_rgb')",
        "Mitsuba 3, OpenEXR and numpy",
    )
}

/// Runs the agreement script at a tiny size with `extra` arguments; returns its report.
fn agreement(sun_scale: f32, extra: &[&str]) -> serde_json::Value {
    let tmp = tempfile::tempdir().expect("tempdir");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let o = Command::new("python3")
        .arg(root.join("tools/mitsuba_agreement.py"))
        .args(["--nimbus", env!("CARGO_BIN_EXE_nimbus")])
        .args(["--voxel", "20", "--filter", "1", "--frames", "4"])
        .args(["--sun-scale", &sun_scale.to_string()])
        .args(extra)
        .arg("--out")
        .arg(tmp.path())
        .output()
        .expect("run python3");
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{stdout}\n{}", text(&o.stderr));
    println!("{stdout}");
    serde_json::from_slice(&std::fs::read(tmp.path().join("agreement.json")).expect("report"))
        .expect("json")
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().expect("a number")
}

#[test]
fn nimbus_and_mitsuba_agree_on_single_scattering_and_see_a_wrong_sun() {
    if !have_gpu() || !have_mitsuba() {
        return;
    }
    let r = agreement(1.0, &["--resolution", "48x27", "--spp", "128"]);
    let ss = &r["single_scattering"];
    let (ours, floor) = (&ss["nimbus_vs_mitsuba"], &ss["noise_floor"]);
    assert!(
        f(&r["cloudy_pixels"]) > 200.0,
        "the view must see clouds: {r}"
    );
    // The image means agree (this coarse grid and 128 spp leave a few per cent).
    assert!((f(&ss["mean_ratio"]) - 1.0).abs() < 0.04, "{ss}");
    // Per pixel, Nimbus is about as close to Mitsuba as Mitsuba is to itself.
    assert!(
        f(&ours["mean_abs"]) < 1.3 * f(&floor["mean_abs"]) + 0.02,
        "{ss}"
    );
    let t = &r["transmittance"]["nimbus_vs_mitsuba"];
    assert!(
        f(&t["mean_signed"]).abs() < 0.01 && f(&t["mean_abs"]) < 0.03,
        "{t}"
    );

    // The control: Mitsuba's sun 10 % dimmer must show.
    let dim = agreement(0.9, &["--resolution", "48x27", "--spp", "128"]);
    let ratio = f(&dim["single_scattering"]["mean_ratio"]);
    assert!(
        (ratio - 1.0 / 0.9).abs() < 0.04 && ratio > f(&ss["mean_ratio"]) + 0.06,
        "a 10 % dimmer sun in Mitsuba gave a ratio of {ratio}"
    );
}

/// Multiple scattering in an overcast deck seen from above (optical depth ~30), where the
/// octaves lose two thirds of the light: the diffusion, the presets' model, holds against
/// Mitsuba's full path tracer, and the octaves are the control that must fail the same bar.
#[test]
fn the_diffusion_holds_in_a_thick_deck_where_the_octaves_fail() {
    if !have_gpu() || !have_mitsuba() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let deck = root.join("examples/verification/deck-above.toml");
    let r = agreement(
        1.0,
        &[
            "--scene",
            deck.to_str().expect("a UTF-8 path"),
            "--resolution",
            "24x14",
            "--spp",
            "16",
            "--multiple-scattering",
            "--ms-spp",
            "32",
        ],
    );
    let ms = &r["multiple_scattering"];
    let (diffusion, octaves) = (f(&ms["diffusion"]["ratio"]), f(&ms["octaves"]["ratio"]));
    println!("deck from above: diffusion / Mitsuba {diffusion:.3}, octaves / Mitsuba {octaves:.3}");
    // ±10 % (the bar) plus this size's noise (Mitsuba's own two renders differ by a
    // few per cent at 32 spp); measured 0.98 at 48x27 and 128 spp.
    let bar = 0.1 + 3.0 * f(&ms["noise_floor"]);
    assert!((diffusion - 1.0).abs() < bar, "diffusion: {ms}");
    assert!((octaves - 1.0).abs() > bar, "the octaves pass too: {ms}");
}

#[test]
fn a_view_with_no_cloud_is_refused_before_mitsuba_renders() {
    if !have_mitsuba() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let scenes = tmp.path().join("scenes");
    std::fs::create_dir(&scenes).expect("mkdir");
    let clear = scenes.join("clear.toml");
    std::fs::write(
        &clear,
        "name = \"clear\"\ndescription = \"x\"\ngenus = \"cumulus\"\ncoverage = 0.0\n",
    )
    .expect("write");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let o = Command::new("python3")
        .arg(root.join("tools/mitsuba_agreement.py"))
        .args(["--nimbus", env!("CARGO_BIN_EXE_nimbus")])
        .arg("--scene")
        .arg(&clear)
        .args(["--resolution", "48x27", "--voxel", "200", "--filter", "1"])
        .arg("--out")
        .arg(tmp.path().join("out"))
        .output()
        .expect("run python3");
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{}\n{err}", text(&o.stdout));
    assert!(
        err.contains("clear.toml") && err.contains("no cloud"),
        "{err}"
    );
    // Refused before Mitsuba renders (the minutes of the comparison): no report, no times.
    assert!(!tmp.path().join("out/agreement.json").exists());
    assert!(!text(&o.stdout).contains("times:"), "{}", text(&o.stdout));
}
