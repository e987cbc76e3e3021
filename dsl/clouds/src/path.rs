//! Paths: the ways a genus can be drawn. Ray marching the procedural volume is one; the others
//! bake part of that same model into a texture once, and draw from it, for devices and views
//! where a full march costs too much (a phone, a background sky). A path is a generation-time
//! choice like a toggle: it is part of the cloud key, so it names shaders, and a scene picks
//! it (`path = "slices"` in a scene file, `--path` on the command line).
//!
//! Every path draws from the genus' own `#[shader_fn]` model (density, phase, lighting), so its
//! error against the reference can be measured beside the presets (`nimbus tradeoff`).

use serde::{Deserialize, Serialize};

/// How the cloud pass draws the genus.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Path {
    /// Ray marching the procedural density, each sample lit by its own secondary marches.
    #[default]
    Volume,
    /// The density and the optical depths its lighting needs, baked by a pass of their own
    /// into a stack of altitude slices around the camera (`model::slices`); the view ray
    /// walks the slices, each sample two texture reads in place of the noise and the
    /// secondary marches, lit by the same phase and scattering functions.
    Slices,
    /// The picture around the camera baked from every direction into one octahedral map by a
    /// pass of its own (`model::impostor`: the volume's own pixel per texel, marched and
    /// composited over the sky or the ground with the air and the haze); the cloud pass reads
    /// its ray's texels and draws the sun's disc: two texture reads a pixel. Over the engine's
    /// depth the map holds the march's result and the cloud pass composites it per pixel.
    Impostor,
    /// The clouds around the camera as a few thousand instanced clusters of soft puffs, each
    /// puff fitted by a pass of its own to the genus' density in its cell (its mass, mean and
    /// spread) with the optical depth to the sun beyond it (`model::mesh`); the cloud pass draws
    /// the puffs a ray passes in closed form, lit by the march's source term: no noise, no
    /// march.
    Mesh,
    /// The sky from a 2D map: the genus' columns in two altitude bands (optical depth, the mean
    /// and spread of the density's altitude, the optical depth to the sun at four depths) baked
    /// around the camera by a pass of their own (`model::blob2d`); a view ray's few samples per
    /// band each read their column and are lit by the march's own source term, with no noise
    /// and no secondary march.
    Blob2d,
}

impl Path {
    /// Every path, in the order `nimbus list` shows them.
    pub const ALL: [Path; 5] = [
        Path::Volume,
        Path::Slices,
        Path::Impostor,
        Path::Mesh,
        Path::Blob2d,
    ];

    /// The scene-file and command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Path::Volume => "volume",
            Path::Slices => "slices",
            Path::Impostor => "impostor",
            Path::Mesh => "mesh",
            Path::Blob2d => "blob2d",
        }
    }

    /// The tag in shader key names (none for the volume, which every key had before paths).
    pub fn tag(self) -> Option<&'static str> {
        match self {
            Path::Volume => None,
            other => Some(other.name()),
        }
    }

    /// One line on what the path draws.
    pub fn doc(self) -> &'static str {
        match self {
            Path::Volume => "ray march through the procedural density (every effect)",
            Path::Slices => {
                "altitude slices baked around the camera (density and optical depths), walked \
                 by the view ray: two texture reads a sample"
            }
            Path::Impostor => {
                "the picture around the camera baked from every direction into one octahedral \
                 impostor (the volume's own pixel per texel, clouds, sky, air and haze): two \
                 texture reads a pixel"
            }
            Path::Mesh => {
                "instanced clusters of soft puffs fitted to the genus' density around the camera, \
                 drawn in closed form and lit by the model: no march"
            }
            Path::Blob2d => {
                "a 2D map of the clouds' columns (two altitude bands) baked around the camera; a \
                 view ray's few samples each read their column, lit as the march lights a sample \
                 (no noise, no secondary march)"
            }
        }
    }

    /// Whether the path draws from a bake of its own pass (`model::bake`): the slice stack
    /// ([`Path::Slices`]), the octahedral impostor ([`Path::Impostor`]) or the 2D map
    /// ([`Path::Blob2d`]) or the cluster table ([`Path::Mesh`]).
    pub fn bakes(self) -> bool {
        !matches!(self, Path::Volume)
    }

    /// The path named `s` (any case, `_` for `-`).
    pub fn parse(s: &str) -> Option<Path> {
        let s = s.trim().to_ascii_lowercase().replace('_', "-");
        Path::ALL.iter().copied().find(|p| p.name() == s)
    }
}

impl std::fmt::Display for Path {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(feature = "clap")]
impl clap::ValueEnum for Path {
    fn value_variants<'a>() -> &'a [Self] {
        &Path::ALL
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()).help(self.doc()))
    }
}
