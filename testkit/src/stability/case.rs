//! What a hard case is: probes (rays with their uniforms), chains and pairs over them, and the
//! small textures they read.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_dsl::cpu::{Texture2d, Texture3d};

/// One view ray with the uniforms it is marched under.
#[derive(Clone, Copy, Debug)]
pub struct Probe {
    pub uniforms: CloudUniforms,
    /// Unit direction, local frame (y up).
    pub direction: Vec3,
    /// Offset of the first sample within the first step, in [0, 1).
    pub jitter: f32,
}

/// Two probes on either side of a threshold (a camera crossing a shell, the sun crossing the
/// horizon, coverage leaving 0): their pixels may differ by at most `rel` of the larger plus
/// `abs` (in units of the clouds' source bound), and their transmittances by `rel + abs`.
#[derive(Clone, Copy, Debug)]
pub struct Pair {
    pub a: usize,
    pub b: usize,
    pub rel: f32,
    pub abs: f32,
}

/// The textures a case's probes read, kept small so the CPU twins run fast. Values sit on a
/// 1/256 grid, which the GPU's f16 textures hold exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CaseTextures {
    /// Pseudo-random texels from a seed: cloud structure on every scale of the probes, and a
    /// random beer shadow map.
    Random(u64),
    /// The same clouds with an empty shadow map, for pairs that change the clouds (a random
    /// shadow map would not change with them).
    RandomUnshadowed(u64),
    /// Every texel of every texture equal (the shadow map then says "no shadow").
    Constant(f32),
}

impl CaseTextures {
    pub fn build(self) -> CloudTextures {
        match self {
            CaseTextures::Random(seed) | CaseTextures::RandomUnshadowed(seed) => {
                let shadowed = matches!(self, CaseTextures::Random(_));
                let mut state = seed.max(1);
                let mut texels = |n: usize, scale: [f32; 4]| -> Vec<Vec4> {
                    (0..n)
                        .map(|_| {
                            Vec4::from_array(std::array::from_fn(|c| {
                                state ^= state >> 12;
                                state ^= state << 25;
                                state ^= state >> 27;
                                let r = state.wrapping_mul(0x2545_f491_4f6c_dd1d);
                                (r % 257) as f32 / 256.0 * scale[c]
                            }))
                        })
                        .collect()
                };
                CloudTextures {
                    weather: Arc::new(Texture2d {
                        size: [16, 16],
                        texels: texels(256, [1.0; 4]),
                    }),
                    shape: Arc::new(Texture3d {
                        size: [16, 16, 16],
                        texels: texels(4096, [1.0; 4]),
                    }),
                    detail: Arc::new(Texture3d {
                        size: [8, 8, 8],
                        texels: texels(512, [1.0; 4]),
                    }),
                    turbulence: Arc::new(Texture2d {
                        size: [8, 8],
                        texels: texels(64, [1.0; 4]),
                    }),
                    shadow: Arc::new(Texture2d {
                        size: [8, 8],
                        texels: texels(64, [1024.0, 0.0625, 4.0, 0.5])
                            .into_iter()
                            .map(|t| if shadowed { t } else { Vec4::ZERO })
                            .collect(),
                    }),
                }
            }
            CaseTextures::Constant(v) => CloudTextures {
                weather: Arc::new(Texture2d {
                    size: [1, 1],
                    texels: vec![Vec4::splat(v)],
                }),
                shape: Arc::new(Texture3d {
                    size: [1, 1, 1],
                    texels: vec![Vec4::splat(v)],
                }),
                detail: Arc::new(Texture3d {
                    size: [1, 1, 1],
                    texels: vec![Vec4::splat(v)],
                }),
                turbulence: Arc::new(Texture2d {
                    size: [1, 1],
                    texels: vec![Vec4::splat(0.5)],
                }),
                shadow: Arc::new(Texture2d {
                    size: [1, 1],
                    texels: vec![Vec4::new(0.0, 0.0, 0.0, 0.0)],
                }),
            },
        }
    }
}

/// A named hard case.
#[derive(Clone, Debug)]
pub struct Case {
    /// Kebab-case name; the tests are named after it.
    pub name: &'static str,
    /// What makes it hard, in one line.
    pub about: &'static str,
    pub key: CloudKey,
    pub textures: CaseTextures,
    pub probes: Vec<Probe>,
    /// Indices of probes that cut one ray at increasing distances: transmittance must not
    /// increase along a chain.
    pub chains: Vec<Vec<usize>>,
    pub pairs: Vec<Pair>,
}
