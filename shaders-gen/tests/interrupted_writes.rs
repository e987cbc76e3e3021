//! `emit` and `render` killed with SIGKILL at many points of their run: the previous output is
//! intact (or the new one complete), never half of either, and the next run cleans up what the
//! killed ones left.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::{have_gpu, nimbus, text, tree};

/// Runs `nimbus args` and kills it after `delay`; true if it was still running then.
fn kill_after(args: &[&str], delay: Duration) -> bool {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nimbus"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn nimbus");
    std::thread::sleep(delay);
    let running = child.try_wait().expect("poll").is_none();
    let _ = child.kill(); // SIGKILL on Unix
    let _ = child.wait();
    running
}

fn leftovers(dir: &Path, prefix: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(prefix))
        .collect()
}

#[test]
fn emit_killed_anywhere_leaves_the_previous_output_whole() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let out_s = out.to_str().expect("utf8");
    let old_args = ["emit", "-g", "cumulus", "-q", "low", "-o", out_s];
    let new_args = ["emit", "-g", "stratus", "-q", "high", "-o", out_s];
    // The two complete outputs, for reference.
    let o = nimbus(&new_args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let new_tree = tree(&out);
    let o = nimbus(&old_args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let old_tree = tree(&out);
    assert_ne!(old_tree, new_tree);

    let (mut killed, mut old_seen, mut new_seen, mut restored) = (0, 0, 0, 0);
    // Delays 2 ms apart over the whole run (an emit of these two keys for every target takes
    // tens of milliseconds): kills land while it generates, writes, or swaps the folders.
    for round in 0..48u64 {
        let delay = Duration::from_millis(1 + round * 2);
        killed += usize::from(kill_after(&new_args, delay));
        if !out.exists() {
            // Killed between moving the old folder aside and the new one in: the old one is
            // complete beside it, and the next run puts it back.
            let aside = leftovers(tmp.path(), ".out.nimbus-old-");
            assert_eq!(aside.len(), 1, "round {round}: the old output is aside");
            assert_eq!(tree(&tmp.path().join(&aside[0])), old_tree);
            restored += 1;
            let o = nimbus(&old_args);
            assert!(o.status.success(), "{}", text(&o.stderr));
            continue;
        }
        let now = tree(&out);
        if now == old_tree {
            old_seen += 1;
        } else if now == new_tree {
            new_seen += 1;
            let o = nimbus(&old_args);
            assert!(o.status.success(), "{}", text(&o.stderr));
        } else {
            panic!(
                "round {round} ({delay:?}): the output folder is neither the old nor the new \
                 one ({} files)",
                now.len()
            );
        }
    }
    println!(
        "emit killed {killed} times mid-run: old output intact {old_seen}×, new complete \
         {new_seen}×, restored from aside {restored}×"
    );
    assert!(killed >= 3, "runs were killed while running ({killed})");
    // The next complete run removes what the killed ones left beside the folder.
    let o = nimbus(&new_args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(tree(&out), new_tree);
    assert_eq!(
        leftovers(tmp.path(), ".out."),
        Vec::<String>::new(),
        "no leftovers of killed runs"
    );
}

#[test]
fn render_killed_anywhere_leaves_the_previous_image_whole() {
    if !have_gpu() {
        return;
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let png = tmp.path().join("clouds.png");
    let png_s = png.to_str().expect("utf8");
    let args = |sun: &'static str| {
        [
            "render",
            "-o",
            png_s,
            "-r",
            "96x54",
            "-q",
            "low",
            "-f",
            "2",
            "--sun-elevation",
            sun,
        ]
    };
    let o = nimbus(&args("20"));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let old = std::fs::read(&png).expect("first image");
    let mut killed = 0;
    for round in 0..12u64 {
        let delay = Duration::from_millis(20 + round * round * 12);
        killed += usize::from(kill_after(&args("50"), delay));
        let now = std::fs::read(&png).expect("an image is always there");
        if now != old {
            // A complete new image, never a partial one.
            image::load_from_memory(&now).expect("a complete PNG");
        }
    }
    println!("render killed {killed} times mid-run; the image was whole every time");
    assert!(killed > 0, "some renders were killed while running");
    let o = nimbus(&args("50"));
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(
        leftovers(tmp.path(), ".nimbus-"),
        Vec::<String>::new(),
        "no temporary files of killed renders"
    );
}
