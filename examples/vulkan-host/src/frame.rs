//! One still frame of a pair, as the package's `frame` list orders it: `sun_light` (compute),
//! `shadow` into the shadow atlas, `air` into the air table, `clouds` into `clouds_hdr`, and
//! `display` into the picture. A still frame neither upscales nor accumulates, so `resolve` is
//! not drawn and `display` reads `clouds_hdr` (the package's `shown`).
//!
//! Every binding slot is filled from the resource its `holds.id` names; every layout, sampler
//! and stage comes from the pass's `descriptor_set_layout`; the target is the one its `writes`
//! names; and the barriers recorded before each pass are its `vulkan_barriers`, the ones the
//! pass graph implies (the block `sun_light` writes made visible to uniform reads, each target
//! made a colour attachment before its pass and shader-readable before the pass that samples
//! it). Only the read-back of the picture is the host's own.

use std::collections::HashMap;

use ash::vk;

use crate::device::{Buffer, Device, Image};
use crate::error::{HostError, vk};
use crate::package::{PackageDir, Pair, Pass, SamplerState, UniformFile, read_bytes, read_json};
use crate::vk_names;

const HDR: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
const SCREEN: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The drawn picture: RGBA8, rows top-down.
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
    /// The Vulkan device that drew it.
    pub device: String,
}

/// Everything made for a frame, destroyed with it.
struct Objects<'d> {
    gpu: &'d Device,
    buffers: Vec<Buffer>,
    images: Vec<Image>,
    samplers: Vec<vk::Sampler>,
    modules: Vec<vk::ShaderModule>,
    set_layouts: Vec<vk::DescriptorSetLayout>,
    pipeline_layouts: Vec<vk::PipelineLayout>,
    pipelines: Vec<vk::Pipeline>,
    pool: vk::DescriptorPool,
}

impl Drop for Objects<'_> {
    fn drop(&mut self) {
        let d = &self.gpu.device;
        // SAFETY: the queue is idle (every submit waits) and nothing else holds these.
        unsafe {
            for p in self.pipelines.drain(..) {
                d.destroy_pipeline(p, None);
            }
            for l in self.pipeline_layouts.drain(..) {
                d.destroy_pipeline_layout(l, None);
            }
            d.destroy_descriptor_pool(self.pool, None);
            for l in self.set_layouts.drain(..) {
                d.destroy_descriptor_set_layout(l, None);
            }
            for m in self.modules.drain(..) {
                d.destroy_shader_module(m, None);
            }
            for s in self.samplers.drain(..) {
                d.destroy_sampler(s, None);
            }
            for i in self.images.drain(..) {
                d.destroy_image_view(i.view, None);
                d.destroy_image(i.image, None);
                d.free_memory(i.memory, None);
            }
            for b in self.buffers.drain(..) {
                d.destroy_buffer(b.buffer, None);
                d.free_memory(b.memory, None);
            }
        }
    }
}

/// What a binding slot is filled with.
#[derive(Clone, Copy)]
enum Resource {
    Buffer(usize),
    Image(usize),
}

/// The target a drawn pass writes (as its `writes` names it), and its size; `None` for the
/// passes a still frame does not draw (`resolve`) and for `sun_light`.
fn target_of(p: &Pass, pair: &Pair, width: u32, height: u32) -> Option<(&'static str, u32, u32)> {
    match p.writes.as_str() {
        "shadow_atlas" => pair
            .shadow_atlas
            .as_ref()
            .map(|a| ("shadow_atlas", a.width, a.height)),
        "air_table" => pair
            .air_table
            .as_ref()
            .map(|a| ("air_table", a.width, a.height)),
        "clouds_hdr" => Some(("clouds_hdr", width, height)),
        "screen" => Some(("screen", width, height)),
        _ => None,
    }
}

/// Renders one frame of `pair` (the first when `None`) at `width` × `height`.
pub fn render(
    pkg: &PackageDir,
    pair: Option<&str>,
    width: u32,
    height: u32,
) -> Result<Picture, HostError> {
    let pair = pkg.pair(pair)?;
    if pair.scene_depth {
        return Err(HostError::Package {
            path: pkg.path("nimbus-package.json"),
            what: format!(
                "the pair {} reads the engine's depth; this host draws no scene of its own",
                pair.pair
            ),
        });
    }
    let gpu = Device::new()?;
    let mut o = Objects {
        gpu: &gpu,
        buffers: Vec::new(),
        images: Vec::new(),
        samplers: Vec::new(),
        modules: Vec::new(),
        set_layouts: Vec::new(),
        pipeline_layouts: Vec::new(),
        pipelines: Vec::new(),
        pool: vk::DescriptorPool::null(),
    };
    let mut resources: HashMap<String, Resource> = HashMap::new();

    // Uniform blocks: the pair's (with this frame's resolution), the resolve's, the display's.
    let block_path = pkg.path(&pair.uniforms);
    let block: UniformFile = read_json(&block_path)?;
    let mut bytes = block.bytes(&block_path)?;
    block.set_floats(
        &mut bytes,
        "resolution",
        &[width as f32, height as f32],
        &block_path,
    )?;
    let uniform = vk::BufferUsageFlags::UNIFORM_BUFFER;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER | uniform;
    o.buffers.push(gpu.buffer(&bytes, uniform)?);
    resources.insert("pair_inputs".into(), Resource::Buffer(o.buffers.len() - 1));
    // The block the sun_light kernel completes (the inputs' bytes until it runs).
    o.buffers.push(gpu.buffer(&bytes, storage)?);
    resources.insert("pair".into(), Resource::Buffer(o.buffers.len() - 1));
    for name in ["resolve", "display"] {
        let path = pkg.path(&format!("uniforms/{name}.json"));
        let file: UniformFile = read_json(&path)?;
        let mut bytes = file.bytes(&path)?;
        // Every block that knows the output size is told this frame's.
        if file.members.iter().any(|m| m.member == "resolution") {
            file.set_floats(
                &mut bytes,
                "resolution",
                &[width as f32, height as f32],
                &path,
            )?;
        }
        o.buffers.push(gpu.buffer(&bytes, uniform)?);
        resources.insert(name.into(), Resource::Buffer(o.buffers.len() - 1));
    }

    // The noise textures, each byte widened to a half float through texel_halves.
    let halves = &pkg.package.texel_halves;
    for t in &pkg.package.textures {
        let path = pkg.path(&t.file);
        let (format, channels) = match t.format.as_str() {
            "r16float" => (vk::Format::R16_SFLOAT, 1),
            "rgba16float" => (HDR, 4),
            other => {
                return Err(HostError::Package {
                    path: pkg.path("nimbus-package.json"),
                    what: format!("texture `{}` has the format `{other}`", t.name),
                });
            }
        };
        let bytes = if t.dimension == "2d" {
            image::load_from_memory_with_format(&read_bytes(&path)?, image::ImageFormat::Png)
                .map_err(|source| HostError::Image {
                    path: path.clone(),
                    source,
                })?
                .to_rgba8()
                .into_raw()
        } else {
            read_bytes(&path)?
        };
        let [w, h, d] = match t.size.as_slice() {
            [w, h] => [*w, *h, 1],
            [w, h, d] => [*w, *h, *d],
            _ => {
                return Err(HostError::Package {
                    path: pkg.path("nimbus-package.json"),
                    what: format!(
                        "texture `{}` has a size of {} numbers",
                        t.name,
                        t.size.len()
                    ),
                });
            }
        };
        let texels = (w * h * d) as usize;
        if bytes.len() != texels * channels {
            return Err(HostError::Package {
                path,
                what: format!(
                    "{} bytes for {w}×{h}×{d} texels of {channels} byte(s)",
                    bytes.len()
                ),
            });
        }
        let wide: Vec<u8> = bytes
            .iter()
            .flat_map(|b| halves[*b as usize].to_le_bytes())
            .collect();
        let staging = gpu.buffer(&wide, vk::BufferUsageFlags::TRANSFER_SRC)?;
        let extent = vk::Extent3D {
            width: w,
            height: h,
            depth: d,
        };
        let img = gpu.image(
            extent,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        )?;
        gpu.submit(|cb| {
            gpu.transition(
                cb,
                img.image,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::PipelineStageFlags::TOP_OF_PIPE,
                    vk::AccessFlags::empty(),
                ),
                (
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(extent);
            unsafe {
                gpu.device.cmd_copy_buffer_to_image(
                    cb,
                    staging.buffer,
                    img.image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[region],
                );
            }
            gpu.transition(
                cb,
                img.image,
                (
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    vk::PipelineStageFlags::FRAGMENT_SHADER,
                    vk::AccessFlags::SHADER_READ,
                ),
            );
            Ok(())
        })?;
        o.buffers.push(staging);
        o.images.push(img);
        resources.insert(t.name.clone(), Resource::Image(o.images.len() - 1));
    }

    // The passes' targets.
    for p in &pair.passes {
        if let Some((name, w, h)) = target_of(p, pair, width, height) {
            let (format, usage) = if name == "screen" {
                (SCREEN, vk::ImageUsageFlags::TRANSFER_SRC)
            } else {
                (HDR, vk::ImageUsageFlags::SAMPLED)
            };
            let extent = vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            };
            o.images.push(gpu.image(
                extent,
                format,
                usage | vk::ImageUsageFlags::COLOR_ATTACHMENT,
            )?);
            resources.insert(name.into(), Resource::Image(o.images.len() - 1));
        }
    }
    // With no resolve drawn, display reads the clouds' target.
    if let Some(r) = resources.get("clouds_hdr").copied() {
        resources.insert("shown".into(), r);
    }

    // Descriptor sets and pipelines, pass by pass.
    let drawn: Vec<&Pass> = pair
        .passes
        .iter()
        .filter(|p| p.writes == "pair" || target_of(p, pair, width, height).is_some())
        .collect();
    let sizes = [
        vk::DescriptorPoolSize {
            ty: vk::DescriptorType::UNIFORM_BUFFER,
            descriptor_count: 32,
        },
        vk::DescriptorPoolSize {
            ty: vk::DescriptorType::STORAGE_BUFFER,
            descriptor_count: 8,
        },
        vk::DescriptorPoolSize {
            ty: vk::DescriptorType::SAMPLED_IMAGE,
            descriptor_count: 64,
        },
        vk::DescriptorPoolSize {
            ty: vk::DescriptorType::SAMPLER,
            descriptor_count: 32,
        },
    ];
    o.pool = unsafe {
        gpu.device.create_descriptor_pool(
            &vk::DescriptorPoolCreateInfo::default()
                .max_sets(drawn.len() as u32)
                .pool_sizes(&sizes),
            None,
        )
    }
    .map_err(vk("vkCreateDescriptorPool"))?;
    let mut prepared = Vec::new();
    for p in &drawn {
        prepared.push(prepare(pkg, p, pair, width, height, &mut o, &resources)?);
    }

    // The frame.
    let screen = match resources.get("screen") {
        Some(Resource::Image(i)) => *i,
        _ => {
            return Err(HostError::Package {
                path: pkg.path("nimbus-package.json"),
                what: format!("the pair {} has no display pass", pair.pair),
            });
        }
    };
    let readback = gpu.buffer(
        &vec![0u8; (width * height * 4) as usize],
        vk::BufferUsageFlags::TRANSFER_DST,
    )?;
    gpu.submit(|cb| {
        for (p, prep) in drawn.iter().zip(&prepared) {
            record(&gpu, cb, p, prep, &o, &resources, pair, width, height);
        }
        let shown = &o.images[screen];
        gpu.transition(
            cb,
            shown.image,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
            (
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_READ,
            ),
        );
        let region = vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(shown.extent);
        unsafe {
            gpu.device.cmd_copy_image_to_buffer(
                cb,
                shown.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.buffer,
                &[region],
            );
        }
        Ok(())
    })?;
    let rgba = gpu.read(&readback, (width * height * 4) as usize)?;
    o.buffers.push(readback);
    let device = gpu.name.clone();
    drop(o);
    Ok(Picture {
        width,
        height,
        rgba,
        device,
    })
}

/// A pass ready to record: its pipeline, layout and descriptor set.
struct Prepared {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set: vk::DescriptorSet,
    compute: bool,
    barriers: Vec<Recorded>,
}

fn prepare(
    pkg: &PackageDir,
    p: &Pass,
    pair: &Pair,
    width: u32,
    height: u32,
    o: &mut Objects,
    resources: &HashMap<String, Resource>,
) -> Result<Prepared, HostError> {
    let gpu = o.gpu;
    let json = pkg.path("nimbus-package.json");
    let bad = |what: String| HostError::Package {
        path: json.clone(),
        what: format!("pass `{}`: {what}", p.pass),
    };
    let layout_desc = p
        .descriptor_set_layout
        .as_ref()
        .ok_or_else(|| bad("no descriptor_set_layout".into()))?;
    if layout_desc.set != 0 {
        return Err(bad(format!(
            "descriptor set {} (this host binds set 0)",
            layout_desc.set
        )));
    }
    // The layout, as the package states it.
    let mut bindings = Vec::new();
    for b in &layout_desc.bindings {
        let ty = vk_names::descriptor_type(&b.descriptor_type)
            .map_err(|n| bad(format!("descriptor type {n}")))?;
        bindings.push(
            vk::DescriptorSetLayoutBinding::default()
                .binding(b.binding)
                .descriptor_type(ty)
                .descriptor_count(b.descriptor_count)
                .stage_flags(vk::ShaderStageFlags::from_raw(b.stage_flags)),
        );
    }
    let set_layout = unsafe {
        gpu.device.create_descriptor_set_layout(
            &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
            None,
        )
    }
    .map_err(vk("vkCreateDescriptorSetLayout"))?;
    o.set_layouts.push(set_layout);
    let layouts = [set_layout];
    let layout = unsafe {
        gpu.device.create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts),
            None,
        )
    }
    .map_err(vk("vkCreatePipelineLayout"))?;
    o.pipeline_layouts.push(layout);
    let set = unsafe {
        gpu.device.allocate_descriptor_sets(
            &vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(o.pool)
                .set_layouts(&layouts),
        )
    }
    .map_err(vk("vkAllocateDescriptorSets"))?[0];

    // Every slot from the resource it holds.
    for b in &layout_desc.bindings {
        let slot = p
            .bindings
            .iter()
            .find(|s| s.binding == b.binding)
            .ok_or_else(|| bad(format!("binding {} is not described", b.binding)))?;
        let ty = vk_names::descriptor_type(&b.descriptor_type)
            .map_err(|n| bad(format!("descriptor type {n}")))?;
        let write = vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(b.binding)
            .descriptor_type(ty);
        match ty {
            vk::DescriptorType::SAMPLER => {
                let s = b
                    .sampler
                    .as_ref()
                    .ok_or_else(|| bad(format!("sampler `{}` has no state", slot.name)))?;
                let sampler = make_sampler(gpu, s).map_err(|n| {
                    bad(format!("sampler `{}`: unknown Vulkan name {n}", slot.name))
                })??;
                o.samplers.push(sampler);
                let info = [vk::DescriptorImageInfo::default().sampler(sampler)];
                unsafe {
                    gpu.device
                        .update_descriptor_sets(&[write.image_info(&info)], &[])
                };
            }
            vk::DescriptorType::SAMPLED_IMAGE => {
                let Some(Resource::Image(i)) = resources.get(&slot.holds.id) else {
                    return Err(bad(format!(
                        "`{}` holds `{}`, which this host does not have",
                        slot.name, slot.holds.id
                    )));
                };
                let info = [vk::DescriptorImageInfo::default()
                    .image_view(o.images[*i].view)
                    .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
                unsafe {
                    gpu.device
                        .update_descriptor_sets(&[write.image_info(&info)], &[])
                };
            }
            _ => {
                let Some(Resource::Buffer(i)) = resources.get(&slot.holds.id) else {
                    return Err(bad(format!(
                        "`{}` holds `{}`, which this host does not have",
                        slot.name, slot.holds.id
                    )));
                };
                let buf = &o.buffers[*i];
                let info = [vk::DescriptorBufferInfo::default()
                    .buffer(buf.buffer)
                    .offset(0)
                    .range(vk::WHOLE_SIZE)];
                unsafe {
                    gpu.device
                        .update_descriptor_sets(&[write.buffer_info(&info)], &[])
                };
            }
        }
    }

    // The shader modules of the pass's files.
    let mut stages = Vec::new();
    let mut names = Vec::new();
    for f in &p.files {
        let path = pkg.path(&f.file);
        let words = ash::util::read_spv(&mut std::io::Cursor::new(read_bytes(&path)?)).map_err(
            |source| HostError::Read {
                path: path.clone(),
                source,
            },
        )?;
        let module = unsafe {
            gpu.device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
        }
        .map_err(vk("vkCreateShaderModule"))?;
        o.modules.push(module);
        let stage = match f.stage.as_deref() {
            Some("vertex") => vk::ShaderStageFlags::VERTEX,
            Some("fragment") => vk::ShaderStageFlags::FRAGMENT,
            Some("compute") => vk::ShaderStageFlags::COMPUTE,
            other => return Err(bad(format!("`{}` has stage {other:?}", f.file))),
        };
        let entry = f
            .entry_point
            .clone()
            .ok_or_else(|| bad(format!("`{}` names no entry point", f.file)))?;
        names.push(std::ffi::CString::new(entry).map_err(|e| bad(e.to_string()))?);
        stages.push((stage, module));
    }
    let infos: Vec<vk::PipelineShaderStageCreateInfo> = stages
        .iter()
        .zip(&names)
        .map(|((stage, module), name)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(*stage)
                .module(*module)
                .name(name)
        })
        .collect();

    let compute = p.dispatch.is_some();
    let pipeline = if compute {
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(infos[0])
            .layout(layout);
        unsafe {
            gpu.device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, e)| vk("vkCreateComputePipelines")(e))?[0]
    } else {
        let format = match target_of(p, pair, width, height) {
            Some(("screen", ..)) => SCREEN,
            _ => HDR,
        };
        let formats = [format];
        let mut rendering =
            vk::PipelineRenderingCreateInfo::default().color_attachment_formats(&formats);
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let attachments = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&infos)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        unsafe {
            gpu.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, e)| vk("vkCreateGraphicsPipelines")(e))?[0]
    };
    o.pipelines.push(pipeline);
    let barriers = barriers(p, o, resources, &bad)?;
    Ok(Prepared {
        pipeline,
        layout,
        set,
        compute,
        barriers,
    })
}

/// The sampler the package describes, or the first Vulkan name this host does not know.
fn make_sampler(gpu: &Device, s: &SamplerState) -> Result<Result<vk::Sampler, HostError>, String> {
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(vk_names::filter(&s.mag_filter)?)
        .min_filter(vk_names::filter(&s.min_filter)?)
        .mipmap_mode(vk_names::mipmap_mode(&s.mipmap_mode)?)
        .address_mode_u(vk_names::address_mode(&s.address_mode_u)?)
        .address_mode_v(vk_names::address_mode(&s.address_mode_v)?)
        .address_mode_w(vk_names::address_mode(&s.address_mode_w)?)
        .max_lod(vk::LOD_CLAMP_NONE);
    Ok(unsafe { gpu.device.create_sampler(&info, None) }.map_err(vk("vkCreateSampler")))
}

/// A barrier of the pass graph, ready to record.
struct Recorded {
    src_stage: vk::PipelineStageFlags,
    dst_stage: vk::PipelineStageFlags,
    src_access: vk::AccessFlags,
    dst_access: vk::AccessFlags,
    /// Images: which, and the layouts.
    image: Option<(vk::Image, vk::ImageLayout, vk::ImageLayout)>,
}

/// The pass's barriers as the package states them, each resource found by its id.
fn barriers(
    p: &Pass,
    o: &Objects,
    resources: &HashMap<String, Resource>,
    bad: &dyn Fn(String) -> HostError,
) -> Result<Vec<Recorded>, HostError> {
    let mut out = Vec::new();
    for b in p.vulkan_barriers.iter().flatten() {
        let name = |n: String| {
            bad(format!(
                "barrier on `{}`: unknown Vulkan name {n}",
                b.resource
            ))
        };
        let image = match resources.get(&b.resource) {
            Some(Resource::Image(i)) => {
                let layout = |l: &Option<String>| {
                    l.as_deref()
                        .map(vk_names::layout)
                        .transpose()
                        .map_err(name)
                        .map(|l| l.unwrap_or(vk::ImageLayout::UNDEFINED))
                };
                Some((
                    o.images[*i].image,
                    layout(&b.old_layout)?,
                    layout(&b.new_layout)?,
                ))
            }
            Some(Resource::Buffer(_)) => None,
            None => {
                return Err(bad(format!(
                    "a barrier on `{}`, which this host does not have",
                    b.resource
                )));
            }
        };
        out.push(Recorded {
            src_stage: vk_names::stages(&b.src_stage_mask).map_err(name)?,
            dst_stage: vk_names::stages(&b.dst_stage_mask).map_err(name)?,
            src_access: vk_names::access(&b.src_access_mask).map_err(name)?,
            dst_access: vk_names::access(&b.dst_access_mask).map_err(name)?,
            image,
        });
    }
    Ok(out)
}

/// Records one pass, after the barriers the package states for it.
#[allow(clippy::too_many_arguments)]
fn record(
    gpu: &Device,
    cb: vk::CommandBuffer,
    p: &Pass,
    prep: &Prepared,
    o: &Objects,
    resources: &HashMap<String, Resource>,
    pair: &Pair,
    width: u32,
    height: u32,
) {
    let d = &gpu.device;
    for b in &prep.barriers {
        match b.image {
            Some((image, old, new)) => gpu.transition(
                cb,
                image,
                (old, b.src_stage, b.src_access),
                (new, b.dst_stage, b.dst_access),
            ),
            None => {
                let barrier = vk::MemoryBarrier::default()
                    .src_access_mask(b.src_access)
                    .dst_access_mask(b.dst_access);
                // SAFETY: recording into a command buffer that is being recorded.
                unsafe {
                    d.cmd_pipeline_barrier(
                        cb,
                        b.src_stage,
                        b.dst_stage,
                        vk::DependencyFlags::empty(),
                        &[barrier],
                        &[],
                        &[],
                    );
                }
            }
        }
    }
    if prep.compute {
        let [x, y, z] = p.dispatch.unwrap_or([1, 1, 1]);
        // SAFETY: the pipeline, layout and set are alive and match.
        unsafe {
            d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, prep.pipeline);
            d.cmd_bind_descriptor_sets(
                cb,
                vk::PipelineBindPoint::COMPUTE,
                prep.layout,
                0,
                &[prep.set],
                &[],
            );
            d.cmd_dispatch(cb, x, y, z);
        }
        return;
    }
    let Some((name, w, h)) = target_of(p, pair, width, height) else {
        return;
    };
    let Some(Resource::Image(i)) = resources.get(name) else {
        return;
    };
    let target = &o.images[*i];
    let attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(target.view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        // Every pass overwrites its whole target.
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: vk::Extent2D {
            width: w,
            height: h,
        },
    };
    let rendering = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: w as f32,
        height: h as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the target was made a colour attachment by the pass's own barrier; the pipeline,
    // layout and set are alive and match.
    unsafe {
        d.cmd_begin_rendering(cb, &rendering);
        d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::GRAPHICS, prep.pipeline);
        d.cmd_bind_descriptor_sets(
            cb,
            vk::PipelineBindPoint::GRAPHICS,
            prep.layout,
            0,
            &[prep.set],
            &[],
        );
        d.cmd_set_viewport(cb, 0, &[viewport]);
        d.cmd_set_scissor(cb, 0, &[area]);
        // One full-screen triangle; the vertex shader makes it from the vertex index.
        d.cmd_draw(cb, 3, 1, 0, 0);
        d.cmd_end_rendering(cb);
    }
}
