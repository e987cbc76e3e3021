//! CPU twins of shader resources: textures and samplers that `#[shader_fn]` functions read on
//! the CPU. Sampling follows the GPU rules (texel centres at (i + 0.5) / size, bilinear or
//! trilinear filtering, repeat or clamp addressing); there is one mip level, so the level
//! argument of `sample_level` must be 0 for CPU and GPU to agree.

use glam::{Vec2, Vec3, Vec4};

/// How coordinates outside [0, 1] are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AddressMode {
    #[default]
    Repeat,
    ClampToEdge,
}

/// Texel filtering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    #[default]
    Linear,
    Nearest,
}

/// A sampler.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Sampler {
    pub address: AddressMode,
    pub filter: Filter,
}

fn wrap(i: i64, n: u32, mode: AddressMode) -> usize {
    let n = i64::from(n);
    match mode {
        AddressMode::Repeat => i.rem_euclid(n) as usize,
        AddressMode::ClampToEdge => i.clamp(0, n - 1) as usize,
    }
}

/// Texel indices and weights along one axis.
fn taps(coord: f32, n: u32, sampler: &Sampler) -> [(usize, f32); 2] {
    let x = coord * n as f32;
    match sampler.filter {
        Filter::Nearest => {
            let i = wrap(x.floor() as i64, n, sampler.address);
            [(i, 1.0), (i, 0.0)]
        }
        Filter::Linear => {
            let t = x - 0.5;
            let i0 = t.floor();
            let f = t - i0;
            let i0 = i0 as i64;
            [
                (wrap(i0, n, sampler.address), 1.0 - f),
                // Saturated (a coordinate beyond ±9.2e18 texels, or infinite): the next texel
                // must not overflow; any defined texel will do, as on a GPU.
                (wrap(i0.wrapping_add(1), n, sampler.address), f),
            ]
        }
    }
}

/// An RGBA f32 2D texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture2d {
    pub size: [u32; 2],
    /// Row-major texels, `size[0] * size[1]` of them.
    pub texels: Vec<Vec4>,
}

impl Texture2d {
    /// Bilinear (or nearest) sample at `uv`; `level` must be 0 (one mip level).
    pub fn sample_level(&self, sampler: &Sampler, uv: Vec2, _level: f32) -> Vec4 {
        let tx = taps(uv.x, self.size[0], sampler);
        let ty = taps(uv.y, self.size[1], sampler);
        let mut acc = Vec4::ZERO;
        for (y, wy) in ty {
            for (x, wx) in tx {
                acc += self.texels[y * self.size[0] as usize + x] * (wx * wy);
            }
        }
        acc
    }

    /// Implicit-derivative sample: on the CPU there is one level, so this is `sample_level(.., 0)`.
    pub fn sample(&self, sampler: &Sampler, uv: Vec2) -> Vec4 {
        self.sample_level(sampler, uv, 0.0)
    }

    /// The texel at `texel` (level 0, the only one); coordinates outside the texture, which
    /// WGSL leaves undefined, read the nearest edge texel.
    pub fn load(&self, texel: glam::IVec2, _level: i32) -> Vec4 {
        let x = wrap(i64::from(texel.x), self.size[0], AddressMode::ClampToEdge);
        let y = wrap(i64::from(texel.y), self.size[1], AddressMode::ClampToEdge);
        self.texels[y * self.size[0] as usize + x]
    }
}

/// An RGBA f32 3D texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture3d {
    pub size: [u32; 3],
    /// Texels with x fastest, then y, then z.
    pub texels: Vec<Vec4>,
}

impl Texture3d {
    /// Trilinear (or nearest) sample at `uvw`; `level` must be 0 (one mip level).
    pub fn sample_level(&self, sampler: &Sampler, uvw: Vec3, _level: f32) -> Vec4 {
        let tx = taps(uvw.x, self.size[0], sampler);
        let ty = taps(uvw.y, self.size[1], sampler);
        let tz = taps(uvw.z, self.size[2], sampler);
        let (sx, sy) = (self.size[0] as usize, self.size[1] as usize);
        let mut acc = Vec4::ZERO;
        for (z, wz) in tz {
            for (y, wy) in ty {
                for (x, wx) in tx {
                    acc += self.texels[(z * sy + y) * sx + x] * (wx * wy * wz);
                }
            }
        }
        acc
    }

    /// Implicit-derivative sample: on the CPU there is one level, so this is `sample_level(.., 0)`.
    pub fn sample(&self, sampler: &Sampler, uvw: Vec3) -> Vec4 {
        self.sample_level(sampler, uvw, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_reads_the_texel_itself_and_clamps_outside() {
        let t = Texture2d {
            size: [3, 2],
            texels: (0..6).map(|i| Vec4::splat(i as f32)).collect(),
        };
        assert_eq!(t.load(glam::IVec2::new(2, 1), 0), Vec4::splat(5.0));
        assert_eq!(t.load(glam::IVec2::new(1, 0), 0), Vec4::splat(1.0));
        // Outside the texture (undefined in WGSL): the nearest edge texel, never a panic.
        assert_eq!(t.load(glam::IVec2::new(-4, 9), 0), Vec4::splat(3.0));
        assert_eq!(
            t.load(glam::IVec2::new(i32::MAX, i32::MIN), 0),
            Vec4::splat(2.0)
        );
    }
}
