//! The clouds' density on a grid, written as a Mitsuba `gridvolume` file (`.vol`), so that an
//! independent offline renderer (Mitsuba 0.6 or 3, or anything reading the format) can render
//! the same clouds.
//!
//! The density is the model's own: [`total_density`]'s CPU twin over the CPU twins of the
//! procedural textures (texel for texel what the GPU kernels write), for the variant and
//! uniforms a scene derives, averaged over each voxel (box filter). [`crate::mitsuba_scene`]
//! writes the scene around it: the grid at its place, the phase function, sun and camera. Values are extinction coefficients σt in 1/m, so a medium with
//! `scale = 1` and lengths in metres renders at the model's optical depth; the scattering
//! albedo is the genus' σs / (σs + σa).
//!
//! File layout (Mitsuba's documented "VOL" binary, little-endian): `b"VOL"`, version byte 3,
//! i32 encoding 1 (f32), i32 resolution x, y, z, i32 channel count 1, f32 bounding box min x,
//! y, z and max x, y, z, then the values with x varying fastest, then y, then z.

use std::path::Path;

use nimbus_output::{Overwrite, Signature, write_file};

use glam::Vec3;
use nimbus_clouds::model::march::total_density;
use nimbus_clouds::model::shadow::altitude_at;
use std::sync::Arc;

use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_dsl::cpu::{Texture2d, Texture3d};

use crate::error::RuntimeError;
use crate::render::{Frame, Renderer, TextureSizes};
use crate::textures::{NoiseKind, texel_value};

/// A box of the local frame: x east, y altitude above the ground, z south (m), centred
/// horizontally on the camera's ground point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub min: Vec3,
    pub max: Vec3,
}

impl Region {
    /// This box grown by `by` metres on each horizontal side (its altitudes kept).
    pub fn widened(self, by: f32) -> Region {
        let grow = Vec3::new(by, 0.0, by);
        Region {
            min: self.min - grow,
            max: self.max + grow,
        }
    }
}

/// Extinction averaged over each voxel.
#[derive(Clone, Debug, PartialEq)]
pub struct DensityGrid {
    pub region: Region,
    pub size: [u32; 3],
    /// σt (1/m), x fastest, then y, then z.
    pub values: Vec<f32>,
    /// σs / (σs + σa) of the genus.
    pub albedo: f32,
    /// Samples per axis averaged in each voxel (1: the voxel centre alone).
    pub filter: u32,
    /// Size of a shape-noise texel (m): a voxel coarser than this cannot resolve the shapes.
    pub shape_texel: f32,
}

impl DensityGrid {
    /// Size of a voxel (m) along x, y, z.
    pub fn voxel(&self) -> glam::Vec3 {
        (self.region.max - self.region.min)
            / glam::Vec3::new(
                self.size[0] as f32,
                self.size[1] as f32,
                self.size[2] as f32,
            )
    }
}

/// Generates the textures on the CPU, texel for texel as the GPU kernels do (no shadow map:
/// density does not read it).
pub fn generate_cpu_textures(sizes: TextureSizes) -> CloudTextures {
    let plane = |kind: NoiseKind, n: u32| Texture2d {
        size: [n, n],
        texels: (0..n * n)
            .map(|i| texel_value(kind.cpu_texel(n, i % n, i / n, 0)))
            .collect(),
    };
    let cube = |kind: NoiseKind, n: u32| Texture3d {
        size: [n, n, n],
        texels: (0..n * n * n)
            .map(|i| texel_value(kind.cpu_texel(n, i % n, (i / n) % n, i / (n * n))))
            .collect(),
    };
    CloudTextures {
        weather: Arc::new(plane(NoiseKind::Weather, sizes.weather)),
        shape: Arc::new(cube(NoiseKind::Shape, sizes.shape)),
        detail: Arc::new(cube(NoiseKind::Detail, sizes.detail)),
        turbulence: Arc::new(plane(NoiseKind::Turbulence, sizes.turbulence)),
        shadow: CloudTextures::no_shadow(),
    }
}

/// The most voxels per axis of a grid.
pub const MAX_VOXELS_PER_AXIS: u32 = 1024;

/// The most samples per axis of a voxel's box filter.
pub const MAX_FILTER: u32 = 8;

/// Checks a grid's region, voxels per axis and filter before any work; the error names the
/// flag-like field and the accepted range.
pub fn check_grid(region: Region, size: [u32; 3], filter: u32) -> Result<(), RuntimeError> {
    let bad = |field, reason| RuntimeError::Region { field, reason };
    if size.iter().any(|n| *n == 0 || *n > MAX_VOXELS_PER_AXIS) {
        return Err(bad(
            "resolution",
            format!("{size:?} must be 1..={MAX_VOXELS_PER_AXIS} voxels per axis"),
        ));
    }
    if !(1..=MAX_FILTER).contains(&filter) {
        return Err(bad(
            "filter",
            format!("{filter} samples per axis must be 1..={MAX_FILTER}"),
        ));
    }
    if !(region.min.is_finite() && region.max.is_finite()) || region.min.cmpge(region.max).any() {
        return Err(bad(
            "region",
            format!(
                "min {} must be below max {} on every axis",
                region.min, region.max
            ),
        ));
    }
    if region.min.y < 0.0 {
        return Err(bad(
            "region",
            format!("starts {} m below the ground", -region.min.y),
        ));
    }
    Ok(())
}

/// Density samples a grid of `size` voxels filtered by `filter`³ takes: the work to estimate.
pub fn grid_samples(size: [u32; 3], filter: u32) -> u64 {
    size.iter().map(|n| u64::from(*n)).product::<u64>() * u64::from(filter).pow(3)
}

/// The density of `frame`'s clouds over `region`, each voxel the average of `filter`³ samples
/// spread evenly over it (a box filter: `filter = 1` is the voxel centre alone, which aliases
/// shapes smaller than a voxel). The slabs of the grid are shared among the CPU's threads;
/// `slab_done` hears of each of the `size[2]` slabs finished (for a progress bar).
pub fn density_grid(
    frame: &Frame,
    region: Region,
    size: [u32; 3],
    filter: u32,
    textures: &CloudTextures,
    slab_done: &(dyn Fn() + Sync),
) -> Result<DensityGrid, RuntimeError> {
    frame.validate()?;
    check_grid(region, size, filter)?;
    let u = Renderer::uniforms(frame);
    let key = frame.variant().key;
    let extent = region.max - region.min;
    let [nx, ny, nz] = size;
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let voxel = extent / Vec3::new(nx as f32, ny as f32, nz as f32);
    let slab = |z: u32| -> Vec<f32> {
        let _bound = textures.bind(u);
        let mut out = Vec::with_capacity((nx * ny) as usize);
        let inv = 1.0 / filter as f32;
        for y in 0..ny {
            for x in 0..nx {
                let corner = region.min + voxel * Vec3::new(x as f32, y as f32, z as f32);
                let mut sum = 0.0f32;
                for k in 0..filter * filter * filter {
                    let sub = Vec3::new(
                        (k % filter) as f32,
                        ((k / filter) % filter) as f32,
                        (k / (filter * filter)) as f32,
                    );
                    let local = corner + voxel * (sub + 0.5) * inv;
                    // Camera-relative position; the altitude follows the planet's curvature.
                    let p = Vec3::new(local.x, local.y - frame.camera_altitude, local.z);
                    let h = altitude_at(p, frame.camera_altitude, u.march.radius);
                    sum += total_density(p, h, 0.0, key);
                }
                out.push(sum * inv * inv * inv * sigma);
            }
        }
        out
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let mut slabs: Vec<(u32, Vec<f32>)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let slab = &slab;
                s.spawn(move || {
                    (t..nz)
                        .step_by(threads as usize)
                        .map(|z| {
                            let values = slab(z);
                            slab_done();
                            (z, values)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_default())
            .collect()
    });
    if slabs.len() != nz as usize {
        return Err(RuntimeError::Kernel(
            "a density export thread stopped early".into(),
        ));
    }
    slabs.sort_by_key(|(z, _)| *z);
    let values = slabs.into_iter().flat_map(|(_, v)| v).collect();
    let media = u.media;
    let shape_texel = 1.0 / (media.shape_repeat.max_element() * textures.shape.size[0] as f32);
    Ok(DensityGrid {
        region,
        size,
        values,
        albedo: u.light.scattering_coefficient / sigma.max(1e-30),
        filter,
        shape_texel,
    })
}

impl DensityGrid {
    /// The file's bytes.
    pub fn to_mitsuba_vol(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(48 + 4 * self.values.len());
        out.extend_from_slice(b"VOL");
        out.push(3);
        out.extend_from_slice(&1i32.to_le_bytes());
        for n in self.size {
            out.extend_from_slice(&(n as i32).to_le_bytes());
        }
        out.extend_from_slice(&1i32.to_le_bytes());
        for v in self
            .region
            .min
            .to_array()
            .into_iter()
            .chain(self.region.max.to_array())
        {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for v in &self.values {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Writes the grid to `path` all or nothing ([`nimbus_output::write_file`]). A volume file
    /// has no room for Nimbus's signature, so an existing file is replaced only when
    /// `overwrite` is forced.
    pub fn save_mitsuba_vol(&self, path: &Path, overwrite: Overwrite) -> Result<(), RuntimeError> {
        write_file(path, Signature::Unsigned, overwrite, &self.to_mitsuba_vol())?;
        Ok(())
    }
}
