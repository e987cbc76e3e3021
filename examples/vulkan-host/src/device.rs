//! The Vulkan context: instance, the first device with a graphics-and-compute queue, memory,
//! and one-shot command buffers. Vulkan 1.3 (dynamic rendering: no render-pass objects).

use std::ffi::CStr;

use ash::vk;

use crate::error::{HostError, vk};

pub struct Device {
    _entry: ash::Entry,
    pub instance: ash::Instance,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub pool: vk::CommandPool,
    memory: vk::PhysicalDeviceMemoryProperties,
    /// The device's name and driver, for reports.
    pub name: String,
}

/// A buffer and its memory.
pub struct Buffer {
    pub buffer: vk::Buffer,
    pub memory: vk::DeviceMemory,
    pub size: u64,
}

/// An image, its memory and a view of the whole of it.
pub struct Image {
    pub image: vk::Image,
    pub memory: vk::DeviceMemory,
    pub view: vk::ImageView,
    pub extent: vk::Extent3D,
}

impl Device {
    pub fn new() -> Result<Self, HostError> {
        // SAFETY: loading the system's Vulkan loader; nothing else holds it.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| HostError::Loader(e.to_string()))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"nimbus-vulkan-host")
            .api_version(vk::API_VERSION_1_3);
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: a valid create info with no extensions or layers.
        let instance =
            unsafe { entry.create_instance(&info, None) }.map_err(vk("vkCreateInstance"))?;
        // SAFETY: the instance is alive for every call below.
        let physicals = unsafe { instance.enumerate_physical_devices() }
            .map_err(vk("vkEnumeratePhysicalDevices"))?;
        let mut chosen = None;
        for p in physicals {
            let props = unsafe { instance.get_physical_device_properties(p) };
            if props.api_version < vk::API_VERSION_1_3 {
                continue;
            }
            let families = unsafe { instance.get_physical_device_queue_family_properties(p) };
            let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
            if let Some(f) = families.iter().position(|f| f.queue_flags.contains(wanted)) {
                chosen = Some((p, f as u32, props));
                break;
            }
        }
        let Some((physical, family, props)) = chosen else {
            unsafe { instance.destroy_instance(None) };
            return Err(HostError::Device(
                "no Vulkan 1.3 device with a graphics and compute queue".into(),
            ));
        };
        let name = unsafe { CStr::from_ptr(props.device_name.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .push_next(&mut v13);
        let device = unsafe { instance.create_device(physical, &info, None) }
            .map_err(vk("vkCreateDevice"))?;
        let queue = unsafe { device.get_device_queue(family, 0) };
        let pool = unsafe {
            device.create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(family),
                None,
            )
        }
        .map_err(vk("vkCreateCommandPool"))?;
        let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
        Ok(Self {
            _entry: entry,
            instance,
            device,
            queue,
            pool,
            memory,
            name,
        })
    }

    fn memory_type(&self, bits: u32, flags: vk::MemoryPropertyFlags) -> Result<u32, HostError> {
        (0..self.memory.memory_type_count)
            .find(|&i| {
                bits & (1 << i) != 0
                    && self.memory.memory_types[i as usize]
                        .property_flags
                        .contains(flags)
            })
            .ok_or_else(|| HostError::Device(format!("no memory type with {flags:?}")))
    }

    fn allocate(
        &self,
        req: vk::MemoryRequirements,
        flags: vk::MemoryPropertyFlags,
    ) -> Result<vk::DeviceMemory, HostError> {
        let info = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(self.memory_type(req.memory_type_bits, flags)?);
        unsafe { self.device.allocate_memory(&info, None) }.map_err(vk("vkAllocateMemory"))
    }

    /// A host-visible buffer holding `bytes` (at least 16 bytes, rounded up to whole words).
    pub fn buffer(&self, bytes: &[u8], usage: vk::BufferUsageFlags) -> Result<Buffer, HostError> {
        let size = (bytes.len().max(16) as u64).div_ceil(16) * 16;
        let buffer = unsafe {
            self.device.create_buffer(
                &vk::BufferCreateInfo::default().size(size).usage(usage),
                None,
            )
        }
        .map_err(vk("vkCreateBuffer"))?;
        let req = unsafe { self.device.get_buffer_memory_requirements(buffer) };
        let memory = self.allocate(
            req,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        )?;
        unsafe { self.device.bind_buffer_memory(buffer, memory, 0) }
            .map_err(vk("vkBindBufferMemory"))?;
        let b = Buffer {
            buffer,
            memory,
            size,
        };
        self.write(&b, bytes)?;
        Ok(b)
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&self, b: &Buffer, bytes: &[u8]) -> Result<(), HostError> {
        unsafe {
            let ptr = self
                .device
                .map_memory(b.memory, 0, b.size, vk::MemoryMapFlags::empty())
                .map_err(vk("vkMapMemory"))?;
            std::ptr::copy_nonoverlapping(bytes.as_ptr(), ptr.cast::<u8>(), bytes.len());
            self.device.unmap_memory(b.memory);
        }
        Ok(())
    }

    /// The first `len` bytes of a host-visible buffer.
    pub fn read(&self, b: &Buffer, len: usize) -> Result<Vec<u8>, HostError> {
        let mut out = vec![0u8; len];
        unsafe {
            let ptr = self
                .device
                .map_memory(b.memory, 0, b.size, vk::MemoryMapFlags::empty())
                .map_err(vk("vkMapMemory"))?;
            std::ptr::copy_nonoverlapping(ptr.cast::<u8>(), out.as_mut_ptr(), len);
            self.device.unmap_memory(b.memory);
        }
        Ok(out)
    }

    /// A device-local 2D or 3D image with a view of all of it.
    pub fn image(
        &self,
        extent: vk::Extent3D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<Image, HostError> {
        let three = extent.depth > 1;
        let info = vk::ImageCreateInfo::default()
            .image_type(if three {
                vk::ImageType::TYPE_3D
            } else {
                vk::ImageType::TYPE_2D
            })
            .format(format)
            .extent(extent)
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let image =
            unsafe { self.device.create_image(&info, None) }.map_err(vk("vkCreateImage"))?;
        let req = unsafe { self.device.get_image_memory_requirements(image) };
        let memory = self.allocate(req, vk::MemoryPropertyFlags::DEVICE_LOCAL)?;
        unsafe { self.device.bind_image_memory(image, memory, 0) }
            .map_err(vk("vkBindImageMemory"))?;
        let view = unsafe {
            self.device.create_image_view(
                &vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(if three {
                        vk::ImageViewType::TYPE_3D
                    } else {
                        vk::ImageViewType::TYPE_2D
                    })
                    .format(format)
                    .subresource_range(COLOR),
                None,
            )
        }
        .map_err(vk("vkCreateImageView"))?;
        Ok(Image {
            image,
            memory,
            view,
            extent,
        })
    }

    /// Records with `record` into a fresh command buffer, submits it and waits for it.
    pub fn submit(
        &self,
        record: impl FnOnce(vk::CommandBuffer) -> Result<(), HostError>,
    ) -> Result<(), HostError> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cb = unsafe { self.device.allocate_command_buffers(&info) }
            .map_err(vk("vkAllocateCommandBuffers"))?[0];
        unsafe {
            self.device
                .begin_command_buffer(
                    cb,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .map_err(vk("vkBeginCommandBuffer"))?;
        }
        record(cb)?;
        unsafe {
            self.device
                .end_command_buffer(cb)
                .map_err(vk("vkEndCommandBuffer"))?;
            let cbs = [cb];
            let submit = [vk::SubmitInfo::default().command_buffers(&cbs)];
            self.device
                .queue_submit(self.queue, &submit, vk::Fence::null())
                .map_err(vk("vkQueueSubmit"))?;
            self.device
                .queue_wait_idle(self.queue)
                .map_err(vk("vkQueueWaitIdle"))?;
            self.device.free_command_buffers(self.pool, &cbs);
        }
        Ok(())
    }

    /// An image layout transition with the access it waits for and the access it allows.
    #[allow(clippy::too_many_arguments)]
    pub fn transition(
        &self,
        cb: vk::CommandBuffer,
        image: vk::Image,
        from: (vk::ImageLayout, vk::PipelineStageFlags, vk::AccessFlags),
        to: (vk::ImageLayout, vk::PipelineStageFlags, vk::AccessFlags),
    ) {
        let barrier = vk::ImageMemoryBarrier::default()
            .old_layout(from.0)
            .new_layout(to.0)
            .src_access_mask(from.2)
            .dst_access_mask(to.2)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image)
            .subresource_range(COLOR);
        unsafe {
            self.device.cmd_pipeline_barrier(
                cb,
                from.1,
                to.1,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[barrier],
            );
        }
    }
}

/// The one mip level and layer of a colour image.
pub const COLOR: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: every object made from the device is destroyed before it (Frame's drop).
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}
