//! The bake of a baked path ([`crate::Path::bakes`]): a texture its own pass draws from the
//! cloud block and the noise, which the cloud pass reads in place of the procedural density.
//! Which texture, and its size, is the path's (`slices`: a stack of altitude slices; `blob2d`:
//! a map of column integrals; `impostor`: the volume's march result per direction; `mesh`: the
//! cluster table of fitted puffs); what makes
//! it out of date is the same for all: everything the block holds but the view.

use crate::Path;
use crate::key::CloudKey;
use crate::model::march::CloudUniforms;

use super::blob2d::blob2d_size;
use super::impostor::impostor_size;
use super::mesh::mesh_size;
use super::slices::slices_size;

/// Members of the cloud block (dotted paths, each with everything under it) no bake depends
/// on: what only the view decides (its projection, the image's size and pixel mapping, the
/// frame's jitter), the composite's switches, the haze, and the shadow map's cascade
/// transforms ([`MAP_READS`] and [`VIEW_READS`] aside). Engine packages list a pair's own
/// ([`bake_ignores`]: `cloud_bake.ignores`) for their hosts' redraw test.
pub const BAKE_IGNORES: [&str; 11] = [
    "inverse_view_projection",
    "resolution",
    "pixel_offset",
    "pixel_scale",
    "subpixel",
    "frame",
    "jitter",
    "composite",
    "haze",
    "shadow.lookup",
    "shadow.inverse_matrix",
];

/// The member of [`BAKE_IGNORES`] the bake of a key that samples the shadow map
/// ([`CloudKey::uses_shadow_map`]) does depend on: each bake lights its texels as the volume's
/// march does at its key, and that reads the map through the cascades' transforms. With
/// cascades in rotation (the JavaScript hosts' default) a moved sun redraws the tiles in turn,
/// each in bands ([`super::tile_bands`]); each tile copied in moves its transform, and the bake
/// is drawn again until every tile is the new sun's: a bake made with the first tile alone
/// would keep the old sun's shadows for good.
pub const MAP_READS: &str = "shadow.lookup";

/// The members of [`BAKE_IGNORES`] an impostor that bakes the whole view
/// ([`CloudKey::bakes_view`]) depends on as well: the composite's, which its bake runs.
pub const VIEW_READS: [&str; 2] = ["composite", "haze"];

/// The members of the cloud block the bake of `key` does not depend on.
pub fn bake_ignores(key: &CloudKey) -> Vec<&'static str> {
    BAKE_IGNORES
        .iter()
        .copied()
        .filter(|m| !(key.uses_shadow_map() && *m == MAP_READS))
        .filter(|m| !(key.bakes_view() && VIEW_READS.contains(m)))
        .collect()
}

/// Whether the member at dotted path `member` is one of `ignores` or lies within one.
fn ignored(ignores: &[&str], member: &str) -> bool {
    ignores.iter().any(|m| {
        member
            .strip_prefix(m)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with('.') || rest.starts_with('['))
    })
}

/// What the bake of `key` from the block `u` depends on: every leaf member's path and value
/// but those of [`bake_ignores`]. Two blocks with equal inputs have the same bake: a host
/// redraws it when they differ.
pub fn bake_inputs(
    u: &CloudUniforms,
    key: &CloudKey,
) -> Result<nimbus_dsl::layout::Members, nimbus_dsl::layout::LayoutError> {
    use nimbus_dsl::layout::{UniformBytes, read_members};
    let bytes = u.to_uniform_bytes()?;
    let ignores = bake_ignores(key);
    Ok(read_members(CloudUniforms::shader_type(), &bytes)
        .into_iter()
        .filter(|(member, _)| !ignored(&ignores, member))
        .collect())
}

/// The bake's texture size (width, height) for `path`; none for a path without one.
pub fn bake_size(path: Path) -> Option<(u32, u32)> {
    match path {
        Path::Slices => Some(slices_size()),
        Path::Blob2d => Some(blob2d_size()),
        Path::Impostor => Some(impostor_size()),
        Path::Mesh => Some(mesh_size()),
        Path::Volume => None,
    }
}
