//! `nimbus gallery` as a user runs it: every genus of the data folder's `gallery/` scenes
//! rendered, lowest first, with a Markdown grid and a contact sheet; a folder Nimbus did not
//! write is left alone; a data folder without gallery scenes is refused.

mod common;

use common::{examples, have_gpu, nimbus, refuses_a_foreign_folder, text};

#[test]
fn gallery_renders_every_genus_with_an_index_and_a_contact_sheet() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("genera");
    let args = ["gallery", "-r", "48x27", "-f", "1", "-o"];
    let o = nimbus(&[&args[..], &[out.to_str().expect("utf8")]].concat());
    assert!(
        o.status.success(),
        "{}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    let genera = [
        "stratus",
        "nimbostratus",
        "stratocumulus",
        "cumulonimbus",
        "cumulus",
        "altocumulus",
        "altostratus",
        "cirrocumulus",
        "cirrostratus",
        "cirrus",
    ];
    let index = std::fs::read_to_string(out.join("gallery.md")).expect("index");
    // Every genus once, lowest cloud base first (cirrostratus and cirrus share 8 km: by name).
    let at: Vec<usize> = genera
        .iter()
        .map(|g| {
            index
                .find(&format!("![{g}]({g}.png)"))
                .unwrap_or_else(|| panic!("{g} missing from the index:\n{index}"))
        })
        .collect();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "order:\n{index}");
    for g in genera {
        let img = image::open(out.join(format!("{g}.png")))
            .expect("png")
            .to_rgb8();
        assert_eq!(img.dimensions(), (48, 27), "{g}");
        let first = img.get_pixel(0, 0);
        assert!(img.pixels().any(|p| p != first), "{g}: a flat image");
    }
    // Three columns, four rows, 4 px between tiles.
    let sheet = image::open(out.join("contact-sheet.png")).expect("sheet");
    assert_eq!(
        (sheet.width(), sheet.height()),
        (3 * 52 - 4, 4 * 31 - 4),
        "contact sheet size"
    );

    // A folder the user made is not replaced without --force, and is left as it was.
    refuses_a_foreign_folder(&args, tmp.path());
}

#[test]
fn a_data_folder_without_gallery_scenes_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let data = tmp.path().join("data");
    std::fs::create_dir_all(data.join("genera")).expect("genera");
    std::fs::create_dir_all(data.join("gallery")).expect("gallery");
    std::fs::copy(
        examples("genera/cumulus.toml"),
        data.join("genera/cumulus.toml"),
    )
    .expect("copy");
    let out = tmp.path().join("out");
    let o = nimbus(&[
        "--data",
        data.to_str().expect("utf8"),
        "gallery",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    let err = text(&o.stderr);
    assert!(!o.status.success(), "an empty gallery folder was accepted");
    assert!(
        err.contains("gallery scene") && err.contains("gallery"),
        "{err}"
    );
    assert!(!out.exists(), "something was written");
}
