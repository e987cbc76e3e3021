//! `nimbus tradeoff` and `nimbus export-density` as a user runs them: a report, a plot and
//! reference images from one command; a Mitsuba volume; and clear errors on bad input.

mod common;

use common::{examples, have_gpu, nimbus, text};

#[test]
fn tradeoff_writes_a_table_a_plot_and_the_references() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let views = tmp.path().join("views");
    std::fs::create_dir(&views).expect("views");
    std::fs::copy(
        examples("views/below-deck-noon.toml"),
        views.join("below-deck-noon.toml"),
    )
    .expect("copy view");
    let out = tmp.path().join("out");
    let o = nimbus(&[
        "tradeoff",
        "--views",
        views.to_str().expect("utf8"),
        "--rows",
        "low,high",
        "-r",
        "48x27",
        "-f",
        "1",
        "--reference-frames",
        "2",
        "-n",
        "1",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{stdout}\n{}", text(&o.stderr));
    let md = std::fs::read_to_string(out.join("tradeoff.md")).expect("report");
    for want in [
        "| **low** |",
        "| **high** |",
        "| reference |",
        "reference, another seed",
        "## Presets and the Pareto front",
        "Adapter: ",
    ] {
        assert!(md.contains(want), "report lacks `{want}`:\n{md}");
    }
    // Low is the fastest row, so nothing can beat it: it is on the front.
    assert!(md.contains("- **low** is on the front"), "{md}");
    let svg = std::fs::read_to_string(out.join("tradeoff.svg")).expect("plot");
    assert!(
        svg.starts_with("<svg")
            && ["Pareto front", "low", "high"]
                .iter()
                .all(|w| svg.contains(w)),
        "{svg}"
    );
    assert!(out.join("reference-below-deck-noon.png").is_file());
}

#[test]
fn tradeoff_refuses_unknown_rows_and_missing_views() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = nimbus(&[
        "tradeoff",
        "--rows",
        "low,medium-rare",
        "-o",
        tmp.path().to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(
        !o.status.success()
            && err.contains("unknown row `medium-rare`")
            && err.contains("high - shadows"),
        "{err}"
    );
    let o = nimbus(&[
        "tradeoff",
        "--views",
        tmp.path().join("nowhere").to_str().expect("utf8"),
        "-o",
        tmp.path().join("out").to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(
        !o.status.success() && err.contains("views folder") && err.contains("nowhere"),
        "{err}"
    );
    assert!(
        !tmp.path().join("out").exists(),
        "nothing may be written on error"
    );
}

#[test]
fn export_density_writes_a_mitsuba_volume_and_refuses_bad_regions() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("clouds.vol");
    let o = nimbus(&[
        "export-density",
        &examples("scenes/default.toml"),
        "--size",
        "16,4,16",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{stdout}\n{}", text(&o.stderr));
    let b = std::fs::read(&out).expect("volume");
    assert_eq!(&b[..4], b"VOL\x03");
    assert_eq!(b.len(), 48 + 4 * 16 * 4 * 16);
    assert!(
        stdout.contains("gridvolume") && stdout.contains("voxels cloudy"),
        "{stdout}"
    );
    let bad = tmp.path().join("bad.vol");
    let o = nimbus(&[
        "export-density",
        &examples("scenes/default.toml"),
        "--region",
        "0,5000,0,100,-1,100",
        "-o",
        bad.to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(
        !o.status.success() && err.contains("density export: region"),
        "{err}"
    );
    assert!(!err.contains("panicked") && !bad.exists(), "{err}");
}
