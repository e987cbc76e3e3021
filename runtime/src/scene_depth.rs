//! The engine's depth buffer as the cloud pass reads it: a frame rendered into a user's scene
//! carries the scene's depth, and the renderer uploads it and the camera's encoding for the
//! `scene-depth` key (see `nimbus_clouds::model::scene_depth`).

use glam::Vec2;
use nimbus_clouds::model::scene_depth::SceneDepthParams;

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::textures::GpuTexture;
use wgpu::util::DeviceExt;

/// The opaque scene a frame's clouds stand in: the engine's depth buffer and how it encodes
/// distance. The renderer fills the camera (`view_projection`, `forward`) and `resolution`
/// of [`SceneDepthParams`] from the frame; the rest says how the buffer was written.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDepth {
    /// Texels per row and rows: the frame's width and height.
    pub width: u32,
    pub height: u32,
    /// Depth texels, first row at the top.
    pub texels: Vec<f32>,
    pub params: SceneDepthParams,
}

impl SceneDepth {
    /// Checks the size against the frame's and the texels for NaN; names the field.
    pub fn validate(&self, width: u32, height: u32) -> Result<(), RuntimeError> {
        if (self.width, self.height) != (width, height) {
            return Err(RuntimeError::Limit(format!(
                "Frame::scene_depth: the depth buffer is {}x{}, the frame {width}x{height} (one depth texel per pixel)",
                self.width, self.height
            )));
        }
        if self.texels.len() != (width as usize) * (height as usize) {
            return Err(RuntimeError::Limit(format!(
                "Frame::scene_depth.texels: {} values for {width}x{height} texels",
                self.texels.len()
            )));
        }
        if let Some(i) = self.texels.iter().position(|d| !d.is_finite()) {
            return Err(RuntimeError::Limit(format!(
                "Frame::scene_depth.texels[{i}]: a depth must be a finite number, got {}",
                self.texels[i]
            )));
        }
        Ok(())
    }

    /// The params with the frame's camera filled in.
    pub fn params_for(&self, view_projection: glam::Mat4, forward: glam::Vec3) -> SceneDepthParams {
        SceneDepthParams {
            view_projection,
            forward,
            resolution: Vec2::new(self.width as f32, self.height as f32),
            ..self.params
        }
    }
}

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
