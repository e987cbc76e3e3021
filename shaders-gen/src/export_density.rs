//! `nimbus export-density`: the clouds of a scene as a Mitsuba grid volume (`.vol`) of
//! extinction coefficients, for rendering the same clouds in an independent renderer.

use std::path::{Path, PathBuf};

use clap::Args;
use glam::Vec3;
use nimbus_output::{Overwrite, Signature, check_file};
use nimbus_runtime::density_export::{Region, density_grid, generate_cpu_textures};
use nimbus_runtime::render::{Frame, TextureSizes};

/// What `nimbus export-density` takes.
#[derive(Args)]
pub(crate) struct ExportDensityArgs {
    /// Scene file (TOML). Default: scenes/default.toml of the data folder.
    scene: Option<PathBuf>,
    /// Output file.
    #[arg(short, long, default_value = "clouds.vol")]
    out: PathBuf,
    /// Box to sample, metres: MINX,MINY,MINZ,MAXX,MAXY,MAXZ (x east, y altitude, z south,
    /// centred on the camera's ground point). Default: 20 km square over the scene's layers.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    region: Option<Vec<f32>>,
    /// Replace the output file even when it exists (a volume file carries no mark of who
    /// wrote it, so an existing one is only replaced with --force).
    #[arg(long)]
    force: bool,
    /// Voxels per axis: NX,NY,NZ.
    #[arg(long, value_delimiter = ',', default_values_t = [128u32, 32, 128])]
    size: Vec<u32>,
}

pub(crate) fn run(
    data: Option<&Path>,
    a: &ExportDensityArgs,
) -> Result<(), Box<dyn std::error::Error>> {
    let file = match &a.scene {
        Some(f) => f.clone(),
        None => crate::data::data_dir(data)?.join("scenes/default.toml"),
    };
    let lib = crate::render::library_for(data, Some(&file))?;
    let scene = nimbus_clouds::load_scene(&file)?;
    let genus = crate::render::scene_genus(&lib, &file, &scene)?;
    let frame = Frame::from_scene(&scene, &genus, 1, 1);
    if a.size.len() != 3 {
        return Err(format!("--size takes NX,NY,NZ (3 numbers), got {}", a.size.len()).into());
    }
    let region = match &a.region {
        Some(r) if r.len() != 6 => {
            return Err(format!(
                "--region takes MINX,MINY,MINZ,MAXX,MAXY,MAXZ (6 numbers), got {}",
                r.len()
            )
            .into());
        }
        Some(r) => Region {
            min: Vec3::new(r[0], r[1], r[2]),
            max: Vec3::new(r[3], r[4], r[5]),
        },
        None => {
            let layers = genus.layers.iter().filter(|l| l.is_enabled());
            let bottom = layers.clone().map(|l| l.altitude).fold(f32::MAX, f32::min);
            let top = layers.map(|l| l.altitude + l.height).fold(0.0, f32::max);
            Region {
                min: Vec3::new(-10_000.0, bottom.min(top), -10_000.0),
                max: Vec3::new(10_000.0, top, 10_000.0),
            }
        }
    };
    let size = [a.size[0], a.size[1], a.size[2]];
    let overwrite = Overwrite::forced(a.force);
    check_file(&a.out, Signature::Unsigned, overwrite)?;
    let textures = generate_cpu_textures(TextureSizes::default());
    let grid = density_grid(&frame, region, size, &textures)?;
    grid.save_mitsuba_vol(&a.out, overwrite)?;
    let max = grid.values.iter().copied().fold(0.0f32, f32::max);
    let mean = grid.values.iter().map(|v| f64::from(*v)).sum::<f64>() / grid.values.len() as f64;
    let cloudy = grid.values.iter().filter(|v| **v > 0.0).count();
    println!(
        "wrote {}: {}x{}x{} voxels of σt (1/m) over [{}] .. [{}] m",
        a.out.display(),
        size[0],
        size[1],
        size[2],
        region.min,
        region.max
    );
    println!(
        "variant {}; σt max {max:.4} /m, mean {mean:.5} /m; {cloudy} of {} voxels cloudy; albedo {}",
        frame.variant().name(),
        grid.values.len(),
        grid.albedo
    );
    println!(
        "Mitsuba 3: {{'type': 'heterogeneous', 'albedo': {}, 'scale': 1.0, 'sigma_t': {{'type': 'gridvolume', 'filename': '{}'}}}}, lengths in metres",
        grid.albedo,
        a.out.display()
    );
    Ok(())
}
