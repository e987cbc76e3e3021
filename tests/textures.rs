//! The procedural textures generated on the GPU equal their CPU twins texel by texel (within one
//! 8-bit level), and tile seamlessly.

mod common;

use nimbus_runtime::textures::NoiseKind;

#[test]
fn gpu_noise_textures_match_their_cpu_twins() {
    let Some(gpu) = common::gpu() else { return };
    for kind in NoiseKind::ALL {
        let size = if matches!(kind, NoiseKind::Shape | NoiseKind::Detail) {
            16
        } else {
            64
        };
        let texels = gpu.noise_texels(kind, size).expect("generate");
        let depth = if matches!(kind, NoiseKind::Shape | NoiseKind::Detail) {
            size
        } else {
            1
        };
        let (mut worst, mut checked) = (0i32, 0usize);
        for z in 0..depth {
            for y in 0..size {
                for x in 0..size {
                    let got = texels[((z * size + y) * size + x) as usize];
                    let want = kind.cpu_texel(size, x, y, z);
                    for byte in 0..4 {
                        let d = ((got >> (8 * byte)) & 255) as i32
                            - ((want >> (8 * byte)) & 255) as i32;
                        worst = worst.max(d.abs());
                    }
                    checked += 1;
                }
            }
        }
        println!("{kind:?}: {checked} texels, largest difference {worst}/255");
        assert!(worst <= 1, "{kind:?}: texels differ by {worst}/255");
        // Not constant: the noise has contrast.
        let reds: Vec<u32> = texels.iter().map(|t| t & 255).collect();
        let (lo, hi) = (
            reds.iter().min().copied().unwrap_or(0),
            reds.iter().max().copied().unwrap_or(0),
        );
        assert!(hi - lo > 40, "{kind:?}: red channel spans only {lo}..{hi}");
    }
}

#[test]
fn noise_tiles_seamlessly() {
    use nimbus_clouds::model::noise::{perlin, worley};
    let period = 4;
    for (x, y, z) in [(0.3f32, 1.7f32, 2.2f32), (3.9, 0.1, 3.5)] {
        let p = glam::vec3(x, y, z);
        let shifted = p + glam::Vec3::new(period as f32, 0.0, period as f32);
        assert!((perlin(p, period, 1) - perlin(shifted, period, 1)).abs() < 1e-5);
        assert!((worley(p, period, 2) - worley(shifted, period, 2)).abs() < 1e-5);
    }
}
