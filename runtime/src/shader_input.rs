//! What a pipeline's shader module is created from.

use nimbus_codegen::Generated;

/// The naga module codegen lowered from the DSL's IR (the default: no text is parsed), or the
/// WGSL codegen printed from the same IR, parsed by wgpu — the text WebGPU hosts load, kept
/// selectable so a test can show that both draw the same picture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShaderInput {
    #[default]
    Lowered,
    PrintedWgsl,
}

impl ShaderInput {
    /// The shader source of `generated` in this form; the lowered module is moved out.
    pub(crate) fn source(self, generated: &mut Generated) -> wgpu::ShaderSource<'static> {
        match self {
            ShaderInput::Lowered => wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(
                std::mem::take(&mut generated.naga),
            )),
            ShaderInput::PrintedWgsl => {
                wgpu::ShaderSource::Wgsl(std::borrow::Cow::Owned(generated.wgsl.clone()))
            }
        }
    }
}
