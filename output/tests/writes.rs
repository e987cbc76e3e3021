//! Files written through nimbus-output: all or nothing, readable like any file the user writes,
//! and never over a file Nimbus did not write unless forced.

use nimbus_output::{
    OutputError, Overwrite, Signature, check_file, replace_folder, signed_png, write_file,
};

fn png() -> Vec<u8> {
    signed_png(2, 1, &[255, 0, 0, 255, 0, 255, 0, 255]).expect("encode")
}

#[test]
fn nimbus_replaces_its_own_png_and_refuses_anyone_elses_unless_forced() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let ours = tmp.path().join("ours.png");
    write_file(&ours, Signature::Png, Overwrite::OwnOnly, &png()).expect("first");
    write_file(&ours, Signature::Png, Overwrite::OwnOnly, &png()).expect("ours again");
    let theirs = tmp.path().join("theirs.png");
    std::fs::write(&theirs, b"\x89PNG\r\n\x1a\nsomeone else's").expect("write");
    let err = write_file(&theirs, Signature::Png, Overwrite::OwnOnly, &png()).expect_err("refused");
    assert!(matches!(err, OutputError::NotOurs { .. }), "{err}");
    assert_eq!(
        std::fs::read(&theirs).expect("read"),
        b"\x89PNG\r\n\x1a\nsomeone else's"
    );
    write_file(&theirs, Signature::Png, Overwrite::Force, &png()).expect("forced");
    assert_eq!(std::fs::read(&theirs).expect("read"), png());
    // Nothing but the two files is left in the folder.
    let names: Vec<_> = std::fs::read_dir(tmp.path())
        .expect("read")
        .flatten()
        .collect();
    assert_eq!(names.len(), 2);
}

#[cfg(unix)]
#[test]
fn outputs_are_as_readable_as_any_file_the_user_writes() {
    use std::os::unix::fs::PermissionsExt;
    let tmp = tempfile::tempdir().expect("tempdir");
    let plain = tmp.path().join("plain.txt");
    std::fs::write(&plain, "x").expect("write");
    let ours = tmp.path().join("report.md");
    write_file(
        &ours,
        Signature::FirstLine("marker"),
        Overwrite::OwnOnly,
        b"marker\n",
    )
    .expect("write");
    let mode =
        |p: &std::path::Path| std::fs::metadata(p).expect("meta").permissions().mode() & 0o777;
    assert_eq!(mode(&ours), mode(&plain), "not tempfile's private 0600");
}

#[test]
fn a_folder_without_a_name_is_refused_before_anything_happens() {
    let err = check_folder_named(".");
    assert!(matches!(err, Some(OutputError::NoName { .. })), "{err:?}");
    let err = check_folder_named("..");
    assert!(matches!(err, Some(OutputError::NoName { .. })), "{err:?}");
}

fn check_folder_named(p: &str) -> Option<OutputError> {
    nimbus_output::check_folder(std::path::Path::new(p), "marker", Overwrite::Force).err()
}

#[test]
fn a_failed_fill_leaves_the_previous_folder_untouched() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    replace_folder(&out, "m", Overwrite::OwnOnly, |d| {
        std::fs::write(d.join("m"), "1").map_err(|e| OutputError::Io {
            action: "write",
            path: d.to_path_buf(),
            source: e,
        })
    })
    .expect("first");
    let err = replace_folder(&out, "m", Overwrite::OwnOnly, |d| {
        std::fs::write(d.join("m"), "2").expect("write");
        Err::<(), _>(OutputError::IsFile {
            path: d.to_path_buf(),
        })
    });
    assert!(err.is_err());
    assert_eq!(std::fs::read_to_string(out.join("m")).expect("read"), "1");
    let left: Vec<_> = std::fs::read_dir(tmp.path())
        .expect("read")
        .flatten()
        .collect();
    assert_eq!(left.len(), 1, "no temporary folder left");
    // The checked path is fine for a file too.
    check_file(
        &tmp.path().join("new.png"),
        Signature::Png,
        Overwrite::OwnOnly,
    )
    .expect("ok");
}

#[test]
fn a_run_killed_between_its_two_renames_is_repaired_by_the_next() {
    // What a run killed after moving the old folder aside and before moving the new one in
    // leaves: no destination, the complete old folder aside, and its new folder beside it.
    if !std::path::Path::new("/proc/self").exists() {
        // Without /proc a pid this large may be reported as invalid rather than dead.
        eprintln!("SKIPPED: no /proc to tell a dead process from an invalid pid");
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let dead = u32::MAX - 7; // no such process
    let aside = tmp.path().join(format!(".out.nimbus-old-{dead}"));
    let new = tmp.path().join(format!(".out.nimbus-new-{dead}"));
    std::fs::create_dir(&aside).expect("mkdir");
    std::fs::write(aside.join("m"), "old").expect("write");
    std::fs::create_dir(&new).expect("mkdir");
    std::fs::write(new.join("half"), "x").expect("write");
    let seen = replace_folder(&out, "m", Overwrite::OwnOnly, |d| {
        // The old output is back in place while the new one is written.
        let seen = std::fs::read_to_string(out.join("m"));
        std::fs::write(d.join("m"), "new").map_err(|e| OutputError::Io {
            action: "write",
            path: d.to_path_buf(),
            source: e,
        })?;
        Ok::<_, OutputError>(seen.ok())
    })
    .expect("replaced");
    assert_eq!(
        seen.as_deref(),
        Some("old"),
        "restored before the new one was written"
    );
    assert_eq!(std::fs::read_to_string(out.join("m")).expect("read"), "new");
    let left: Vec<String> = std::fs::read_dir(tmp.path())
        .expect("read")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        left,
        vec!["out".to_string()],
        "the dead run's leftovers are gone"
    );
}
