//! A git revision of Nimbus as an emitted folder, for `nimbus diff`: the checkout is the one the
//! command runs in (not the one the binary was built from, which an installed binary may not
//! have), and the revision is emitted by that checkout's own `nimbus`, built with cargo.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// What comparing git revisions needs, said by every error that finds part of it missing.
const NEEDS: &str = "comparing git revisions needs a Nimbus git checkout as the current \
                     directory, with git and cargo on PATH; or compare two folders written by \
                     `nimbus emit`";

#[derive(Debug, thiserror::Error)]
pub(crate) enum RevisionError {
    #[error("`{rev}` is not a folder, and git is not on PATH: {needs}", needs = NEEDS)]
    NoGit { rev: String },

    #[error(
        "`{rev}` is not a folder, and there is no git checkout at or above {}: {needs}",
        cwd.display(),
        needs = NEEDS
    )]
    NoCheckout { rev: String, cwd: PathBuf },

    #[error(
        "`{rev}` is not a folder, and the git checkout {} is not Nimbus's (no \
         shaders-gen/Cargo.toml): {needs}",
        root.display(),
        needs = NEEDS
    )]
    NotNimbus { rev: String, root: PathBuf },

    #[error("`{rev}` is not a folder, and cargo is not on PATH: {needs}", needs = NEEDS)]
    NoCargo { rev: String },

    #[error(
        "`{rev}` is neither a folder written by `nimbus emit` nor a revision of the git \
         checkout {}",
        root.display()
    )]
    UnknownRevision { rev: String, root: PathBuf },

    #[error("emitting revision `{rev}` failed (cargo's output is above)")]
    EmitFailed { rev: String },

    #[error("running {tool}: {source}")]
    Run {
        tool: &'static str,
        source: std::io::Error,
    },
}

/// Runs `tool`, telling a missing program (`missing`) from other failures to start it.
fn run(
    tool: &'static str,
    command: &mut Command,
    missing: impl FnOnce() -> RevisionError,
) -> Result<Output, RevisionError> {
    command.output().map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            missing()
        } else {
            RevisionError::Run { tool, source }
        }
    })
}

/// The root of the Nimbus git checkout around the current directory, with cargo there to build
/// it; `rev` names the revision wanted, for the error.
fn checkout(rev: &str) -> Result<PathBuf, RevisionError> {
    let rev = rev.to_string();
    let cwd = std::env::current_dir().map_err(|source| RevisionError::Run {
        tool: "git",
        source,
    })?;
    let found = run(
        "git",
        Command::new("git")
            .args(["rev-parse", "--show-toplevel"])
            .current_dir(&cwd),
        || RevisionError::NoGit { rev: rev.clone() },
    )?;
    if !found.status.success() {
        return Err(RevisionError::NoCheckout { rev, cwd });
    }
    let root = PathBuf::from(String::from_utf8_lossy(&found.stdout).trim_end());
    if !root.join("shaders-gen/Cargo.toml").is_file() {
        return Err(RevisionError::NotNimbus { rev, root });
    }
    run("cargo", Command::new("cargo").arg("--version"), || {
        RevisionError::NoCargo { rev: rev.clone() }
    })?;
    Ok(root)
}

/// Emits every shader of the project at git revision `rev` into a fresh folder under
/// `scratch`, by running `emit` from a worktree of that revision.
pub(crate) fn emit_revision(rev: &str, scratch: &Path) -> Result<PathBuf, RevisionError> {
    let root = checkout(rev)?;
    let tree = scratch.join(format!("tree-{}", rev.replace('/', "_")));
    let out = scratch.join(format!("emit-{}", rev.replace('/', "_")));
    let no_git = || RevisionError::NoGit {
        rev: rev.to_string(),
    };
    let added = run(
        "git",
        Command::new("git")
            .current_dir(&root)
            .args(["worktree", "add", "--detach", "--force"])
            .arg(&tree)
            .arg(rev),
        no_git,
    )?;
    if !added.status.success() {
        return Err(RevisionError::UnknownRevision {
            rev: rev.to_string(),
            root,
        });
    }
    // A target folder of its own, absolute, so that building an old revision neither replaces
    // the checkout's binaries nor starts from nothing each time.
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let target = std::path::absolute(target)
        .map_err(|source| RevisionError::Run {
            tool: "cargo",
            source,
        })?
        .join("nimbus-diff");
    let status = Command::new("cargo")
        .current_dir(&tree)
        .env("CARGO_TARGET_DIR", target)
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "nimbus-cli",
            "--",
            "emit",
            "-t",
            "all",
            "-o",
        ])
        .arg(&out)
        .status();
    // The worktree goes whatever the build did; failing to remove it leaves only a stale
    // entry that `git worktree prune` clears.
    let _ = Command::new("git")
        .current_dir(&root)
        .args(["worktree", "remove", "--force"])
        .arg(&tree)
        .status();
    let status = status.map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            RevisionError::NoCargo {
                rev: rev.to_string(),
            }
        } else {
            RevisionError::Run {
                tool: "cargo",
                source,
            }
        }
    })?;
    if !status.success() {
        return Err(RevisionError::EmitFailed {
            rev: rev.to_string(),
        });
    }
    Ok(out)
}
