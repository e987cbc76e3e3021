//! The Vulkan enum and flag names the package writes, as the values `ash` takes. A C host reads
//! the same names as its own enumerants.

use ash::vk;

/// Flags from `|`-joined names, or the first name this table does not know.
fn flags<T: Copy + std::ops::BitOr<Output = T>>(
    text: &str,
    empty: T,
    table: &[(&str, T)],
) -> Result<T, String> {
    let mut out = empty;
    for name in text.split('|').map(str::trim).filter(|n| !n.is_empty()) {
        let (_, v) = table
            .iter()
            .find(|(n, _)| *n == name)
            .ok_or_else(|| name.to_string())?;
        out = out | *v;
    }
    Ok(out)
}

pub fn stages(text: &str) -> Result<vk::PipelineStageFlags, String> {
    use vk::PipelineStageFlags as S;
    flags(
        text,
        S::empty(),
        &[
            ("VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT", S::TOP_OF_PIPE),
            ("VK_PIPELINE_STAGE_VERTEX_SHADER_BIT", S::VERTEX_SHADER),
            ("VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT", S::FRAGMENT_SHADER),
            ("VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT", S::COMPUTE_SHADER),
            (
                "VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT",
                S::COLOR_ATTACHMENT_OUTPUT,
            ),
            ("VK_PIPELINE_STAGE_TRANSFER_BIT", S::TRANSFER),
        ],
    )
}

pub fn access(text: &str) -> Result<vk::AccessFlags, String> {
    use vk::AccessFlags as A;
    flags(
        text,
        A::empty(),
        &[
            ("VK_ACCESS_SHADER_READ_BIT", A::SHADER_READ),
            ("VK_ACCESS_SHADER_WRITE_BIT", A::SHADER_WRITE),
            ("VK_ACCESS_UNIFORM_READ_BIT", A::UNIFORM_READ),
            (
                "VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT",
                A::COLOR_ATTACHMENT_WRITE,
            ),
            ("VK_ACCESS_TRANSFER_READ_BIT", A::TRANSFER_READ),
        ],
    )
}

pub fn layout(name: &str) -> Result<vk::ImageLayout, String> {
    Ok(match name {
        "VK_IMAGE_LAYOUT_UNDEFINED" => vk::ImageLayout::UNDEFINED,
        "VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL" => vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        "VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL" => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        _ => return Err(name.to_string()),
    })
}

pub fn filter(name: &str) -> Result<vk::Filter, String> {
    Ok(match name {
        "VK_FILTER_NEAREST" => vk::Filter::NEAREST,
        "VK_FILTER_LINEAR" => vk::Filter::LINEAR,
        _ => return Err(name.to_string()),
    })
}

pub fn mipmap_mode(name: &str) -> Result<vk::SamplerMipmapMode, String> {
    Ok(match name {
        "VK_SAMPLER_MIPMAP_MODE_NEAREST" => vk::SamplerMipmapMode::NEAREST,
        "VK_SAMPLER_MIPMAP_MODE_LINEAR" => vk::SamplerMipmapMode::LINEAR,
        _ => return Err(name.to_string()),
    })
}

pub fn address_mode(name: &str) -> Result<vk::SamplerAddressMode, String> {
    Ok(match name {
        "VK_SAMPLER_ADDRESS_MODE_REPEAT" => vk::SamplerAddressMode::REPEAT,
        "VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT" => vk::SamplerAddressMode::MIRRORED_REPEAT,
        "VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE" => vk::SamplerAddressMode::CLAMP_TO_EDGE,
        _ => return Err(name.to_string()),
    })
}

pub fn descriptor_type(name: &str) -> Result<vk::DescriptorType, String> {
    Ok(match name {
        "VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER" => vk::DescriptorType::UNIFORM_BUFFER,
        "VK_DESCRIPTOR_TYPE_STORAGE_BUFFER" => vk::DescriptorType::STORAGE_BUFFER,
        "VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE" => vk::DescriptorType::SAMPLED_IMAGE,
        "VK_DESCRIPTOR_TYPE_SAMPLER" => vk::DescriptorType::SAMPLER,
        _ => return Err(name.to_string()),
    })
}
