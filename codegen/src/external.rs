//! Validation by the consumers' own tools: glslangValidator for GLSL (naga lets a few ES 3.00
//! built-ins through that WebGL2 rejects), two independent HLSL front ends for HLSL —
//! glslangValidator's (each entry point compiled to SPIR-V, as Unity's own cross-compilers read
//! HLSL) and Slang's (the whole file as one program, from the `slangpy` wheel) —, and spirv-val
//! for SPIR-V. A missing tool is reported as such, never as a pass.

use std::io::Write as _;
use std::process::{Command, Stdio};

use crate::backend::Contents;
use crate::generate::OutputFile;
use crate::target::Target;

/// The outcome of one external check.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExternalCheck {
    Passed {
        tool: &'static str,
    },
    Failed {
        tool: &'static str,
        output: String,
    },
    ToolMissing {
        tool: &'static str,
    },
    /// The target has no external validator available on Linux (MSL, WGSL).
    NotApplicable,
}

fn tool_available(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok()
}

/// Runs `tool` on `bytes` written as `file_name`; it fails on a non-zero status, or on output
/// holding any of `fatal` (warnings the tool exits 0 with but a consumer would fail on).
fn run(
    tool: &'static str,
    args: &[&str],
    fatal: &[&str],
    file_name: &str,
    bytes: &[u8],
) -> ExternalCheck {
    if !tool_available(tool) {
        return ExternalCheck::ToolMissing { tool };
    }
    let dir = std::env::temp_dir().join(format!(
        "nimbus-ext-{}-{}",
        std::process::id(),
        crate::generate::fnv1a(bytes)
    ));
    if std::fs::create_dir_all(&dir).is_err() {
        return ExternalCheck::Failed {
            tool,
            output: format!("cannot create {}", dir.display()),
        };
    }
    let path = dir.join(file_name);
    let written = std::fs::File::create(&path).and_then(|mut f| f.write_all(bytes));
    let result = match written {
        Err(e) => ExternalCheck::Failed {
            tool,
            output: format!("cannot write {}: {e}", path.display()),
        },
        Ok(()) => match Command::new(tool).args(args).arg(&path).output() {
            Ok(out)
                if out.status.success()
                    && !fatal.iter().any(|f| {
                        String::from_utf8_lossy(&out.stdout).contains(f)
                            || String::from_utf8_lossy(&out.stderr).contains(f)
                    }) =>
            {
                ExternalCheck::Passed { tool }
            }
            Ok(out) => ExternalCheck::Failed {
                tool,
                output: format!(
                    "{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ),
            },
            Err(e) => ExternalCheck::Failed {
                tool,
                output: e.to_string(),
            },
        },
    };
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// Checks one emitted file with the tools its consumers use (see [`check_files`]).
pub fn check_file(file: &OutputFile) -> ExternalCheck {
    check_files(&[file])
        .pop()
        .unwrap_or(ExternalCheck::NotApplicable)
}

/// Checks emitted files, one outcome per file in order. An HLSL file passes when both front ends
/// take every entry point; Slang runs once for the whole batch.
pub fn check_files(files: &[&OutputFile]) -> Vec<ExternalCheck> {
    let hlsl: Vec<(&str, &str, Vec<String>)> = files
        .iter()
        .filter_map(|f| match (f.target, &f.contents) {
            (Target::Hlsl, Contents::Text(t)) => Some((
                f.file_name.as_str(),
                t.as_str(),
                f.manifest
                    .as_ref()
                    .map(|m| m.entry_points.values().cloned().collect())
                    .unwrap_or_default(),
            )),
            _ => None,
        })
        .collect();
    let mut slang = slang_check(&hlsl).into_iter();
    files
        .iter()
        .map(|f| match f.target {
            Target::Hlsl => {
                let glslang = check_hlsl_with_glslang(f);
                let slang = slang.next().unwrap_or(ExternalCheck::NotApplicable);
                match (glslang, slang) {
                    (failed @ ExternalCheck::Failed { .. }, _)
                    | (_, failed @ ExternalCheck::Failed { .. }) => failed,
                    (missing @ ExternalCheck::ToolMissing { .. }, _)
                    | (_, missing @ ExternalCheck::ToolMissing { .. }) => missing,
                    _ => ExternalCheck::Passed {
                        tool: "glslangValidator (HLSL) and Slang",
                    },
                }
            }
            _ => check_one(f),
        })
        .collect()
}

/// glslang's HLSL front end on every entry point the file's manifest lists.
fn check_hlsl_with_glslang(file: &OutputFile) -> ExternalCheck {
    let (Contents::Text(t), Some(manifest)) = (&file.contents, &file.manifest) else {
        return ExternalCheck::NotApplicable;
    };
    for (stage, entry) in &manifest.entry_points {
        let stage = match stage.as_str() {
            "vertex" => "vert",
            "fragment" => "frag",
            _ => "comp",
        };
        let check = run(
            "glslangValidator",
            &["-D", "-V", "-S", stage, "-e", entry, "-o", "/dev/null"],
            // glslang exits 0 when the entry point is missing; Unity would not compile it.
            &["Entry point not found"],
            &file.file_name,
            t.as_bytes(),
        );
        if !matches!(check, ExternalCheck::Passed { .. }) {
            return check;
        }
    }
    ExternalCheck::Passed {
        tool: "glslangValidator",
    }
}

/// The Slang check's script, run by Python with the `slangpy` wheel.
const SLANG_CHECK: &str = include_str!("slang_check.py");

/// Slang's front end on each `(file name, text, entry points)`: one outcome each, in order.
pub fn slang_check(files: &[(&str, &str, Vec<String>)]) -> Vec<ExternalCheck> {
    const TOOL: &str = "Slang (python3 -m pip install slangpy)";
    if files.is_empty() {
        return Vec::new();
    }
    let available = Command::new("python3")
        .args(["-c", "import slangpy"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !available {
        return files
            .iter()
            .map(|_| ExternalCheck::ToolMissing { tool: TOOL })
            .collect();
    }
    let failed = |output: String| {
        files
            .iter()
            .map(|_| ExternalCheck::Failed {
                tool: TOOL,
                output: output.clone(),
            })
            .collect()
    };
    let dir = std::env::temp_dir().join(format!(
        "nimbus-slang-{}-{}",
        std::process::id(),
        crate::generate::fnv1a(files.iter().map(|f| f.0).collect::<String>().as_bytes())
    ));
    if let Err(e) = std::fs::create_dir_all(&dir) {
        return failed(format!("cannot create {}: {e}", dir.display()));
    }
    let mut list = Vec::new();
    for (name, text, entries) in files {
        let path = dir.join(name);
        if let Err(e) = std::fs::write(&path, text) {
            let _ = std::fs::remove_dir_all(&dir);
            return failed(format!("cannot write {}: {e}", path.display()));
        }
        list.push(serde_json::json!({ "path": path, "entries": entries }));
    }
    let script = dir.join("slang_check.py");
    let run = std::fs::write(&script, SLANG_CHECK).and_then(|()| {
        let mut child = Command::new("python3")
            .arg(&script)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        if let Some(mut stdin) = child.stdin.take() {
            stdin.write_all(serde_json::Value::Array(list).to_string().as_bytes())?;
        }
        child.wait_with_output()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let out = match run {
        Ok(out) => out,
        Err(e) => return failed(format!("cannot run python3: {e}")),
    };
    let results: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect();
    if results.len() != files.len() {
        return failed(format!(
            "the Slang check answered for {} of {} files: {}",
            results.len(),
            files.len(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    results
        .into_iter()
        .map(|r| {
            if r["ok"].as_bool() == Some(true) {
                ExternalCheck::Passed { tool: TOOL }
            } else {
                ExternalCheck::Failed {
                    tool: TOOL,
                    output: r["output"].as_str().unwrap_or_default().to_string(),
                }
            }
        })
        .collect()
}

fn check_one(file: &OutputFile) -> ExternalCheck {
    match (file.target, &file.contents) {
        (Target::GlslEs300 | Target::Glsl450, Contents::Text(t)) => {
            run("glslangValidator", &[], &[], &file.file_name, t.as_bytes())
        }
        (Target::SpirV, c @ Contents::SpirV(_)) => run(
            "spirv-val",
            &["--target-env", "vulkan1.0"],
            &[],
            &file.file_name,
            &c.to_bytes(),
        ),
        _ => ExternalCheck::NotApplicable,
    }
}
