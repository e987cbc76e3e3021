//! Output targets and their file naming.

use std::fmt;
use std::str::FromStr;

use crate::error::CodegenError;

/// A shader language/version Nimbus emits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    /// WGSL for wgpu, Bevy and WebGPU (overrides kept).
    Wgsl,
    /// GLSL ES 3.00 for WebGL2 / three.js.
    GlslEs300,
    /// GLSL 4.50 core for OpenGL and Vulkan-GLSL toolchains.
    Glsl450,
    /// HLSL shader model 5.0, Direct3D 11 registers: one file per module, every entry point
    /// (Unity, FXC, DXC, Slang).
    Hlsl,
    /// Metal Shading Language 2.1.
    Msl,
    /// SPIR-V 1.0 binary for Vulkan.
    SpirV,
}

impl Target {
    pub const ALL: [Target; 6] = [
        Target::Wgsl,
        Target::GlslEs300,
        Target::Glsl450,
        Target::Hlsl,
        Target::Msl,
        Target::SpirV,
    ];

    /// The name used on the command line and in manifests.
    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::GlslEs300 => "glsl-es300",
            Target::Glsl450 => "glsl450",
            Target::Hlsl => "hlsl",
            Target::Msl => "msl",
            Target::SpirV => "spirv",
        }
    }

    /// File extension of the emitted file.
    pub fn extension(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::GlslEs300 | Target::Glsl450 => "glsl",
            Target::Hlsl => "hlsl",
            Target::Msl => "metal",
            Target::SpirV => "spv",
        }
    }

    /// Whether the target gets a JSON binding manifest beside each file.
    pub fn has_binding_manifest(self) -> bool {
        matches!(
            self,
            Target::GlslEs300 | Target::Glsl450 | Target::Hlsl | Target::Msl
        )
    }

    /// Parses a comma-separated list (`all` selects every target).
    pub fn parse_list(list: &str) -> Result<Vec<Target>, CodegenError> {
        let mut out = Vec::new();
        for part in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            if part == "all" {
                return Ok(Target::ALL.to_vec());
            }
            let t: Target = part.parse()?;
            if !out.contains(&t) {
                out.push(t);
            }
        }
        if out.is_empty() {
            return Err(CodegenError::UnknownTarget {
                given: list.to_string(),
                known: known_list(),
            });
        }
        Ok(out)
    }
}

fn known_list() -> String {
    let mut names: Vec<&str> = Target::ALL.iter().map(|t| t.name()).collect();
    names.push("all");
    names.join(", ")
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Target {
    type Err = CodegenError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let normalised = s.trim().to_ascii_lowercase().replace('_', "-");
        Target::ALL
            .into_iter()
            .find(|t| t.name() == normalised)
            .or(match normalised.as_str() {
                "glsl" | "glsl-es" | "webgl2" | "gles300" => Some(Target::GlslEs300),
                "glsl-450" | "vulkan-glsl" => Some(Target::Glsl450),
                "metal" => Some(Target::Msl),
                "spv" | "spir-v" => Some(Target::SpirV),
                _ => None,
            })
            .ok_or_else(|| CodegenError::UnknownTarget {
                given: s.to_string(),
                known: known_list(),
            })
    }
}

#[cfg(feature = "clap")]
impl clap::ValueEnum for Target {
    fn value_variants<'a>() -> &'a [Self] {
        &Target::ALL
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()))
    }
}
