//! Validation by the consumers' own tools: glslangValidator for GLSL (naga lets a few ES 3.00
//! built-ins through that WebGL2 rejects), glslangValidator's HLSL front end for HLSL (compiled
//! to SPIR-V, as Unity's own cross-compilers read HLSL), and spirv-val for SPIR-V. A missing
//! tool is reported as such, never as a pass.

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

/// Checks one emitted file with the tool its consumers use.
pub fn check_file(file: &OutputFile) -> ExternalCheck {
    match (file.target, &file.contents) {
        (Target::GlslEs300 | Target::Glsl450, Contents::Text(t)) => {
            run("glslangValidator", &[], &[], &file.file_name, t.as_bytes())
        }
        (Target::Hlsl, Contents::Text(t)) => {
            let Some((entry, stage)) = &file.entry_point else {
                return ExternalCheck::NotApplicable;
            };
            let stage = match stage {
                nimbus_dsl::ir::Stage::Vertex => "vert",
                nimbus_dsl::ir::Stage::Fragment => "frag",
                nimbus_dsl::ir::Stage::Compute => "comp",
            };
            run(
                "glslangValidator",
                &["-D", "-V", "-S", stage, "-e", entry, "-o", "/dev/null"],
                // glslang exits 0 when the entry point is missing; Unity would not compile it.
                &["Entry point not found"],
                &file.file_name,
                t.as_bytes(),
            )
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
