//! Image error against a reference, on what a viewer sees: both images tonemapped to display
//! values in [0, 1] with the same exposure, then RMSE over the RGB channels, PSNR from it, and
//! SSIM (Wang et al. 2004) on luma from the `image-compare` crate.

use image_compare::Algorithm;

use nimbus_runtime::RuntimeError;
use nimbus_runtime::render::Image;

/// How far an image is from its reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// Root mean square difference of the display values, 0..1.
    pub rmse: f64,
    /// Peak signal-to-noise ratio in dB, `20·log10(1 / RMSE)` (infinite for identical images).
    pub psnr_db: f64,
    /// Mean structural similarity of the luma, 1 = identical.
    pub ssim: f64,
}

/// Compares `image` with `reference` after tonemapping both at `exposure`.
pub fn image_error(
    image: &Image,
    reference: &Image,
    exposure: f32,
) -> Result<ImageError, RuntimeError> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(RuntimeError::BadFrame(format!(
            "cannot compare a {}x{} image with a {}x{} reference",
            image.width, image.height, reference.width, reference.height
        )));
    }
    let (a, b) = (image.to_rgba8(exposure), reference.to_rgba8(exposure));
    let mut sum = 0.0f64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            let d = (f64::from(p[c]) - f64::from(q[c])) / 255.0;
            sum += d * d;
        }
    }
    let rmse = (sum / (3.0 * f64::from(image.width) * f64::from(image.height))).sqrt();
    let luma = |img: &image::RgbaImage| {
        image::GrayImage::from_fn(img.width(), img.height(), |x, y| {
            let p = img.get_pixel(x, y);
            let y = 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
            image::Luma([y.round().clamp(0.0, 255.0) as u8])
        })
    };
    let ssim =
        image_compare::gray_similarity_structure(&Algorithm::MSSIMSimple, &luma(&a), &luma(&b))
            .map_err(|e| RuntimeError::BadFrame(format!("SSIM: {e}")))?
            .score;
    Ok(ImageError {
        rmse,
        psnr_db: 20.0 * (1.0 / rmse).log10(),
        ssim,
    })
}
