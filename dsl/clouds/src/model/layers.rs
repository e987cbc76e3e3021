//! Layer packing: four layers per lane group, one `vec4` per parameter, so one weather fetch and
//! one shape fetch serve four layers at once (as in @takram/three-clouds), and two groups give
//! eight layers. The uniform layout is derived from this one Rust definition.

use glam::{Mat4, Vec4};

use crate::{CloudLayer, Genus};
use nimbus_dsl::prelude::*;

/// Four layers' parameters, one lane each. A lane whose layer is absent has zero height and
/// zero density scale, which makes its density exactly 0.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct LayerGroup {
    /// Altitude of each layer's bottom (m).
    pub min_height: Vec4,
    /// Altitude of each layer's top (m).
    pub max_height: Vec4,
    pub density_scale: Vec4,
    pub shape_amount: Vec4,
    pub shape_detail_amount: Vec4,
    pub weather_exponent: Vec4,
    pub shape_altering_bias: Vec4,
    pub coverage_filter_width: Vec4,
    /// Density profile coefficients a, b, c, d of `a·e^(b·η) + c·η + d`.
    pub profile_a: Vec4,
    pub profile_b: Vec4,
    pub profile_c: Vec4,
    pub profile_d: Vec4,
    /// 1 for layers that cast shadows, else 0.
    pub shadow_mask: Vec4,
    /// Weather channel selection: `lane = channel_matrix * weather.rgba`.
    pub channel_matrix: Mat4,
}

impl LayerGroup {
    /// A group with no layers (every lane contributes 0).
    pub fn empty() -> Self {
        Self::pack(&[])
    }

    /// Packs up to four layers (extra layers are ignored; callers split into groups).
    pub fn pack(layers: &[CloudLayer]) -> Self {
        let lane = |f: &dyn Fn(&CloudLayer) -> f32, default: f32| -> Vec4 {
            Vec4::from_array(std::array::from_fn(|i| layers.get(i).map_or(default, f)))
        };
        let mut cols = [Vec4::ZERO; 4];
        for (i, l) in layers.iter().take(4).enumerate() {
            // Column c of the matrix multiplies weather component c; row i is lane i.
            cols[l.channel.index()][i] = 1.0;
        }
        Self {
            min_height: lane(&|l| l.altitude, 0.0),
            max_height: lane(&|l| l.altitude + l.height, 0.0),
            density_scale: lane(&|l| l.density_scale, 0.0),
            shape_amount: lane(&|l| l.shape_amount, 0.0),
            shape_detail_amount: lane(&|l| l.shape_detail_amount, 0.0),
            weather_exponent: lane(&|l| l.weather_exponent, 1.0),
            shape_altering_bias: lane(&|l| l.shape_altering_bias, 1.0),
            coverage_filter_width: lane(&|l| l.coverage_filter_width, 1.0),
            profile_a: lane(&|l| l.density_profile.a, 0.0),
            profile_b: lane(&|l| l.density_profile.b, 0.0),
            profile_c: lane(&|l| l.density_profile.c, 0.0),
            profile_d: lane(&|l| l.density_profile.d, 0.0),
            shadow_mask: lane(&|l| if l.shadow { 1.0 } else { 0.0 }, 0.0),
            channel_matrix: Mat4::from_cols(cols[0], cols[1], cols[2], cols[3]),
        }
    }

    /// The groups of a genus: `[group0, group1]` (group 1 empty for four layers or fewer).
    pub fn from_genus(genus: &Genus) -> [LayerGroup; 2] {
        let (a, b) = genus.layers.split_at(genus.layers.len().min(4));
        [LayerGroup::pack(a), LayerGroup::pack(b)]
    }
}
