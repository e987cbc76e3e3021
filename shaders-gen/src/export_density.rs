//! `nimbus export-density`: the clouds of a scene as a Mitsuba grid volume (`.vol`) of
//! extinction coefficients, each voxel the average over it, and optionally the Mitsuba 3 scene
//! around it (grid in place, phase function, sun, camera) for rendering the same clouds in an
//! independent renderer (`tools/mitsuba_agreement.py` compares the two).

use std::path::{Path, PathBuf};

use clap::Args;
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use nimbus_output::{Overwrite, Signature, TEXT_MARKER, check_file, write_file};
use nimbus_runtime::RuntimeError;
use nimbus_runtime::density_export::{
    MAX_VOXELS_PER_AXIS, Region, check_grid, density_grid, generate_cpu_textures, grid_samples,
};
use nimbus_runtime::mitsuba_scene::{mitsuba_scene_xml, phase_table};
use nimbus_runtime::render::{Frame, TextureSizes};

use crate::error::CliError;
use crate::scene_input::SceneInput;

/// What `nimbus export-density` takes.
#[derive(Args)]
pub(crate) struct ExportDensityArgs {
    /// Scene file (TOML). Default: scenes/default.toml of the data folder.
    scene: Option<PathBuf>,
    /// Output volume file.
    #[arg(short, long, default_value = "clouds.vol")]
    out: PathBuf,
    /// Also write a Mitsuba 3 scene (XML) that renders the volume as the scene's camera sees
    /// it: grid at its place and size, the genus' phase function, the sun, the camera.
    #[arg(long)]
    mitsuba: Option<PathBuf>,
    /// Box to sample, metres: MINX,MINY,MINZ,MAXX,MAXY,MAXZ (x east, y altitude, z south,
    /// centred on the camera's ground point). Default: the part of the cloud layers the
    /// camera's view crosses (out to --reach), widened towards the sun so that the light
    /// reaching those clouds crosses the box too.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    region: Option<Vec<f32>>,
    /// How far along the view the default region reaches (m).
    #[arg(long, default_value_t = 30_000.0)]
    reach: f32,
    /// Widen the default region on every horizontal side by this many depths of the cloud
    /// layers. Light scattered many times reaches the viewed clouds from up to a few layer
    /// depths away, and leaks out of the sides of a box that ends sooner: a renderer's multiple
    /// scattering on a deck needs about 2 (a slab's diffuse light decays sideways as
    /// e^(−π·distance/depth): 0.2 % at two depths). Single scattering needs none.
    #[arg(long, default_value_t = 0.0)]
    margin: f32,
    /// Replace the output files even when they exist (a volume file carries no mark of who
    /// wrote it, so an existing one is only replaced with --force).
    #[arg(long)]
    force: bool,
    /// Voxels per axis: NX,NY,NZ. Default: voxels of --voxel metres, at most 256 along the
    /// longest axis.
    #[arg(long, value_delimiter = ',')]
    size: Option<Vec<u32>>,
    /// Edge of a voxel (m) when --size is not given (at most 1,024 voxels per axis). Default:
    /// half a shape-noise texel (26 m), coarser when the region would need more than 256.
    #[arg(long)]
    voxel: Option<f32>,
    /// Samples per axis averaged in each voxel (box filter; 1 = the voxel centre alone).
    #[arg(long, default_value_t = 2)]
    filter: u32,
}

/// The most `--margin` takes, in layer depths: beyond a few the diffuse light is gone
/// (e^(−π·20) at 20), and the box would only grow.
const MAX_MARGIN: f32 = 20.0;

/// The box of the cloud layers that the camera's view crosses within `reach`, widened towards
/// the sun by the path the sunlight takes through the layers to those points.
fn view_region(frame: &Frame, bottom: f32, top: f32, reach: f32) -> Region {
    let (forward, up) = frame.camera_basis();
    let right = forward.cross(up);
    let half_h = (frame.fov_deg.to_radians() * 0.5).tan();
    let half_w = half_h * frame.width as f32 / frame.height as f32;
    let eye = Vec3::new(0.0, frame.camera_altitude, 0.0);
    let sun = nimbus_runtime::render::Renderer::uniforms(frame)
        .light
        .sun_direction;
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    let n = 16;
    for j in 0..=n {
        for i in 0..=n {
            let sx = (2.0 * i as f32 / n as f32 - 1.0) * half_w;
            let sy = (2.0 * j as f32 / n as f32 - 1.0) * half_h;
            let d = (forward + right * sx + up * sy).normalize();
            // The stretch of this ray between the layers' bottom and top, within reach.
            let (mut t0, mut t1) = (0.0f32, reach);
            if d.y.abs() > 1e-6 {
                let (a, b) = ((bottom - eye.y) / d.y, (top - eye.y) / d.y);
                t0 = t0.max(a.min(b));
                t1 = t1.min(a.max(b));
            } else if eye.y < bottom || eye.y > top {
                continue;
            }
            if t1 <= t0 {
                continue;
            }
            for t in [t0, t1] {
                let p = eye + d * t;
                lo = lo.min(p);
                hi = hi.max(p);
                // Where the sunlight reaching p entered the layers (at most `reach` away).
                if sun.y > 1e-3 {
                    let s = p + sun * ((top - p.y) / sun.y).min(reach);
                    lo = lo.min(s);
                    hi = hi.max(s);
                }
            }
        }
    }
    if lo.x > hi.x {
        // The view misses the layers: the layers over the camera's ground point.
        lo = Vec3::new(-reach, bottom, -reach);
        hi = Vec3::new(reach, top, reach);
    }
    Region {
        min: Vec3::new(lo.x, bottom, lo.z),
        max: Vec3::new(hi.x.max(lo.x + 1.0), top, hi.z.max(lo.z + 1.0)),
    }
}

pub(crate) fn run(
    data: Option<&Path>,
    a: &ExportDensityArgs,
) -> Result<(), Box<dyn std::error::Error>> {
    let file = match &a.scene {
        Some(f) => f.clone(),
        None => crate::data::data_dir(data)?.join("scenes/default.toml"),
    };
    // Every flag and both outputs are checked before any work (the noise textures alone take
    // seconds), each error naming its flag.
    if !(a.reach.is_finite() && a.reach > 0.0 && a.reach <= 1e6) {
        return Err(format!("--reach: {} m must be in (0, 1e6]", a.reach).into());
    }
    if !(a.margin.is_finite() && (0.0..=MAX_MARGIN).contains(&a.margin)) {
        return Err(format!(
            "--margin: {} layer depths must be in [0, {MAX_MARGIN}]",
            a.margin
        )
        .into());
    }
    let state = SceneInput::load(data, &file, None)?.single_at(0.0, "export-density")?;
    let genus = &state.genus;
    let mut frame = state.frame(640, 360);
    // The density does not depend on the lighting; the scene file for Mitsuba is the
    // single-scattering model Nimbus's verification mode renders.
    frame.verification = true;
    frame.features.octaves = 1;
    frame.features.diffusion = false;
    let layers = genus.layers.iter().filter(|l| l.is_enabled());
    let bottom = layers.clone().map(|l| l.altitude).fold(f32::MAX, f32::min);
    let top = layers.map(|l| l.altitude + l.height).fold(0.0, f32::max);
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
        None => view_region(&frame, bottom.min(top), top, a.reach)
            .widened(a.margin * (top - bottom).max(0.0)),
    };
    flagged(check_grid(region, [1, 1, 1], 1))?;
    let size = grid_size(a, region)?;
    flagged(check_grid(region, size, a.filter))?;
    let overwrite = Overwrite::forced(a.force);
    check_outputs(a, overwrite)?;
    // The work, estimated before it starts: an absurd one is refused unless forced.
    let samples = grid_samples(size, a.filter);
    let estimate = samples as f64 / SAMPLES_PER_SECOND_PER_CORE / cores() as f64;
    say!(
        "{}x{}x{} voxels × {}³ samples = {samples} density samples: about {} on {} core(s)",
        size[0],
        size[1],
        size[2],
        a.filter,
        duration(estimate),
        cores()
    );
    if samples > MAX_SAMPLES && !a.force {
        return Err(CliError::Refused {
            what: "export size",
            given: format!(
                "{samples} density samples ({}x{}x{} voxels × {}³), about {} here",
                size[0],
                size[1],
                size[2],
                a.filter,
                duration(estimate)
            ),
            accepted: format!(
                "at most {MAX_SAMPLES} without --force: lower --size or --filter, raise --voxel, \
                 or pass --force to run it anyway"
            ),
        }
        .into());
    }
    let textures = generate_cpu_textures(TextureSizes::default());
    // The phase table before the grid: a phase Mitsuba cannot represent is refused first.
    let phase = match &a.mitsuba {
        Some(_) => Some(phase_table(&frame, &textures)?),
        None => None,
    };
    let bar = ProgressBar::new(u64::from(size[2]));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} slabs  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let grid = density_grid(&frame, region, size, a.filter, &textures, &|| bar.inc(1));
    bar.finish_and_clear();
    let grid = grid?;
    grid.save_mitsuba_vol(&a.out, overwrite)?;
    let max = grid.values.iter().copied().fold(0.0f32, f32::max);
    let mean = grid.values.iter().map(|v| f64::from(*v)).sum::<f64>() / grid.values.len() as f64;
    let cloudy = grid.values.iter().filter(|v| **v > 0.0).count();
    let voxel = grid.voxel();
    say!(
        "wrote {}: {}x{}x{} voxels of σt (1/m) over [{}] .. [{}] m, each {:.1} x {:.1} x {:.1} m, averaged over {}³ samples",
        a.out.display(),
        size[0],
        size[1],
        size[2],
        region.min,
        region.max,
        voxel.x,
        voxel.y,
        voxel.z,
        grid.filter
    );
    say!(
        "variant {}; σt max {max:.4} /m, mean {mean:.5} /m; {cloudy} of {} voxels cloudy; albedo {}",
        frame.variant().name(),
        grid.values.len(),
        grid.albedo
    );
    if voxel.max_element() > grid.shape_texel {
        say_err!(
            "warning: voxels of up to {:.0} m are coarser than the shape noise's {:.0} m texels: \
             the grid cannot resolve the cloud shapes (use a smaller --region or a larger --size)",
            voxel.max_element(),
            grid.shape_texel
        );
    }
    match (&a.mitsuba, &phase) {
        (Some(x), Some(phase)) => {
            let volume = volume_name(x, &a.out);
            let xml = mitsuba_scene_xml(&frame, &grid, &volume, phase);
            write_file(
                x,
                Signature::FirstLine(TEXT_MARKER),
                overwrite,
                xml.as_bytes(),
            )?;
            say!(
                "wrote {}: Mitsuba 3 scene (camera, sun of irradiance 1, phase function, the grid in place); \
                 `mitsuba {}` renders single scattering",
                x.display(),
                x.display()
            );
        }
        _ => say!(
            "Mitsuba 3: {{'type': 'heterogeneous', 'albedo': {}, 'scale': 1.0, 'sigma_t': {{'type': 'gridvolume', 'filename': '{}'}}}}, lengths in metres; --mitsuba FILE.xml writes the whole scene",
            grid.albedo,
            a.out.display()
        ),
    }
    Ok(())
}

/// Density samples one core evaluates per second here (debug builds are slower), for the
/// estimate printed before the work: the order of magnitude, not a promise.
const SAMPLES_PER_SECOND_PER_CORE: f64 = 1.0e6;

/// The most density samples an export takes without `--force` (about half an hour at the
/// rate above on 2 cores).
const MAX_SAMPLES: u64 = 4_000_000_000;

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Seconds for people: `40 s`, `12 min`, `80 h`.
fn duration(seconds: f64) -> String {
    if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 5400.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.0} h", seconds / 3600.0)
    }
}

/// A grid check's error, named by the flag that set the value.
fn flagged(checked: Result<(), RuntimeError>) -> Result<(), CliError> {
    checked.map_err(|e| match e {
        RuntimeError::Region { field, reason } => CliError::Refused {
            what: match field {
                "resolution" => "--size (voxels per axis)",
                "filter" => "--filter",
                _ => "--region",
            },
            given: reason,
            accepted: "see `nimbus export-density --help`".into(),
        },
        other => CliError::Texture {
            flag: "export-density",
            source: Box::new(other),
        },
    })
}

/// Voxels per axis: `--size`, or voxels of `--voxel` metres (26 m by default, coarser where the
/// region would need more than 256 per axis). A `--voxel` that would need more than the grid
/// holds is refused, not clamped.
fn grid_size(a: &ExportDensityArgs, region: Region) -> Result<[u32; 3], CliError> {
    let bad = |what, given: String, accepted: String| CliError::Refused {
        what,
        given,
        accepted,
    };
    if let Some(s) = &a.size {
        return match s.as_slice() {
            [x, y, z] => Ok([*x, *y, *z]),
            _ => Err(bad(
                "--size",
                format!("{} numbers", s.len()),
                "NX,NY,NZ (3 numbers)".into(),
            )),
        };
    }
    let extent = region.max - region.min;
    let edge = match a.voxel {
        Some(v) if !(v.is_finite() && v >= 0.1) => {
            return Err(bad("--voxel", format!("{v} m"), "at least 0.1 m".into()));
        }
        Some(v) => v,
        None => (26.0f32).max(extent.max_element() / 256.0),
    };
    let needed = |e: f32| (f64::from(e) / f64::from(edge)).ceil().max(1.0);
    let most = needed(extent.max_element());
    if most > f64::from(MAX_VOXELS_PER_AXIS) {
        return Err(bad(
            "--voxel",
            format!(
                "{edge} m over a region {:.0} m across needs {most} voxels along it",
                extent.max_element()
            ),
            format!(
                "at most {MAX_VOXELS_PER_AXIS} per axis: a --voxel of at least {:.1} m, or a \
                 smaller --region",
                extent.max_element() / MAX_VOXELS_PER_AXIS as f32
            ),
        ));
    }
    Ok([needed(extent.x), needed(extent.y), needed(extent.z)].map(|n| n as u32))
}

/// Both outputs, before any work: writable, not someone else's, and not the same file.
fn check_outputs(a: &ExportDensityArgs, overwrite: Overwrite) -> Result<(), CliError> {
    check_file(&a.out, Signature::Unsigned, overwrite)?;
    if let Some(x) = &a.mitsuba {
        if same_file(x, &a.out) {
            return Err(CliError::Refused {
                what: "--mitsuba",
                given: format!("{} is the same file as -o", x.display()),
                accepted: "another file than the volume's: the scene is XML, the volume binary \
                        (e.g. -o clouds.vol --mitsuba clouds.xml)"
                    .into(),
            });
        }
        check_file(x, Signature::FirstLine(TEXT_MARKER), overwrite)?;
    }
    Ok(())
}

/// Whether two paths name one file (the same path, or one existing file by two names).
fn same_file(a: &Path, b: &Path) -> bool {
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    if absolute(a) == absolute(b) {
        return true;
    }
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// The volume's path as the scene file should name it: relative to the scene's folder when
/// both are in the same folder, absolute otherwise.
fn volume_name(scene: &Path, volume: &Path) -> String {
    let folder = |p: &Path| {
        p.parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
            .canonicalize()
            .ok()
    };
    match (folder(scene), folder(volume), volume.file_name()) {
        (Some(a), Some(b), Some(name)) if a == b => name.to_string_lossy().into_owned(),
        _ => std::path::absolute(volume)
            .unwrap_or_else(|_| volume.to_path_buf())
            .display()
            .to_string(),
    }
}
