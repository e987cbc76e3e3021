//! The engine's depth buffer as a frame carries it: its texels and how it encodes distance.
//! The cloud pass reads it for the `scene-depth` key (see `model::scene_depth`); a host uploads
//! it as it is (the wgpu runtime as an r32float texture).

use glam::Vec2;

use crate::frame::FrameError;
use crate::model::scene_depth::SceneDepthParams;

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
    pub fn validate(&self, width: u32, height: u32) -> Result<(), FrameError> {
        if (self.width, self.height) != (width, height) {
            return Err(FrameError::Invalid {
                field: "Frame::scene_depth",
                reason: format!(
                    "the depth buffer is {}x{}, the frame {width}x{height} (one depth texel per pixel)",
                    self.width, self.height
                ),
            });
        }
        if self.texels.len() != (width as usize) * (height as usize) {
            return Err(FrameError::Invalid {
                field: "Frame::scene_depth.texels",
                reason: format!("{} values for {width}x{height} texels", self.texels.len()),
            });
        }
        if let Some(i) = self.texels.iter().position(|d| !d.is_finite()) {
            return Err(FrameError::Invalid {
                field: "Frame::scene_depth.texels",
                reason: format!(
                    "texel {i}: a depth must be a finite number, got {}",
                    self.texels[i]
                ),
            });
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
