//! The parts of `nimbus-package.json` and `uniforms/*.json` this host reads. The package's
//! JSON Schema (`nimbus-package.schema.json`) describes every field; unknown ones are ignored.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde::de::DeserializeOwned;

use crate::error::HostError;

#[derive(Deserialize)]
pub struct Package {
    pub engine: String,
    pub textures: Vec<TextureFile>,
    /// The half-float bit pattern of each byte value k/255 (as Nimbus's runtime widens them).
    pub texel_halves: Vec<u16>,
    pub pairs: Vec<Pair>,
}

#[derive(Deserialize)]
pub struct TextureFile {
    pub name: String,
    pub file: String,
    pub dimension: String,
    pub size: Vec<u32>,
    /// The texel format to create: `r16float` (one channel) or `rgba16float`.
    pub format: String,
}

#[derive(Deserialize)]
pub struct AtlasSize {
    pub width: u32,
    pub height: u32,
}

#[derive(Deserialize)]
pub struct Pair {
    pub pair: String,
    pub uniforms: String,
    pub scene_depth: bool,
    pub shadow_atlas: Option<AtlasSize>,
    pub air_table: Option<AtlasSize>,
    pub passes: Vec<Pass>,
}

#[derive(Deserialize)]
pub struct Pass {
    pub pass: String,
    pub files: Vec<ShaderFile>,
    pub bindings: Vec<Binding>,
    pub descriptor_set_layout: Option<DescriptorSetLayout>,
    pub dispatch: Option<[u32; 3]>,
    /// The target it draws (or `pair`, the block `sun_light` completes).
    pub writes: String,
    /// The barriers to record before it.
    pub vulkan_barriers: Option<Vec<Barrier>>,
}

/// A pipeline barrier the pass graph states, flags as `|`-joined Vulkan names.
#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Barrier {
    pub resource: String,
    pub src_stage_mask: String,
    pub src_access_mask: String,
    pub dst_stage_mask: String,
    pub dst_access_mask: String,
    pub old_layout: Option<String>,
    pub new_layout: Option<String>,
}

#[derive(Deserialize)]
pub struct ShaderFile {
    pub file: String,
    pub entry_point: Option<String>,
    pub stage: Option<String>,
}

#[derive(Deserialize)]
pub struct Binding {
    pub binding: u32,
    pub name: String,
    pub holds: Holds,
}

/// Which resource a binding slot holds, by the id the package's `resources` list.
#[derive(Deserialize)]
pub struct Holds {
    pub id: String,
}

#[derive(Deserialize)]
pub struct DescriptorSetLayout {
    pub set: u32,
    pub bindings: Vec<LayoutBinding>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct LayoutBinding {
    pub binding: u32,
    pub descriptor_type: String,
    pub descriptor_count: u32,
    pub stage_flags: u32,
    pub sampler: Option<SamplerState>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct SamplerState {
    pub mag_filter: String,
    pub min_filter: String,
    pub mipmap_mode: String,
    pub address_mode_u: String,
    pub address_mode_v: String,
    pub address_mode_w: String,
}

/// A uniform block file: its bytes and where each member lies.
#[derive(Deserialize)]
pub struct UniformFile {
    pub size: usize,
    pub bytes_hex: String,
    pub members: Vec<Member>,
}

#[derive(Deserialize)]
pub struct Member {
    pub member: String,
    pub offset: u32,
    #[serde(rename = "type")]
    pub ty: String,
}

pub(crate) fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T, HostError> {
    let text = std::fs::read_to_string(path).map_err(|source| HostError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| HostError::Json {
        path: path.to_path_buf(),
        source,
    })
}

pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, HostError> {
    std::fs::read(path).map_err(|source| HostError::Read {
        path: path.to_path_buf(),
        source,
    })
}

impl UniformFile {
    /// The block's bytes, from `bytes_hex`.
    pub fn bytes(&self, path: &Path) -> Result<Vec<u8>, HostError> {
        let hex = self.bytes_hex.as_bytes();
        let bad = |what: &str| HostError::Package {
            path: path.to_path_buf(),
            what: format!("bytes_hex {what}"),
        };
        if hex.len() != self.size * 2 {
            return Err(bad(&format!(
                "holds {} hex digits for a block of {} bytes",
                hex.len(),
                self.size
            )));
        }
        hex.chunks(2)
            .map(|pair| {
                std::str::from_utf8(pair)
                    .ok()
                    .and_then(|s| u8::from_str_radix(s, 16).ok())
                    .ok_or_else(|| bad("is not hexadecimal"))
            })
            .collect()
    }

    /// Writes `values` (32-bit floats) over the member `name` of `bytes`.
    pub fn set_floats(
        &self,
        bytes: &mut [u8],
        name: &str,
        values: &[f32],
        path: &Path,
    ) -> Result<(), HostError> {
        let m = self
            .members
            .iter()
            .find(|m| m.member == name)
            .ok_or_else(|| HostError::Package {
                path: path.to_path_buf(),
                what: format!("the block has no member `{name}`"),
            })?;
        let start = m.offset as usize;
        let end = start + 4 * values.len();
        let slot = bytes
            .get_mut(start..end)
            .ok_or_else(|| HostError::Package {
                path: path.to_path_buf(),
                what: format!("`{name}` ({}) lies outside the block", m.ty),
            })?;
        for (chunk, v) in slot.chunks_mut(4).zip(values) {
            chunk.copy_from_slice(&v.to_le_bytes());
        }
        Ok(())
    }
}

/// A package folder and its description.
pub struct PackageDir {
    pub dir: PathBuf,
    pub package: Package,
}

impl PackageDir {
    pub fn open(dir: &Path) -> Result<Self, HostError> {
        let package: Package = read_json(&dir.join("nimbus-package.json"))?;
        if package.engine != "vulkan" {
            return Err(HostError::Package {
                path: dir.join("nimbus-package.json"),
                what: format!(
                    "engine is `{}`; this host draws `vulkan` packages (nimbus emit --engine vulkan)",
                    package.engine
                ),
            });
        }
        if package.texel_halves.len() != 256 {
            return Err(HostError::Package {
                path: dir.join("nimbus-package.json"),
                what: format!(
                    "texel_halves has {} entries, not 256",
                    package.texel_halves.len()
                ),
            });
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            package,
        })
    }

    pub fn path(&self, file: &str) -> PathBuf {
        self.dir.join(file)
    }

    /// The pair called `name`, or the first.
    pub fn pair(&self, name: Option<&str>) -> Result<&Pair, HostError> {
        let pairs = &self.package.pairs;
        match name {
            Some(n) => pairs
                .iter()
                .find(|p| p.pair == n)
                .ok_or_else(|| HostError::Package {
                    path: self.path("nimbus-package.json"),
                    what: format!(
                        "no pair `{n}`; it holds {}",
                        pairs
                            .iter()
                            .map(|p| p.pair.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                }),
            None => pairs.first().ok_or_else(|| HostError::Package {
                path: self.path("nimbus-package.json"),
                what: "no pairs".into(),
            }),
        }
    }
}
