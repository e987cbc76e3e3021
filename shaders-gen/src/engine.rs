//! The engines `nimbus emit --engine` writes packages for: the shading language each one runs,
//! the limits its API guarantees on every device, and the conventions that make its first frame
//! right.

use nimbus_codegen::Target;

/// An engine a package is written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Engine {
    /// three.js on WebGL2: GLSL ES 3.00 for `RawShaderMaterial` (`glslVersion: GLSL3`).
    Three,
    /// WebGPU in a browser: WGSL.
    Webgpu,
    /// wgpu (Rust): WGSL.
    Wgpu,
    /// Vulkan: SPIR-V 1.0.
    Vulkan,
    /// Unity: HLSL shader model 5.0 (Direct3D 11 registers), ShaderLab and C#.
    Unity,
    /// Metal: MSL 2.1.
    Metal,
}

/// Largest texture sides an engine's API guarantees on every device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Limits {
    pub texture_2d: u32,
    pub texture_3d: u32,
    /// Where the figures come from.
    pub source: &'static str,
}

impl Engine {
    /// The `--engine` value.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Engine::Three => "three",
            Engine::Webgpu => "webgpu",
            Engine::Wgpu => "wgpu",
            Engine::Vulkan => "vulkan",
            Engine::Unity => "unity",
            Engine::Metal => "metal",
        }
    }

    /// The one target the package's shaders are written in.
    pub(crate) fn target(self) -> Target {
        match self {
            Engine::Three => Target::GlslEs300,
            Engine::Webgpu | Engine::Wgpu => Target::Wgsl,
            Engine::Vulkan => Target::SpirV,
            Engine::Unity => Target::Hlsl,
            Engine::Metal => Target::Msl,
        }
    }

    pub(crate) fn language(self) -> &'static str {
        match self {
            Engine::Three => "GLSL ES 3.00 (WebGL2)",
            Engine::Webgpu | Engine::Wgpu => "WGSL",
            Engine::Vulkan => "SPIR-V 1.0",
            Engine::Unity => "HLSL shader model 5.0",
            Engine::Metal => "MSL 2.1",
        }
    }

    /// The texture sizes every device of the engine's API supports (the minimums the API
    /// requires of an implementation, not what a particular GPU offers).
    pub(crate) fn limits(self) -> Limits {
        match self {
            Engine::Three => Limits {
                texture_2d: 2048,
                texture_3d: 256,
                source: "WebGL 2.0 / OpenGL ES 3.0 minimum MAX_TEXTURE_SIZE and MAX_3D_TEXTURE_SIZE",
            },
            Engine::Webgpu | Engine::Wgpu => Limits {
                texture_2d: 8192,
                texture_3d: 2048,
                source: "WebGPU default maxTextureDimension2D and maxTextureDimension3D",
            },
            Engine::Vulkan => Limits {
                texture_2d: 4096,
                texture_3d: 256,
                source: "Vulkan 1.0 required maxImageDimension2D and maxImageDimension3D",
            },
            Engine::Unity => Limits {
                texture_2d: 16384,
                texture_3d: 2048,
                source: "Direct3D 11 feature level 11_0 texture limits",
            },
            Engine::Metal => Limits {
                texture_2d: 8192,
                texture_3d: 2048,
                source: "Metal feature set tables, Apple2 family (the oldest with MSL 2.1)",
            },
        }
    }

    /// Whether the engine's host code is JavaScript (the package then carries the JavaScript
    /// twin of what a moving sun changes).
    pub(crate) fn javascript_host(self) -> bool {
        matches!(self, Engine::Three | Engine::Webgpu)
    }

    /// Whether the package carries the `sun_light` kernel: hosts without JavaScript complete
    /// the cloud block on the GPU (every such engine has compute).
    pub(crate) fn sun_kernel(self) -> bool {
        !self.javascript_host()
    }

    /// Whether uniform blocks are bound as arrays of `uvec4` words (three.js's `UniformsGroup`
    /// cannot describe nested structs with `u32` members; one typed array of the bytes it can).
    pub(crate) fn flat_uniforms(self) -> bool {
        matches!(self, Engine::Three)
    }

    /// Whether the framebuffer's first row is the bottom one (OpenGL conventions): the
    /// display pass then flips the image (`display.flip_y = 1`).
    pub(crate) fn bottom_up(self) -> bool {
        matches!(self, Engine::Three)
    }

    /// The conventions that make the first frame right, as the package states them.
    pub(crate) fn conventions(self) -> Vec<(&'static str, String)> {
        let mut c = vec![
            (
                "draw",
                "every pass is one full-screen triangle: draw 3 vertices with no vertex or index \
                 buffer; the vertex shader builds the positions from the vertex index"
                    .to_string(),
            ),
            (
                "depth",
                "no depth or stencil attachment, test or write".to_string(),
            ),
            (
                "blend",
                "none: each pass overwrites its whole target".to_string(),
            ),
        ];
        match self {
            Engine::Three => {
                c.push((
                    "cull",
                    "none (THREE.DoubleSide): the GLSL vertex shader flips y for OpenGL's clip \
                     space, which turns the triangle clockwise, so three's default FrontSide \
                     would cull it and leave the frame black"
                        .to_string(),
                ));
                c.push((
                    "rows",
                    "the passes work top-down in gl_FragCoord rows (as WGSL's position does); \
                     set display.flip_y = 1 so the last pass shows the image upright"
                        .to_string(),
                ));
                c.push((
                    "uniforms",
                    "each uniform block is bound as one array of uvec4 words holding the block's \
                     bytes (uniforms/*.json: size and bytes_hex; floats are read by bitcast); \
                     in three.js, a UniformsGroup named as the file's .json manifest names the \
                     block, with one THREE.Uniform whose value is a Float32Array view of the \
                     bytes (three writes typed arrays verbatim), as nimbus-clouds.js does"
                        .to_string(),
                ));
                c.push((
                    "material",
                    "THREE.RawShaderMaterial with glslVersion THREE.GLSL3; the files carry their \
                     own #version line, which three's GLSL3 prefix must not repeat: strip the \
                     first line, or use the package's ES module"
                        .to_string(),
                ));
            }
            Engine::Webgpu | Engine::Wgpu | Engine::Vulkan | Engine::Unity | Engine::Metal => {
                c.push(("cull", "none, or counter-clockwise front faces".to_string()));
                if self.sun_kernel() {
                    c.push((
                        "sun",
                        "the shadow and clouds passes bind the buffer the sun_light pass writes \
                         (storage + uniform usage, the block's size), not the one the host \
                         fills: run sun_light (one invocation) after writing the block whenever \
                         light.sun_direction or camera_altitude changed"
                            .to_string(),
                    ));
                }
                if self == Engine::Unity {
                    c.push((
                        "compute",
                        "sun-light.compute runs the kernel; it writes the completed block as \
                         words into a structured buffer (RWStructuredBuffer<uint>), which \
                         Direct3D 11 cannot also bind as a constant buffer: copy it into the \
                         block's constant buffer (CommandBuffer.CopyBuffer) before the passes \
                         that read it, as NimbusClouds.cs does"
                            .to_string(),
                    ));
                    c.push((
                        "samplers",
                        "inline sampler states: each SamplerState is named with its filter and \
                         wrap (linear_sampler_linear_repeat), which Unity reads from the name; \
                         a host binds no sampler"
                            .to_string(),
                    ));
                }
                c.push((
                    "rows",
                    "top-down (row 0 at the top), the API's own convention; display.flip_y = 0"
                        .to_string(),
                ));
            }
        }
        c
    }

    /// What validates this engine's files beyond naga when no external tool ran.
    pub(crate) fn unchecked_note(self) -> &'static str {
        match self {
            Engine::Three => "glslangValidator was not found (apt-get install glslang-tools)",
            Engine::Vulkan => "spirv-val was not found (apt-get install spirv-tools)",
            Engine::Webgpu | Engine::Wgpu => {
                "naga is wgpu's and Firefox's own WGSL front end; Chromium's Tint is not \
                 available here"
            }
            Engine::Unity => {
                "glslangValidator (its HLSL front end, apt-get install glslang-tools) or Slang \
                 (python3 -m pip install slangpy) was not found; DXC, FXC and Unity do not run \
                 here"
            }
            Engine::Metal => "Apple's Metal compiler does not run on Linux",
        }
    }

    /// How a host names a binding in this engine's files.
    pub(crate) fn binding_note(self) -> &'static str {
        match self {
            Engine::Three => {
                "GLSL ES 3.00 has no bind groups: each uniform block and each combined sampler \
                 (texture + sampler) is named in the file's .json manifest, with the texture's \
                 address mode and filter"
            }
            Engine::Webgpu | Engine::Wgpu => {
                "@group/@binding as listed; a bind-group layout per pass follows from the \
                 bindings below"
            }
            Engine::Vulkan => "descriptor set = group, binding = binding, as listed",
            Engine::Unity => {
                "one HLSL file per pass with every entry point; each binding in the register of \
                 its class numbered as its binding (b0, t1, s6, u1), the uniform blocks as \
                 cbuffers named as listed; Unity binds them by name (the file's .json manifest \
                 lists each name and register)"
            }
            Engine::Metal => {
                "buffer, texture and sampler indices as listed in the file's .json manifest"
            }
        }
    }
}
