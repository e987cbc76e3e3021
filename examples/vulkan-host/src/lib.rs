//! A Nimbus Vulkan package drawn with the Vulkan API alone: what a Vulkan engine's integration
//! of the package looks like, in one place. It reads only the package's files
//! (`nimbus-package.json`, the uniform files, the textures, the SPIR-V), creates every
//! descriptor-set layout, sampler and pipeline from what the package states, and records the
//! frame the package's `frame` list describes, with the barriers its pass graph implies. Nothing
//! of Nimbus is linked.
//!
//! `cargo run -p nimbus-vulkan-host -- PACKAGE_DIR OUT.png [-r WxH] [--pair NAME]`

mod device;
mod error;
mod frame;
mod package;
mod vk_names;

pub use error::HostError;
pub use frame::Picture;
pub use package::PackageDir;

/// Draws one still frame of `pair` (the package's first when `None`) at `width` × `height`.
pub fn render(
    package: &std::path::Path,
    pair: Option<&str>,
    width: u32,
    height: u32,
) -> Result<Picture, HostError> {
    let pkg = PackageDir::open(package)?;
    frame::render(&pkg, pair, width, height)
}
