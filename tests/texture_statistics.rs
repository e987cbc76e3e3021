//! Coverage means what it means in @takram/three-clouds: the procedural textures have the
//! value distributions of that library's textures (`local_weather.png`, `shape.bin`,
//! `shape_detail.bin` of @takram/three-clouds 0.7.6, whose quantiles are below), so the same
//! coverage remap and erosion formulas give the same share of sky covered. Before matching,
//! the shape noise had mean 0.37 against 0.80: erosion cut away most of every cloud, and a
//! coverage of 0.4 showed mostly clear sky where the reference library shows mostly cloud.

use nimbus_runtime::textures::NoiseKind;

/// Quantiles 10, 25, 50, 75 and 90 % and the mean of the reference library's textures.
const REFERENCE: [(&str, usize, [f32; 5], f32); 6] = [
    ("weather R", 0, [0.0, 0.0, 0.224, 0.475, 0.678], 0.278),
    ("weather G", 1, [0.0, 0.0, 0.035, 0.263, 0.522], 0.160),
    ("weather B", 2, [0.231, 0.353, 0.498, 0.647, 0.773], 0.500),
    ("weather A", 3, [0.11, 0.216, 0.384, 0.588, 0.773], 0.415),
    ("shape", 0, [0.694, 0.749, 0.804, 0.855, 0.890], 0.797),
    ("detail", 0, [0.588, 0.647, 0.718, 0.784, 0.839], 0.715),
];

/// Every texel of channel `channel` of the `kind` texture of side `n` (3D textures: all
/// slices).
fn texels(kind: NoiseKind, n: u32, depth: u32, channel: usize) -> Vec<f32> {
    let mut v = Vec::new();
    for z in 0..depth {
        for y in 0..n {
            for x in 0..n {
                let t = kind.cpu_texel(n, x, y, z);
                v.push(((t >> (8 * channel)) & 255) as f32 / 255.0);
            }
        }
    }
    v.sort_by(f32::total_cmp);
    v
}

#[test]
fn procedural_textures_have_the_reference_library_s_value_distributions() {
    for (name, channel, quantiles, mean) in REFERENCE {
        let v = match name {
            "shape" => texels(NoiseKind::Shape, 32, 32, channel),
            "detail" => texels(NoiseKind::Detail, 32, 32, channel),
            _ => texels(NoiseKind::Weather, 256, 1, channel),
        };
        let q = |p: f32| v[((v.len() - 1) as f32 * p) as usize];
        let ours = [0.1, 0.25, 0.5, 0.75, 0.9].map(q);
        let our_mean = v.iter().sum::<f32>() / v.len() as f32;
        println!(
            "{name}: quantiles {ours:.3?} (reference {quantiles:?}), mean {our_mean:.3} ({mean})"
        );
        for (o, r) in ours.iter().zip(quantiles) {
            assert!(
                (o - r).abs() <= 0.05,
                "{name}: quantile {o:.3} against the reference's {r}"
            );
        }
        assert!(
            (our_mean - mean).abs() <= 0.02,
            "{name}: mean {our_mean} against {mean}"
        );
    }
}

/// The detail noise's means that far samples erode with (`detail_level`) are the procedural
/// texture's own, at the size `nimbus render` uses and at twice it.
#[test]
fn detail_moments_are_the_texture_s() {
    use nimbus_clouds::model::noise::{DETAIL_MOMENTS, DETAIL_SIZE};
    for n in [DETAIL_SIZE, DETAIL_SIZE * 2] {
        let v = texels(NoiseKind::Detail, n, n, 0);
        let count = v.len() as f64;
        let mean = v.iter().map(|&d| f64::from(d)).sum::<f64>() / count;
        let sixth = v.iter().map(|&d| f64::from(d).powi(6)).sum::<f64>() / count;
        println!("detail {n}³: mean {mean:.4}, mean of d⁶ {sixth:.4} (constants {DETAIL_MOMENTS})");
        assert!(
            (mean - f64::from(DETAIL_MOMENTS.x)).abs() < 0.005,
            "mean {mean}"
        );
        assert!(
            (sixth - f64::from(DETAIL_MOMENTS.y)).abs() < 0.005,
            "d⁶ {sixth}"
        );
    }
}

/// Every procedural texture tiles: across its wrap (last column to first, last row to first)
/// neighbouring texels differ no more than neighbours inside it do. The weather's `b` channel
/// ran at half the frequency with the full period and did not tile; its seam was a hard
/// straight edge across every high layer.
#[test]
fn procedural_textures_tile_without_a_seam() {
    let n = 128u32;
    let channel = |t: u32, c: usize| ((t >> (8 * c)) & 255) as f32 / 255.0;
    for c in 0..4 {
        let at = |x: u32, y: u32| channel(NoiseKind::Weather.cpu_texel(n, x % n, y % n, 0), c);
        let mut inner = Vec::new();
        let mut seam = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let (dx, dy) = (
                    (at(x, y) - at(x + 1, y)).abs(),
                    (at(x, y) - at(x, y + 1)).abs(),
                );
                let wraps_x = x == n - 1;
                let wraps_y = y == n - 1;
                if wraps_x {
                    seam.push(dx)
                } else {
                    inner.push(dx)
                }
                if wraps_y {
                    seam.push(dy)
                } else {
                    inner.push(dy)
                }
            }
        }
        inner.sort_by(f32::total_cmp);
        let p99 = inner[inner.len() * 99 / 100];
        let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
        let worst = seam.iter().copied().fold(0.0f32, f32::max);
        println!(
            "weather channel {c}: neighbours inside differ by {:.4} on average (p99 {p99:.4}); across the wrap {:.4} (worst {worst:.4})",
            mean(&inner),
            mean(&seam)
        );
        assert!(
            mean(&seam) <= 2.0 * mean(&inner) + 1.0 / 255.0 && worst <= 2.0 * p99 + 2.0 / 255.0,
            "weather channel {c} has a seam at its wrap"
        );
    }
}
