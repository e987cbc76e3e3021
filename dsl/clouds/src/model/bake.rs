//! The bake of a baked path ([`crate::Path::bakes`]): a texture its own pass draws from the
//! cloud block and the noise, which the cloud pass reads in place of the procedural density.
//! Which texture, and its size, is the path's (`slices`: a stack of altitude slices; `blob2d`:
//! a map of column integrals; `impostor`: the volume's march result per direction); what makes
//! it out of date is the same for all: everything the block holds but the view.

use crate::Path;
use crate::model::march::CloudUniforms;

use super::blob2d::blob2d_size;
use super::impostor::impostor_size;
use super::slices::slices_size;

/// Members of the cloud block (dotted paths, each with everything under it) no bake depends
/// on: what only the view decides (its projection, the image's size and pixel mapping, the
/// frame's jitter), the composite's switches, the haze and the shadow map's cascade
/// transforms (the slices and the 2D map march their whole way to the sun and read no map;
/// the impostor's march reads it as the volume's does, and what it holds follows the sun, the
/// camera's place and the clouds, which the bake does depend on: the transforms only move as
/// its tiles are redrawn). Engine packages list them (`cloud_bake.ignores`) for their hosts'
/// redraw test.
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

/// Whether the member at dotted path `path` is one of [`BAKE_IGNORES`] or lies within one.
pub fn bake_ignores(path: &str) -> bool {
    BAKE_IGNORES.iter().any(|m| {
        path.strip_prefix(m)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with('.') || rest.starts_with('['))
    })
}

/// What the bake of the block `u` depends on: every leaf member's path and value but those of
/// [`BAKE_IGNORES`]. Two blocks with equal inputs have the same bake: a host redraws it when
/// they differ.
pub fn bake_inputs(
    u: &CloudUniforms,
) -> Result<nimbus_dsl::layout::Members, nimbus_dsl::layout::LayoutError> {
    use nimbus_dsl::layout::{UniformBytes, read_members};
    let bytes = u.to_uniform_bytes()?;
    Ok(read_members(CloudUniforms::shader_type(), &bytes)
        .into_iter()
        .filter(|(path, _)| !bake_ignores(path))
        .collect())
}

/// The bake's texture size (width, height) for `path`; none for a path without one.
pub fn bake_size(path: Path) -> Option<(u32, u32)> {
    match path {
        Path::Slices => Some(slices_size()),
        Path::Blob2d => Some(blob2d_size()),
        Path::Impostor => Some(impostor_size()),
        Path::Volume | Path::Mesh => None,
    }
}
