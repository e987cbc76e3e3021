//! The clouds' density on a grid, written as a Mitsuba `gridvolume` file (`.vol`), so that an
//! independent offline renderer (Mitsuba 0.6 or 3, or anything reading the format) can render
//! the same clouds.
//!
//! The density is the model's own: [`total_density`]'s CPU twin over the CPU twins of the
//! procedural textures (texel for texel what the GPU kernels write), for the variant and
//! uniforms a scene derives. Values are extinction coefficients σt in 1/m, so a medium with
//! `scale = 1` and lengths in metres renders at the model's optical depth; the scattering
//! albedo is the genus' σs / (σs + σa).
//!
//! File layout (Mitsuba's documented "VOL" binary, little-endian): `b"VOL"`, version byte 3,
//! i32 encoding 1 (f32), i32 resolution x, y, z, i32 channel count 1, f32 bounding box min x,
//! y, z and max x, y, z, then the values with x varying fastest, then y, then z.

use std::path::Path;

use nimbus_output::{Overwrite, Signature, write_file};

use glam::{Vec3, Vec4};
use nimbus_clouds::model::march::total_density;
use nimbus_clouds::model::shadow::altitude_at;
use std::sync::Arc;

use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_dsl::cpu::{Texture2d, Texture3d};

use crate::error::RuntimeError;
use crate::render::{Frame, Renderer, TextureSizes};
use crate::textures::NoiseKind;

/// A box of the local frame: x east, y altitude above the ground, z south (m), centred
/// horizontally on the camera's ground point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub min: Vec3,
    pub max: Vec3,
}

/// Extinction samples at voxel centres.
#[derive(Clone, Debug, PartialEq)]
pub struct DensityGrid {
    pub region: Region,
    pub size: [u32; 3],
    /// σt (1/m), x fastest, then y, then z.
    pub values: Vec<f32>,
    /// σs / (σs + σa) of the genus.
    pub albedo: f32,
}

fn unpack(word: u32) -> Vec4 {
    Vec4::from_array(std::array::from_fn(|c| {
        ((word >> (8 * c)) & 0xff) as f32 / 255.0
    }))
}

/// Generates the textures on the CPU, texel for texel as the GPU kernels do (no shadow map:
/// density does not read it).
pub fn generate_cpu_textures(sizes: TextureSizes) -> CloudTextures {
    let plane = |kind: NoiseKind, n: u32| Texture2d {
        size: [n, n],
        texels: (0..n * n)
            .map(|i| unpack(kind.cpu_texel(n, i % n, i / n, 0)))
            .collect(),
    };
    let cube = |kind: NoiseKind, n: u32| Texture3d {
        size: [n, n, n],
        texels: (0..n * n * n)
            .map(|i| unpack(kind.cpu_texel(n, i % n, (i / n) % n, i / (n * n))))
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

/// Samples the density of `frame`'s clouds at the voxel centres of `region`.
pub fn density_grid(
    frame: &Frame,
    region: Region,
    size: [u32; 3],
    textures: &CloudTextures,
) -> Result<DensityGrid, RuntimeError> {
    frame.validate()?;
    let bad = |field, reason| RuntimeError::Region { field, reason };
    if size.iter().any(|n| *n == 0 || *n > 1024) {
        return Err(bad(
            "resolution",
            format!("{size:?} must be 1..=1024 voxels per axis"),
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
    let u = Renderer::uniforms(frame);
    let key = frame.variant().key;
    let _bound = textures.bind(u);
    let extent = region.max - region.min;
    let [nx, ny, nz] = size;
    let mut values = Vec::with_capacity((nx * ny * nz) as usize);
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let f = (Vec3::new(x as f32, y as f32, z as f32) + 0.5)
                    / Vec3::new(nx as f32, ny as f32, nz as f32);
                let local = region.min + extent * f;
                // Camera-relative position; the altitude follows the planet's curvature.
                let p = Vec3::new(local.x, local.y - frame.camera_altitude, local.z);
                let h = altitude_at(p, frame.camera_altitude, u.march.radius);
                let rho = total_density(p, h, key);
                values.push(rho * sigma);
            }
        }
    }
    Ok(DensityGrid {
        region,
        size,
        values,
        albedo: u.light.scattering_coefficient / sigma.max(1e-30),
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
