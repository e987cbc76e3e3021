//! One test per failure found by trying the newer commands (`gallery`, `animate`, engine
//! packages, timelines, EXR, `export-density --mitsuba`) as a hostile user would (issue 29):
//! no panic at any accepted size, no hang, no folder or file of the user's lost, one meaning
//! per scene, and messages that name where the value came from. The output crate's own tests
//! (`output/tests/writes.rs`) cover the kills between renames.

mod common;

use std::io::Read;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{examples, have_gpu, text, tree};

/// Runs nimbus in `dir` with `env` set and `unset` removed.
fn run_in(dir: &Path, args: &[&str], env: &[(&str, &str)], unset: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_nimbus"));
    c.args(args).current_dir(dir).env_remove("NIMBUS_DATA");
    for k in unset {
        c.env_remove(k);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run nimbus")
}

fn run(dir: &Path, args: &[&str]) -> Output {
    run_in(dir, args, &[], &[])
}

/// Asserts a refusal: a failure exit (not a panic's 101) whose stderr has every `wants`.
fn refused(o: &Output, wants: &[&str]) -> String {
    let err = text(&o.stderr);
    assert!(!o.status.success(), "must fail; stderr: {err}");
    assert_eq!(o.status.code(), Some(1), "not a clean refusal: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for w in wants {
        assert!(err.contains(w), "stderr lacks `{w}`: {err}");
    }
    err
}

fn write(dir: &Path, rel: &str, text: &str) {
    let p = dir.join(rel);
    std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
    std::fs::write(p, text).expect("write");
}

/// Names in `dir` that a run left behind (temporary files and folders of Nimbus's).
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".nimbus-") || n.starts_with(".nimbus"))
        .collect()
}

#[test]
fn a_closed_stdout_ends_the_log_not_the_command() {
    // `nimbus list | head -0`: the reader is gone before the first line. Rust ignores SIGPIPE,
    // so every `println!` would panic ("failed printing to stdout: Broken pipe", exit 101).
    let tmp = tempfile::tempdir().expect("tempdir");
    let a = tmp.path().join("a");
    let b = tmp.path().join("b");
    for (dir, name) in [(&a, "preview-hg"), (&b, "preview")] {
        let o = run(
            tmp.path(),
            &["emit", name, "-o", dir.to_str().expect("utf8")],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let diff = ["diff", a.to_str().expect("utf8"), b.to_str().expect("utf8")];
    let commands: [&[&str]; 5] = [
        &["list"],
        &["check", "preview"],
        &["bench", "-i", "1"],
        &diff,
        &["explain", &examples("scenes/day-with-wind.toml")],
    ];
    for args in commands {
        let mut child = Command::new(env!("CARGO_BIN_EXE_nimbus"))
            .args(args)
            .current_dir(tmp.path())
            .env_remove("NIMBUS_DATA")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        drop(child.stdout.take());
        let mut err = String::new();
        if let Some(mut e) = child.stderr.take() {
            e.read_to_string(&mut err).expect("stderr");
        }
        let status = child.wait().expect("wait");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_ne!(status.code(), Some(101), "{args:?}: {err}");
        // `diff` of two different folders reports the difference by its exit code.
        if args[0] != "diff" {
            assert!(status.success(), "{args:?}: {err}");
        }
    }
}

#[test]
fn a_picture_larger_than_the_device_holds_is_refused_before_any_work() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run(
        tmp.path(),
        &["render", "-r", "16384x16384", "-o", "big.png"],
    );
    let limits = nimbus_runtime::Gpu::new().expect("gpu").device().limits();
    if limits.max_buffer_size >= 16384 * 16384 * 16 {
        // A device that holds it renders it; this one is not the case to check.
        eprintln!("SKIPPED: this adapter holds a 16384² readback; nothing to refuse");
        return;
    }
    refused(&o, &["16384x16384", "per buffer", "largest picture"]);
    assert!(!tmp.path().join("big.png").exists());
    // animate refuses the same size before it makes its folder: no hidden half-written folder.
    let o = run(
        tmp.path(),
        &[
            "animate",
            &examples("scenes/day-with-wind.toml"),
            "--to",
            "0",
            "-r",
            "16384x16384",
            "-o",
            "anim",
        ],
    );
    refused(&o, &["16384x16384", "largest picture"]);
    assert!(!tmp.path().join("anim").exists());
    assert!(
        leftovers(tmp.path()).is_empty(),
        "{:?}",
        leftovers(tmp.path())
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_as_output_is_refused_at_once() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let fifo = tmp.path().join("pipe.png");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    assert!(made, "mkfifo");
    let f = fifo.to_str().expect("utf8");
    let commands: [&[&str]; 5] = [
        &["render", "-o", f, "-r", "16x9"],
        &["emit", "preview-hg", "-o", f],
        &["export-density", "-o", f],
        &["gallery", "-o", f],
        &["tradeoff", "-o", f],
    ];
    for args in commands {
        // Opening a FIFO to read a signature would block forever: bounded by a deadline here.
        let mut child = Command::new(env!("CARGO_BIN_EXE_nimbus"))
            .args(args)
            .current_dir(tmp.path())
            .env_remove("NIMBUS_DATA")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        let deadline = Instant::now() + Duration::from_secs(120);
        let status = loop {
            if let Some(s) = child.try_wait().expect("wait") {
                break s;
            }
            if Instant::now() > deadline {
                let _ = child.kill();
                panic!("{args:?} hangs on a FIFO");
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let mut err = String::new();
        if let Some(mut e) = child.stderr.take() {
            e.read_to_string(&mut err).expect("stderr");
        }
        assert_eq!(status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains("FIFO") || err.contains("is a file"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_users_folder_with_a_gallery_md_or_an_animation_json_is_left_alone() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(tmp.path(), "pictures/gallery.md", "# my gallery\n");
    write(tmp.path(), "pictures/holiday.jpg", "a photo");
    write(tmp.path(), "clips/animation.json", "{\"mine\": true}");
    write(tmp.path(), "clips/notes.txt", "my notes");
    let before = (
        tree(&tmp.path().join("pictures")),
        tree(&tmp.path().join("clips")),
    );
    let o = run(tmp.path(), &["gallery", "-o", "pictures"]);
    refused(&o, &["pictures", "nimbus-output.txt", "--force"]);
    let scene = examples("scenes/day-with-wind.toml");
    let o = run(tmp.path(), &["animate", &scene, "--to", "0", "-o", "clips"]);
    refused(&o, &["clips", "nimbus-output.txt", "--force"]);
    // A Nimbus folder the user added a file to is theirs too.
    let o = run(tmp.path(), &["emit", "preview-hg", "-o", "shaders"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    write(tmp.path(), "shaders/notes.txt", "mine");
    let o = run(tmp.path(), &["emit", "preview-hg", "-o", "shaders"]);
    refused(&o, &["notes.txt", "Nimbus did not write"]);
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("shaders/notes.txt")).expect("read"),
        "mine"
    );
    let after = (
        tree(&tmp.path().join("pictures")),
        tree(&tmp.path().join("clips")),
    );
    assert!(before == after, "the user's folders changed");
}

/// A scene whose clock puts the sun below the horizon at second 0: night.
const NIGHT: &str = "name = \"night\"\ndescription = \"x\"\ngenus = \"cumulus\"\n\
    quality = \"high\"\nsun_elevation_deg = 45.0\n\n[clock]\nstart = \"2026-06-21T01:00\"\n\
    utc_offset_hours = 2.0\nlatitude_deg = 47.37\nlongitude_deg = 8.54\n";

/// The value after `prefix` on the first line of `out` holding it.
fn line_value(out: &str, prefix: &str) -> Option<String> {
    out.lines()
        .find_map(|l| l.trim_start().strip_prefix(prefix))
        .map(|v| v.trim().to_string())
}

#[test]
fn a_clock_scene_means_one_sun_in_every_command() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // The shipped day-with-wind: the clock's sun (59.8°), not the file's default 45°.
    let o = run(
        tmp.path(),
        &["explain", &examples("scenes/day-with-wind.toml")],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("sun 59.8°"), "{}", text(&o.stdout));
    // At night the clock's sun is down: no light shafts, whatever sun_elevation_deg says.
    write(tmp.path(), "scenes/night.toml", NIGHT);
    let scene = tmp.path().join("scenes/night.toml");
    let scene = scene.to_str().expect("utf8");
    let o = run(tmp.path(), &["explain", scene]);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let shafts = out
        .lines()
        .find(|l| l.trim_start().starts_with("light-shafts"))
        .expect("a light-shafts line");
    assert!(shafts.contains(" out "), "{shafts}");
    let explained = line_value(&out, "shader:").expect("explain names the shader");
    // emit --scene writes the shader explain names (and render draws, below).
    let o = run(
        tmp.path(),
        &["emit", "--scene", scene, "-t", "wgsl", "-o", "e"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let emitted: Vec<String> = std::fs::read_dir(tmp.path().join("e"))
        .expect("read")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("clouds-") && n.ends_with(".wgsl"))
        .collect();
    assert_eq!(emitted, vec![format!("{explained}.wgsl")]);
    if have_gpu() {
        let o = run(tmp.path(), &["render", scene, "-r", "16x9", "-o", "n.png"]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        assert_eq!(
            line_value(&text(&o.stdout), "shader:").as_deref(),
            Some(explained.as_str())
        );
    }
}

#[test]
fn an_unknown_weather_genus_is_named_with_its_file_by_every_command() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write(
        tmp.path(),
        "scenes/w.toml",
        "name = \"w\"\ndescription = \"x\"\ngenus = \"cumulus\"\n\n[[weather]]\nat = 60.0\n\
         genus = \"cumulonimbos\"\n",
    );
    let scene = tmp.path().join("scenes/w.toml");
    let scene = scene.to_str().expect("utf8");
    let commands: [&[&str]; 5] = [
        &["explain", scene],
        &["emit", "--scene", scene, "-o", "e"],
        &["animate", scene, "--to", "60", "-o", "a"],
        &["render", scene, "-r", "16x9", "--time", "30"],
        &["export-density", scene],
    ];
    for args in commands {
        let o = run(tmp.path(), args);
        let err = refused(&o, &["w.toml", "[[weather]]", "cumulonimbos", "cumulus"]);
        assert!(!err.contains("this adapter cannot"), "{args:?}: {err}");
    }
}

#[cfg(unix)]
#[test]
fn links_loops_and_files_in_the_way_are_refused_before_the_work() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    std::os::unix::fs::symlink(dir.join("nowhere.png"), dir.join("dangling.png")).expect("ln");
    std::os::unix::fs::symlink(dir.join("loop"), dir.join("loop")).expect("ln");
    write(dir, "f", "the user's file");
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["render", "-o", "dangling.png", "-r", "16x9"],
            &["dangling.png", "symbolic link", "does not exist"],
        ),
        (
            &["render", "-o", "loop", "-r", "16x9"],
            &["loop", "symbolic link"],
        ),
        (&["emit", "preview-hg", "-o", "loop"], &["symbolic link"]),
        (
            &["render", "-o", "f/x.png", "-r", "16x9"],
            &["f is a file, not a folder"],
        ),
        (
            &["emit", "preview-hg", "-o", "f/out"],
            &["f is a file, not a folder"],
        ),
        (
            &["export-density", "-o", "c.vol", "--mitsuba", "./c.vol"],
            &["--mitsuba", "same file as -o"],
        ),
    ];
    for (args, wants) in cases {
        let o = run(dir, args);
        let err = refused(&o, wants);
        // Refused up front: no render, no generation (they print before writing).
        let out = text(&o.stdout);
        assert!(
            !out.contains("rendered in") && !out.contains("wrote"),
            "{out}"
        );
        assert!(!err.contains("while Nimbus was writing"), "{err}");
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("f")).expect("read"),
        "the user's file"
    );
    assert!(!dir.join("c.vol").exists());
}

#[test]
fn a_file_name_says_what_it_holds() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run(tmp.path(), &["render", "-o", "out.jpg", "-r", "16x9"]);
    refused(&o, &["out.jpg", "PNG (.png) or OpenEXR (.exr)", "out.png"]);
    let o = run(
        tmp.path(),
        &["render", "-o", "out.png", "--format", "exr", "-r", "16x9"],
    );
    refused(&o, &["--format", "out.png", "out.exr"]);
    assert!(!tmp.path().join("out.jpg").exists() && !tmp.path().join("out.png").exists());
}

#[test]
fn emit_help_names_shaders_that_exist() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run(tmp.path(), &["emit", "--help"]);
    let help = text(&o.stdout);
    assert!(
        !help.contains("preview/hg") && !help.contains("cumulus.high"),
        "{help}"
    );
    // Every single-word name the help of the NAME argument gives is one emit accepts.
    let arguments = help
        .split_once("Arguments:")
        .and_then(|(_, rest)| rest.split_once("Options:"))
        .map(|(args, _)| args)
        .expect("an Arguments section");
    let names: Vec<&str> = arguments
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|n| {
            n.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        })
        .filter(|n| !n.starts_with('-'))
        .collect();
    assert!(names.contains(&"preview-hg"), "{names:?}");
    for name in names {
        let o = run(tmp.path(), &["emit", name, "-t", "wgsl", "-o", "out"]);
        assert!(o.status.success(), "emit {name}: {}", text(&o.stderr));
    }
}

#[test]
fn the_density_profile_overflow_blames_the_term_that_carries_it() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let genus = std::fs::read_to_string(examples("genera/cumulus.toml")).expect("read");
    assert!(genus.contains("c = 0.75"), "the example's profile changed");
    let bad = genus
        .replace("name = \"cumulus\"", "name = \"g\"")
        .replace("c = 0.75", "c = -1e38");
    write(tmp.path(), "g.toml", &bad);
    let o = run(tmp.path(), &["render", "-g", "./g.toml", "-r", "16x9"]);
    let err = refused(&o, &["g.toml", "density_profile.c", "lower |c|"]);
    assert!(!err.contains("density_profile.a"), "{err}");
}

#[test]
fn export_density_refuses_bad_or_absurd_work_before_doing_any() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let cases: [(&[&str], &[&str]); 9] = [
        (&["--size", "0,4,4"], &["--size", "1..=1024"]),
        (&["--margin=-1"], &["--margin", "-1", "[0, 20]"]),
        (&["--margin", "NaN"], &["--margin", "NaN", "[0, 20]"]),
        (&["--margin", "25"], &["--margin", "25", "[0, 20]"]),
        (&["--filter", "9"], &["--filter", "1..=8"]),
        (&["--region", "0,0,0,1,1"], &["--region", "6 numbers"]),
        (&["--region", "0,10,0,1,5,1"], &["--region", "below max"]),
        (&["--voxel", "0.1"], &["--voxel", "at most 1024 per axis"]),
        (
            &["--size", "1024,1024,1024", "--filter", "8"],
            &["export size", "h here", "--force"],
        ),
    ];
    for (args, wants) in cases {
        let o = run(tmp.path(), &[&["export-density"], args].concat());
        refused(&o, wants);
        assert!(!tmp.path().join("clouds.vol").exists());
    }
    let o = run(
        tmp.path(),
        &[
            "render",
            "--verification",
            "--enable",
            "powder,haze",
            "-r",
            "16x9",
        ],
    );
    refused(&o, &["--verification", "powder"]);
}

#[test]
fn without_a_home_folder_no_copy_of_the_examples_is_left_behind() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let temp = tmp.path().join("temp");
    std::fs::create_dir(&temp).expect("mkdir");
    let t = temp.to_str().expect("utf8");
    for _ in 0..2 {
        let o = run_in(
            tmp.path(),
            &["list"],
            &[("TMPDIR", t)],
            &["HOME", "XDG_DATA_HOME"],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        assert!(
            text(&o.stdout).contains("nimbus-examples-"),
            "the private copy was used"
        );
    }
    let left: Vec<_> = std::fs::read_dir(&temp).expect("read").flatten().collect();
    assert!(left.is_empty(), "left in the temporary folder: {left:?}");
}

#[test]
fn a_run_without_a_desktop_session_prints_no_display_noise() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = run_in(
        tmp.path(),
        &["render", "-r", "16x9", "-f", "1", "-o", "x.png"],
        &[],
        &["XDG_RUNTIME_DIR", "NODEVICE_SELECT", "WAYLAND_DISPLAY"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        !text(&o.stderr).contains("XDG_RUNTIME_DIR"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn a_long_formation_run_says_how_long_before_it_starts() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    write(
        tmp.path(),
        "scenes/f.toml",
        "name = \"f\"\ndescription = \"x\"\ngenus = \"cumulus\"\nquality = \"low\"\n\n\
         [formation]\ncells = 8\nstep_seconds = 20.0\n",
    );
    let o = run(
        tmp.path(),
        &[
            "render",
            "scenes/f.toml",
            "--time",
            "6000",
            "-r",
            "16x9",
            "-f",
            "1",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("formation: 301 steps of the 8x8 automaton"),
        "{}",
        text(&o.stdout)
    );
}
