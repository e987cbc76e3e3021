//! What can go wrong, naming the file, the field or the Vulkan call.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Error)]
pub enum HostError {
    #[error("cannot read `{}`: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("`{}` is not what this host reads: {source}", path.display())]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    #[error("`{}`: {what}", path.display())]
    Package { path: PathBuf, what: String },
    #[error("cannot decode the texture `{}`: {source}", path.display())]
    Image {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
    #[error("no Vulkan loader on this machine: {0}")]
    Loader(String),
    #[error("{call} failed: {result}")]
    Vulkan {
        call: &'static str,
        result: ash::vk::Result,
    },
    #[error("{0}")]
    Device(String),
}

/// Maps a failed Vulkan call to an error naming it.
pub(crate) fn vk(call: &'static str) -> impl FnOnce(ash::vk::Result) -> HostError {
    move |result| HostError::Vulkan { call, result }
}
