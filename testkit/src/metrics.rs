//! Image error against a reference, in display space and in linear radiance.
//!
//! Display space is what a viewer sees: both images tonemapped to display values in [0, 1] with
//! the same exposure, then RMSE over the RGB channels, PSNR from it, SSIM (Wang et al. 2004) on
//! luma from the `image-compare` crate, and FLIP (Andersson et al. 2020, NVIDIA's perceptual
//! difference, through the `nv-flip` crate). Linear space is what the model computes: the
//! relative mean absolute error of luminance and the ratio of mean luminances (a preset that
//! darkens the clouds reads below 1). Several renders of one row under different jitter seeds
//! split its error into bias and noise ([`bias_noise`]).

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
    /// Mean FLIP error of the display values, 0 = identical, 1 = as different as can be.
    pub flip: f64,
    /// Mean |ΔY| of linear luminance over the reference's mean luminance.
    pub linear: f64,
    /// Mean linear luminance over the reference's: below 1, the image is darker.
    pub luminance_ratio: f64,
}

/// Relative luminance of linear Rec. 709 RGB.
pub fn luminance(p: &[f32; 4]) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

fn mean_luminance(image: &Image) -> f64 {
    image.pixels.iter().map(luminance).sum::<f64>() / image.pixels.len().max(1) as f64
}

fn same_size(image: &Image, reference: &Image) -> Result<(), RuntimeError> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(RuntimeError::BadFrame(format!(
            "cannot compare a {}x{} image with a {}x{} reference",
            image.width, image.height, reference.width, reference.height
        )));
    }
    Ok(())
}

/// A row's error split over several renders that differ only in their jitter seed, in linear
/// luminance relative to the reference's mean: what more frames would not remove (bias) and
/// what they would (noise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiasNoise {
    /// RMS over pixels of (mean over seeds − reference), less the share of the renders' and
    /// the reference's own noise that the mean still carries.
    pub bias: f64,
    /// RMS over pixels of the standard deviation across seeds (the noise of one render).
    pub noise: f64,
    /// Renders the split was taken over.
    pub seeds: usize,
}

/// Splits the error of `images` (one row rendered under different jitter seeds) against
/// `reference` into bias and noise. `reference_noise` is the RMS linear luminance difference
/// (relative, as here) between the reference and itself under another seed: half its square
/// is the reference's own variance, which the bias would otherwise count.
pub fn bias_noise(
    images: &[Image],
    reference: &Image,
    reference_noise: f64,
) -> Result<BiasNoise, RuntimeError> {
    for image in images {
        same_size(image, reference)?;
    }
    let k = images.len();
    let scale = mean_luminance(reference).max(1e-12);
    let (mut bias2, mut var) = (0.0f64, 0.0f64);
    for (i, r) in reference.pixels.iter().enumerate() {
        let y: Vec<f64> = images.iter().map(|im| luminance(&im.pixels[i])).collect();
        let mean = y.iter().sum::<f64>() / k.max(1) as f64;
        bias2 += (mean - luminance(r)).powi(2);
        if k > 1 {
            var += y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1) as f64;
        }
    }
    let n = reference.pixels.len().max(1) as f64;
    let (bias2, var) = (bias2 / n / (scale * scale), var / n / (scale * scale));
    // E[(mean of k − reference)²] = bias² + σ²/k + σ_ref².
    let corrected = bias2 - var / k.max(1) as f64 - 0.5 * reference_noise * reference_noise;
    Ok(BiasNoise {
        bias: corrected.max(0.0).sqrt(),
        noise: var.sqrt(),
        seeds: k,
    })
}

/// RMS linear luminance difference of `image` against `reference`, relative to the
/// reference's mean luminance.
pub fn linear_rms(image: &Image, reference: &Image) -> Result<f64, RuntimeError> {
    same_size(image, reference)?;
    let scale = mean_luminance(reference).max(1e-12);
    let sum: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| (luminance(a) - luminance(b)).powi(2))
        .sum();
    Ok((sum / reference.pixels.len().max(1) as f64).sqrt() / scale)
}

/// Compares `image` with `reference` after tonemapping both at `exposure`.
pub fn image_error(
    image: &Image,
    reference: &Image,
    exposure: f32,
) -> Result<ImageError, RuntimeError> {
    same_size(image, reference)?;
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
    let rgb = |img: &image::RgbaImage| {
        let bytes: Vec<u8> = img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
        nv_flip::FlipImageRgb8::with_data(img.width(), img.height(), &bytes)
    };
    let flip_map = nv_flip::flip(rgb(&b), rgb(&a), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let flip = f64::from(nv_flip::FlipPool::from_image(&flip_map).mean());
    let reference_luminance = mean_luminance(reference).max(1e-12);
    let linear = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(p, q)| (luminance(p) - luminance(q)).abs())
        .sum::<f64>()
        / image.pixels.len().max(1) as f64
        / reference_luminance;
    Ok(ImageError {
        rmse,
        psnr_db: 20.0 * (1.0 / rmse).log10(),
        ssim,
        flip,
        linear,
        luminance_ratio: mean_luminance(image) / reference_luminance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: impl Fn(usize) -> f32) -> Image {
        Image {
            width: 32,
            height: 32,
            pixels: (0..1024)
                .map(|i| {
                    let v = values(i);
                    [v, v, v, 1.0]
                })
                .collect(),
        }
    }

    /// Uniform in [−1, 1), from an xorshift sequence.
    fn noise(seed: &mut u64) -> f32 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    #[test]
    fn bias_and_noise_are_told_apart() {
        // Reference 1 everywhere; eight renders of 1 + bias + uniform noise of half-width 0.3
        // (σ = 0.3/√3 = 0.1732) per pixel and render.
        let reference = image(|_| 1.0);
        let renders = |bias: f32, seed: u64| -> Vec<Image> {
            let mut s = seed;
            (0..8)
                .map(|_| {
                    let n: Vec<f32> = (0..1024).map(|_| 0.3 * noise(&mut s)).collect();
                    image(|i| 1.0 + bias + n[i])
                })
                .collect()
        };
        let sigma = 0.3 / 3f64.sqrt();
        let split = bias_noise(&renders(0.1, 7), &reference, 0.0).expect("split");
        println!("bias 0.1, σ {sigma:.4}: {split:?}");
        assert!((split.noise - sigma).abs() < 0.01, "{split:?}");
        assert!((split.bias - 0.1).abs() < 0.01, "{split:?}");
        // Pure noise: the raw RMS of the mean is σ/√8 = 0.061; the split reads (almost) no bias.
        let split = bias_noise(&renders(0.0, 11), &reference, 0.0).expect("split");
        println!("no bias: {split:?}");
        assert!(
            split.bias < 0.02 && (split.noise - sigma).abs() < 0.01,
            "{split:?}"
        );
        assert_eq!(split.seeds, 8);
    }

    #[test]
    fn a_darker_image_reads_below_one_and_flip_sees_it() {
        let reference = image(|i| 0.02 + 0.0001 * (i % 32) as f32);
        let darker = image(|i| 0.9 * (0.02 + 0.0001 * (i % 32) as f32));
        let same = image_error(&reference, &reference, 8.0).expect("self");
        assert_eq!(same.flip, 0.0);
        assert_eq!(same.linear, 0.0);
        assert!((same.luminance_ratio - 1.0).abs() < 1e-12);
        let e = image_error(&darker, &reference, 8.0).expect("darker");
        assert!((e.luminance_ratio - 0.9).abs() < 1e-6, "{e:?}");
        assert!((e.linear - 0.1).abs() < 1e-6, "{e:?}");
        assert!(e.flip > 0.01, "{e:?}");
    }
}
