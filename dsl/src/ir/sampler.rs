//! How a sampler binding filters and addresses, declared with the binding so that every
//! consumer (the wgpu runtime, another engine reading the manifest) creates the same sampler.

/// What happens to coordinates outside [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AddressMode {
    Repeat,
    ClampToEdge,
    MirrorRepeat,
}

/// Texel filtering, for magnification, minification and between mip levels alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FilterMode {
    Nearest,
    Linear,
}

/// A sampler binding's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SamplerDesc {
    pub address: AddressMode,
    pub filter: FilterMode,
}

impl SamplerDesc {
    pub const LINEAR_REPEAT: SamplerDesc = SamplerDesc {
        address: AddressMode::Repeat,
        filter: FilterMode::Linear,
    };
    pub const LINEAR_CLAMP: SamplerDesc = SamplerDesc {
        address: AddressMode::ClampToEdge,
        filter: FilterMode::Linear,
    };
    pub const NEAREST_CLAMP: SamplerDesc = SamplerDesc {
        address: AddressMode::ClampToEdge,
        filter: FilterMode::Nearest,
    };
}

impl AddressMode {
    /// The WebGPU spelling (`repeat`, `clamp-to-edge`, `mirror-repeat`).
    pub fn name(self) -> &'static str {
        match self {
            AddressMode::Repeat => "repeat",
            AddressMode::ClampToEdge => "clamp-to-edge",
            AddressMode::MirrorRepeat => "mirror-repeat",
        }
    }
}

impl FilterMode {
    /// The WebGPU spelling (`nearest`, `linear`).
    pub fn name(self) -> &'static str {
        match self {
            FilterMode::Nearest => "nearest",
            FilterMode::Linear => "linear",
        }
    }
}
