//! Linear output: one frame as an OpenEXR with separate layers, for measuring rather than
//! looking — the composited image (`R G B A`, alpha the clouds' opacity), the clouds alone
//! (`clouds.R G B`, the radiance they scatter towards the camera before the air in front of
//! them), their transmittance (`clouds.transmittance`) and their front depth (`depth.Z`, the
//! transmittance-weighted mean distance of the scattering in metres, −1 where there is none).
//!
//! Each layer is the frame rendered with the matching [`PixelOutput`] shader and the same
//! jitter sequence, so the layers line up pixel for pixel; with several accumulated frames each
//! is the same average over frames. The renderer's targets are half floats, so each value
//! carries 11 significant bits (relative rounding ≤ 2⁻¹¹ ≈ 0.05 %); the file stores them as
//! 32-bit floats.

use std::path::Path;

use nimbus_clouds::PixelOutput;
use nimbus_output::{ExrChannel, Overwrite, write_exr};

use crate::error::RuntimeError;
use crate::render::{Frame, Image, Renderer};

/// The layers of one frame, linear (no exposure, no tone curve).
#[derive(Clone, Debug, PartialEq)]
pub struct LayeredImage {
    /// What `render` shows: clouds over sky or ground, air and haze; alpha the opacity.
    pub composite: Image,
    /// The clouds alone: radiance in RGB, transmittance in alpha.
    pub clouds: Image,
    /// Front depth (km as the shader writes it, −1 where no cloud) in red.
    pub depth: Image,
}

impl Renderer<'_> {
    /// Renders `frame` once per layer ([`LayeredImage`]); `progress` hears of each frame of
    /// each layer (`done` counts over all three).
    pub fn render_layers(
        &mut self,
        frame: &Frame,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<LayeredImage, RuntimeError> {
        let total = 3 * frame.frames;
        let mut layer = |renderer: &mut Self, index: u32, output: PixelOutput| {
            let mut f = frame.clone();
            f.output = output;
            f.continue_history = false;
            renderer.render_with_progress(&f, &mut |done, _| {
                progress(index * frame.frames + done, total)
            })
        };
        let composite = layer(self, 0, PixelOutput::Composite)?;
        let clouds = layer(self, 1, PixelOutput::Clouds)?;
        let depth = layer(self, 2, PixelOutput::Depth)?;
        Ok(LayeredImage {
            composite,
            clouds,
            depth,
        })
    }
}

impl LayeredImage {
    /// The EXR channels, named as compositing tools expect (`layer.channel`).
    pub fn channels(&self) -> Vec<ExrChannel> {
        let channel = |name: &str, image: &Image, c: usize| ExrChannel {
            name: name.to_string(),
            values: image.pixels.iter().map(|p| p[c]).collect(),
        };
        vec![
            channel("R", &self.composite, 0),
            channel("G", &self.composite, 1),
            channel("B", &self.composite, 2),
            channel("A", &self.composite, 3),
            channel("clouds.R", &self.clouds, 0),
            channel("clouds.G", &self.clouds, 1),
            channel("clouds.B", &self.clouds, 2),
            channel("clouds.transmittance", &self.clouds, 3),
            ExrChannel {
                name: "depth.Z".into(),
                values: self
                    .depth
                    .pixels
                    .iter()
                    .map(|p| if p[0] < 0.0 { -1.0 } else { p[0] * 1e3 })
                    .collect(),
            },
        ]
    }

    /// Writes the layers to `path` as an OpenEXR (32-bit float, lossless), all or nothing; an
    /// existing file is replaced only when Nimbus wrote it or `overwrite` is forced. A frame
    /// with a non-finite value is refused ([`Image::check`]).
    pub fn save_exr(&self, path: &Path, overwrite: Overwrite) -> Result<(), RuntimeError> {
        for image in [&self.composite, &self.clouds, &self.depth] {
            image.check()?;
        }
        let size = (self.composite.width, self.composite.height);
        write_exr(path, size, &self.channels(), overwrite)?;
        Ok(())
    }
}
