//! SPIR-V 1.0 for Vulkan. Writer flags are explicit: naga's default adds debug names only in
//! debug builds, which would make debug and release builds emit different words.

use naga::back::spv::{Options, PipelineOptions, WriterFlags};
use nimbus_dsl::ir::Stage;

use super::{Baked, Contents, naga_stage};

pub(super) fn write(baked: &Baked, stage: Stage, entry: &str) -> Result<Contents, String> {
    let options = Options {
        lang_version: (1, 0),
        flags: WriterFlags::ADJUST_COORDINATE_SPACE
            | WriterFlags::LABEL_VARYINGS
            | WriterFlags::CLAMP_FRAG_DEPTH,
        ..Default::default()
    };
    let pipeline = PipelineOptions {
        shader_stage: naga_stage(stage),
        entry_point: entry.to_string(),
    };
    let words = naga::back::spv::write_vec(&baked.module, &baked.info, &options, Some(&pipeline))
        .map_err(|e| e.to_string())?;
    Ok(Contents::SpirV(words))
}
