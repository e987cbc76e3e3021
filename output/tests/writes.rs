//! Files written through nimbus-output: all or nothing, readable like any file the user writes,
//! and never over a file Nimbus did not write unless forced.

use std::path::Path;

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
    nimbus_output::check_folder(std::path::Path::new(p), Overwrite::Force).err()
}

#[test]
fn a_failed_fill_leaves_the_previous_folder_untouched() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    replace_folder(&out, Overwrite::OwnOnly, |d| {
        std::fs::write(d.join("m"), "1").map_err(|e| OutputError::Io {
            action: "write",
            path: d.to_path_buf(),
            source: e,
        })
    })
    .expect("first");
    let err = replace_folder(&out, Overwrite::OwnOnly, |d| {
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

/// Writes one file `m` with `text` into the folder being filled.
fn fill_m(text: &'static str) -> impl FnOnce(&Path) -> Result<(), OutputError> {
    move |d| {
        std::fs::write(d.join("m"), text).map_err(|e| OutputError::Io {
            action: "write",
            path: d.to_path_buf(),
            source: e,
        })
    }
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A pid no process has: leftovers named after it are a dead run's.
fn dead_pid() -> Option<u32> {
    if !Path::new("/proc/self").exists() {
        // Without /proc a pid this large may be reported as invalid rather than dead.
        eprintln!("SKIPPED: no /proc to tell a dead process from an invalid pid");
        return None;
    }
    Some(u32::MAX - 7)
}

#[test]
fn a_run_killed_between_its_two_renames_is_finished_by_the_next() {
    // What a run killed after moving the old folder aside and before moving its complete new
    // folder in leaves: no destination, the old folder aside, the new one beside it.
    let Some(dead) = dead_pid() else { return };
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    replace_folder(&out, Overwrite::OwnOnly, fill_m("killed run's")).expect("first");
    let new = tmp.path().join(format!(".out.nimbus-new-{dead}"));
    std::fs::rename(&out, &new).expect("complete new folder");
    let aside = tmp.path().join(format!(".out.nimbus-old-{dead}"));
    std::fs::create_dir(&aside).expect("mkdir");
    std::fs::write(aside.join("m"), "old").expect("write");
    let seen = replace_folder(&out, Overwrite::OwnOnly, |d| {
        let seen = std::fs::read_to_string(out.join("m"));
        fill_m("new")(d)?;
        Ok::<_, OutputError>(seen.ok())
    })
    .expect("replaced");
    assert_eq!(
        seen.as_deref(),
        Some("killed run's"),
        "the dead run's complete output was moved in, not the old one put back"
    );
    assert_eq!(std::fs::read_to_string(out.join("m")).expect("read"), "new");
    assert_eq!(
        names_in(tmp.path()),
        vec!["out".to_string()],
        "the leftovers are gone"
    );
}

#[test]
fn a_folder_the_user_removed_after_a_killed_run_stays_removed() {
    // A run killed while deleting the folder it moved aside leaves part of the old folder; the
    // user then removes the output folder. The next run must not bring the old one back.
    let Some(dead) = dead_pid() else { return };
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let aside = tmp.path().join(format!(".out.nimbus-old-{dead}"));
    replace_folder(&aside, Overwrite::OwnOnly, fill_m("old, half deleted")).expect("aside");
    let half_new = tmp.path().join(format!(".out.nimbus-new-{dead}"));
    std::fs::create_dir(&half_new).expect("mkdir");
    std::fs::write(half_new.join("m"), "half").expect("write");
    let seen = replace_folder(&out, Overwrite::OwnOnly, |d| {
        let seen = out.exists();
        fill_m("new")(d)?;
        Ok::<_, OutputError>(seen)
    })
    .expect("written");
    assert!(!seen, "nothing was restored at the destination");
    assert_eq!(std::fs::read_to_string(out.join("m")).expect("read"), "new");
    assert_eq!(names_in(tmp.path()), vec!["out".to_string()]);
}

#[test]
fn a_folder_holding_a_file_named_like_nimbus_index_is_the_users() {
    // The user's own gallery.md (and a photo) in the destination: a name proves nothing.
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("gallery");
    std::fs::create_dir(&out).expect("mkdir");
    std::fs::write(out.join("gallery.md"), "my notes").expect("write");
    std::fs::write(out.join("holiday.jpg"), "photo").expect("write");
    let err = replace_folder(&out, Overwrite::OwnOnly, fill_m("x")).expect_err("refused");
    assert!(matches!(err, OutputError::NotOurs { .. }), "{err}");
    assert!(err.to_string().contains("nimbus-output.txt"), "{err}");
    assert_eq!(names_in(&out), vec!["gallery.md", "holiday.jpg"]);
    assert_eq!(names_in(tmp.path()), vec!["gallery".to_string()]);
}

#[test]
fn a_file_added_to_or_edited_in_a_nimbus_folder_makes_it_the_users() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    replace_folder(&out, Overwrite::OwnOnly, fill_m("1")).expect("first");
    assert!(out.join(nimbus_output::OWNERSHIP_FILE).is_file());
    replace_folder(&out, Overwrite::OwnOnly, fill_m("2")).expect("its own, again");
    std::fs::create_dir(out.join("mine")).expect("mkdir");
    std::fs::write(out.join("mine/notes.txt"), "mine").expect("write");
    let err = replace_folder(&out, Overwrite::OwnOnly, fill_m("3")).expect_err("refused");
    assert!(err.to_string().contains("mine/notes.txt"), "{err}");
    assert_eq!(std::fs::read_to_string(out.join("m")).expect("read"), "2");
    std::fs::remove_dir_all(out.join("mine")).expect("rm");
    std::fs::write(out.join("m"), "edited").expect("edit");
    let err = replace_folder(&out, Overwrite::OwnOnly, fill_m("3")).expect_err("refused");
    assert!(err.to_string().contains("m was changed"), "{err}");
    // Removing one of Nimbus's own files takes nothing of the user's.
    std::fs::remove_file(out.join("m")).expect("rm");
    replace_folder(&out, Overwrite::OwnOnly, fill_m("4")).expect("replaced");
    replace_folder(&out, Overwrite::Force, fill_m("5")).expect("forced");
}

#[cfg(unix)]
#[test]
fn links_fifos_and_files_in_the_way_are_refused_up_front() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    let fifo = dir.join("pipe.png");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    assert!(made, "mkfifo");
    // Reading a FIFO for a signature would block: it is refused by its kind, at once.
    let err = check_file(&fifo, Signature::Png, Overwrite::OwnOnly).expect_err("fifo");
    assert!(matches!(err, OutputError::NotPlain { .. }), "{err}");
    assert!(err.to_string().contains("FIFO"), "{err}");
    let err = check_file(&fifo, Signature::Png, Overwrite::Force).expect_err("forced fifo");
    assert!(matches!(err, OutputError::NotPlain { .. }), "{err}");
    let err = nimbus_output::check_folder(&fifo, Overwrite::Force).expect_err("fifo folder");
    assert!(matches!(err, OutputError::NotPlain { .. }), "{err}");

    let dangling = dir.join("dangling.png");
    std::os::unix::fs::symlink(dir.join("nowhere.png"), &dangling).expect("link");
    let err = write_file(&dangling, Signature::Png, Overwrite::OwnOnly, &png()).expect_err("x");
    assert!(matches!(err, OutputError::IsLink { .. }), "{err}");
    assert!(err.to_string().contains("does not exist"), "{err}");
    let looped = dir.join("loop");
    std::os::unix::fs::symlink(&looped, &looped).expect("loop");
    let err = check_file(&looped, Signature::Png, Overwrite::Force).expect_err("loop");
    assert!(err.to_string().contains("loop"), "{err}");
    let err = nimbus_output::check_folder(&looped, Overwrite::Force).expect_err("loop folder");
    assert!(matches!(err, OutputError::IsLink { .. }), "{err}");
    let err = check_file(&looped.join("x.png"), Signature::Png, Overwrite::Force).expect_err("in");
    assert!(err.to_string().contains("symbolic links"), "{err}");

    let file = dir.join("f");
    std::fs::write(&file, "user's").expect("write");
    let err = check_file(&file.join("x.png"), Signature::Png, Overwrite::Force).expect_err("f/x");
    assert!(matches!(err, OutputError::NotAFolder { .. }), "{err}");
    let err = nimbus_output::check_folder(&file.join("a/b"), Overwrite::Force).expect_err("f/a/b");
    assert!(matches!(err, OutputError::NotAFolder { .. }), "{err}");
    assert_eq!(std::fs::read_to_string(&file).expect("read"), "user's");
    let err = check_file(&dir.join("none/x.png"), Signature::Png, Overwrite::Force).expect_err("");
    assert!(matches!(err, OutputError::NoFolder { .. }), "{err}");
}
