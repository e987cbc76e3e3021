//! Display output: tonemapped 8-bit sRGB through the same `tonemap` shader function the model
//! defines, written to PNG atomically (a temporary file renamed into place), and refused when
//! the frame is broken (non-finite), so a failed render is never passed off as one.

use std::path::Path;

use nimbus_output::{Overwrite, write_png};

use nimbus_clouds::model::tonemap::tonemap;

use crate::error::RuntimeError;
use crate::render::Image;

impl Image {
    /// Checks that the frame is usable: every value finite. (A black frame is a result: the
    /// renderer tells a dark scene from an adapter that drew nothing.)
    pub fn check(&self) -> Result<(), RuntimeError> {
        if let Some(i) = self
            .pixels
            .iter()
            .position(|p| p.iter().any(|v| !v.is_finite()))
        {
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            return Err(RuntimeError::BadFrame(format!(
                "pixel ({x}, {y}) is not finite: {:?}",
                self.pixels[i]
            )));
        }
        Ok(())
    }

    /// Display-referred RGBA8 pixels: `exposure` times the radiance, ACES, sRGB.
    pub fn to_rgba8(&self, exposure: f32) -> image::RgbaImage {
        image::RgbaImage::from_fn(self.width, self.height, |x, y| {
            let p = self.pixels[(y * self.width + x) as usize];
            let c = tonemap(glam::vec3(p[0], p[1], p[2]), exposure);
            let to8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            image::Rgba([to8(c.x), to8(c.y), to8(c.z), 255])
        })
    }

    /// Writes the tonemapped frame to `path` (PNG, signed as Nimbus's) after [`Image::check`],
    /// all or nothing ([`nimbus_output::write_file`]): an existing file there is replaced only
    /// when Nimbus wrote it or `overwrite` is forced.
    pub fn save_png(
        &self,
        path: &Path,
        exposure: f32,
        overwrite: Overwrite,
    ) -> Result<(), RuntimeError> {
        self.check()?;
        let rgba = self.to_rgba8(exposure);
        write_png(path, rgba.dimensions(), rgba.as_raw(), overwrite)?;
        Ok(())
    }
}
