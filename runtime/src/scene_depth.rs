//! The engine's depth buffer as the cloud pass reads it: a frame rendered into a user's scene
//! carries the scene's depth, and the renderer uploads it and the camera's encoding for the
//! `scene-depth` key (see `nimbus_clouds::model::scene_depth`).

pub use nimbus_clouds::engine_depth::SceneDepth;

use crate::gpu::Gpu;
use crate::textures::GpuTexture;
use wgpu::util::DeviceExt;

impl Gpu {
    /// The depth texels as a texture the passes load texel by texel: one 32-bit float each, as
    /// an engine's depth buffer holds them. The passes never filter it (its binding is
    /// unfilterable), so every adapter takes it at full precision.
    pub fn scene_depth_texture(&self, depth: &SceneDepth) -> GpuTexture {
        let size = wgpu::Extent3d {
            width: depth.width,
            height: depth.height,
            depth_or_array_layers: 1,
        };
        let desc = wgpu::TextureDescriptor {
            label: Some("scene depth"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        };
        let bytes: &[u8] = bytemuck::cast_slice(&depth.texels);
        let texture = self.device().create_texture_with_data(
            self.queue(),
            &desc,
            wgpu::util::TextureDataOrder::LayerMajor,
            bytes,
        );
        let view = texture.create_view(&Default::default());
        GpuTexture {
            texture,
            view,
            size: depth.width,
            red_moments: None,
        }
    }
}
