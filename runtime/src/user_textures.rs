//! Textures supplied by the user instead of the procedural ones: PNG for the 2D textures
//! (weather, turbulence), raw bytes for the 3D ones (shape, detail).
//!
//! The raw format: `N³` texels, x fastest, then y, then z, each either one byte (R8, copied
//! to every channel) or four (RGBA8); `N` follows from the file's length, which must be
//! `N³` or `4·N³` for a power-of-two `N`. That is what most noise tools write and what a
//! `numpy.ndarray.tofile` of a `uint8` cube gives.

use std::path::{Path, PathBuf};

use crate::error::RuntimeError;
use crate::gpu::Gpu;
use crate::textures::{GpuTexture, texel_value};

fn texture_error(file: &Path, reason: impl Into<String>) -> RuntimeError {
    RuntimeError::Texture {
        file: file.to_path_buf(),
        reason: reason.into(),
    }
}

/// Side of a cube texture stored as `bytes` bytes, and bytes per texel.
pub fn raw_cube_side(bytes: usize) -> Option<(u32, u32)> {
    for channels in [4u32, 1] {
        if !bytes.is_multiple_of(channels as usize) {
            continue;
        }
        let texels = bytes / channels as usize;
        let side = (texels as f64).cbrt().round() as u32;
        if side >= 2 && side.is_power_of_two() && (side as usize).pow(3) == texels {
            return Some((side, channels));
        }
    }
    None
}

impl Gpu {
    /// Uploads RGBA8 texels widened to half floats, as the procedural textures are
    /// ([`crate::textures::texel_value`]; why: [`Gpu::texture_from_texels`]).
    fn upload_rgba8(
        &self,
        label: &str,
        size: wgpu::Extent3d,
        dimension: wgpu::TextureDimension,
        rgba: &[u8],
    ) -> GpuTexture {
        let values: Vec<f32> = rgba
            .chunks_exact(4)
            .flat_map(|t| texel_value(u32::from_le_bytes([t[0], t[1], t[2], t[3]])).to_array())
            .collect();
        let halves: Vec<u16> = values.iter().map(|v| crate::gpu::f16_bits(*v)).collect();
        let (texture, view) = self.half_float_texture(
            label,
            [size.width, size.height, size.depth_or_array_layers],
            dimension,
            4,
            &halves,
        );
        // The red channel's means, for the detail level of detail.
        let count = (values.len() / 4).max(1) as f64;
        let (mut mean, mut sixth) = (0.0f64, 0.0f64);
        for r in values.iter().step_by(4) {
            let r = f64::from(*r);
            mean += r;
            sixth += r.powi(6);
        }
        GpuTexture {
            texture,
            view,
            size: size.width,
            red_moments: Some(glam::Vec2::new(
                (mean / count) as f32,
                (sixth / count) as f32,
            )),
        }
    }

    /// Loads a 2D texture from a PNG file (any colour type; stored as RGBA8, linear).
    pub fn load_png_texture(&self, file: &Path) -> Result<GpuTexture, RuntimeError> {
        self.upload_texture(&DecodedTexture::png(file)?)
    }

    /// Loads a 3D texture from a raw R8 or RGBA8 cube (see the module documentation).
    pub fn load_raw_volume(&self, file: &Path) -> Result<GpuTexture, RuntimeError> {
        self.upload_texture(&DecodedTexture::raw_volume(file)?)
    }

    /// Uploads a decoded texture, after checking it fits this adapter.
    pub fn upload_texture(&self, t: &DecodedTexture) -> Result<GpuTexture, RuntimeError> {
        let limits = self.device().limits();
        let (max, dimension, depth) = if t.volume {
            (
                limits.max_texture_dimension_3d,
                wgpu::TextureDimension::D3,
                t.size[2],
            )
        } else {
            (
                limits.max_texture_dimension_2d,
                wgpu::TextureDimension::D2,
                1,
            )
        };
        if t.size.iter().any(|s| *s > max) {
            return Err(texture_error(
                &t.file,
                format!(
                    "{}x{}x{} exceeds this adapter's {max} texels per side",
                    t.size[0], t.size[1], t.size[2]
                ),
            ));
        }
        Ok(self.upload_rgba8(
            &t.file.display().to_string(),
            wgpu::Extent3d {
                width: t.size[0],
                height: t.size[1],
                depth_or_array_layers: depth,
            },
            dimension,
            &t.rgba,
        ))
    }
}

/// A user texture read and checked on the CPU, before any GPU work: RGBA8 texels, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedTexture {
    pub file: PathBuf,
    /// Width, height, depth (1 for a 2D texture).
    pub size: [u32; 3],
    pub volume: bool,
    pub rgba: Vec<u8>,
}

impl DecodedTexture {
    /// A 2D texture from a PNG file (any colour type; stored as RGBA8, linear).
    pub fn png(file: &Path) -> Result<DecodedTexture, RuntimeError> {
        let img = image::open(file).map_err(|e| texture_error(file, e.to_string()))?;
        let rgba = img.to_rgba8();
        let (w, h) = rgba.dimensions();
        Ok(DecodedTexture {
            file: file.to_path_buf(),
            size: [w, h, 1],
            volume: false,
            rgba: rgba.into_raw(),
        })
    }

    /// A 3D texture from a raw R8 or RGBA8 cube (see the module documentation).
    pub fn raw_volume(file: &Path) -> Result<DecodedTexture, RuntimeError> {
        let bytes = std::fs::read(file).map_err(|e| texture_error(file, e.to_string()))?;
        let (side, channels) = raw_cube_side(bytes.len()).ok_or_else(|| {
            texture_error(
                file,
                format!(
                    "{} bytes is not N³ (R8) or 4·N³ (RGBA8) for a power-of-two N ≥ 2",
                    bytes.len()
                ),
            )
        })?;
        let rgba = if channels == 4 {
            bytes
        } else {
            bytes.iter().flat_map(|b| [*b, *b, *b, *b]).collect()
        };
        Ok(DecodedTexture {
            file: file.to_path_buf(),
            size: [side, side, side],
            volume: true,
            rgba,
        })
    }
}
