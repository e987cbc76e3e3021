//! `nimbus gallery`: every genus from the view that shows its signature (the scenes of the data
//! folder's `gallery/`, one per genus), rendered to PNG, with an index that lays them out as a
//! grid, lowest clouds first.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use nimbus_clouds::limits::{self, Origin};
use nimbus_output::{Overwrite, replace_folder};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Renderer, TextureSizes};

use crate::error::CliError;
use crate::scene_input::{SceneInput, SceneState};

/// The index of the gallery folder (a Markdown grid of the pictures).
const INDEX: &str = "gallery.md";

/// Every genus in one picture, in the index's grid.
const SHEET: &str = "contact-sheet.png";

/// What `nimbus gallery` takes.
#[derive(Args)]
pub(crate) struct GalleryArgs {
    /// Output folder (replaced whole; only a folder Nimbus wrote, unless --force).
    #[arg(short, long, default_value = "gallery")]
    out: PathBuf,
    /// Image size of each genus, WIDTHxHEIGHT.
    #[arg(short, long, default_value = "480x270")]
    resolution: String,
    /// Frames of temporal accumulation per image.
    #[arg(short, long, default_value_t = 8)]
    frames: u32,
    /// Exposure before the ACES curve.
    #[arg(long, default_value_t = 8.0)]
    exposure: f32,
    /// Columns of the index's grid.
    #[arg(long, default_value_t = 3)]
    columns: usize,
    /// Draw every genus by this path (default: each view's own, the volume unless its scene
    /// names another), to set a path's gallery beside the volume's.
    #[arg(long, value_enum, ignore_case = true)]
    path: Option<nimbus_clouds::Path>,
    /// Replace the output folder even when Nimbus did not write it.
    #[arg(long)]
    force: bool,
}

/// One rendered genus.
struct Tile {
    file: String,
    genus: String,
    about: String,
    view: String,
}

pub(crate) fn run(data: Option<&Path>, a: &GalleryArgs) -> Result<(), Box<dyn std::error::Error>> {
    let (width, height) = crate::render::parse_resolution(&a.resolution)?;
    limits::FRAMES.check(f64::from(a.frames), Origin::Flag("--frames"))?;
    limits::EXPOSURE.check(f64::from(a.exposure), Origin::Flag(limits::EXPOSURE.flag))?;
    if a.columns == 0 {
        return Err(CliError::Unknown {
            kind: "column count",
            given: "0".into(),
            known: "1 or more".into(),
        }
        .into());
    }
    // The destination first: a folder that is not Nimbus's fails now, not after the work.
    nimbus_output::check_folder(&a.out, Overwrite::forced(a.force))?;
    let dir = crate::data::data_dir(data)?;
    let lib = crate::data::load(data)?;
    let scenes_dir = dir.join("gallery");
    let mut scenes: Vec<(PathBuf, SceneState)> = Vec::new();
    let entries = std::fs::read_dir(&scenes_dir).map_err(|e| CliError::Unknown {
        kind: "gallery folder",
        given: format!("{} ({e})", scenes_dir.display()),
        known: "a folder of scene files, one per genus, in the data folder".into(),
    })?;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "toml") {
            let state = SceneInput::load_with(&lib, &path, None)?.single_at(0.0, "gallery")?;
            scenes.push((path, state));
        }
    }
    if scenes.is_empty() {
        return Err(CliError::Unknown {
            kind: "gallery scene",
            given: format!("none in {}", scenes_dir.display()),
            known: "one scene file (TOML) per genus".into(),
        }
        .into());
    }
    // Lowest clouds first, as the cloud atlases order the genera: by the base of the genus'
    // first layer, its cloud (a later one may be what falls from it, as nimbostratus' rain
    // reaches the ground).
    let mut frames = Vec::new();
    for (_, state) in &scenes {
        let mut frame = state.frame(width, height);
        frame.frames = a.frames;
        if let Some(p) = a.path {
            frame.features.path = p;
        }
        frame.validate()?;
        let base = state
            .genus
            .layers
            .iter()
            .find(|l| l.is_enabled())
            .map_or(f32::MAX, |l| l.altitude);
        frames.push((base, &state.scene, frame));
    }
    frames.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.name.cmp(&y.1.name)));
    let gpu = Gpu::new()?;
    say!("adapter: {}", gpu.info());
    for (_, _, f) in &frames {
        gpu.check_picture("each picture", f.width, f.height)?;
    }
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    let overwrite = Overwrite::forced(a.force);
    let start = Instant::now();
    let tiles = replace_folder(&a.out, overwrite, |tmp| {
        let mut tiles = Vec::new();
        let cols = a.columns.min(frames.len().max(1)) as u32;
        let rows = frames.len().div_ceil(cols as usize) as u32;
        // The grid as one picture, 4 px of white between the tiles.
        let gap = 4;
        let mut sheet = image::RgbaImage::from_pixel(
            cols * (width + gap) - gap,
            rows * (height + gap) - gap,
            image::Rgba([255, 255, 255, 255]),
        );
        for (i, (_, scene, frame)) in frames.iter().enumerate() {
            let t = Instant::now();
            let image = renderer.render(frame)?;
            let file = format!("{}.png", scene.name);
            image.save_png(&tmp.join(&file), a.exposure, Overwrite::Force)?;
            let (x, y) = (
                (i as u32 % cols) * (width + gap),
                (i as u32 / cols) * (height + gap),
            );
            image::imageops::replace(
                &mut sheet,
                &image.to_rgba8(a.exposure),
                i64::from(x),
                i64::from(y),
            );
            say!(
                "{:>14}: {} ({:.1} s)",
                scene.name,
                frame.variant().name(),
                t.elapsed().as_secs_f64()
            );
            tiles.push(Tile {
                file,
                genus: frame.genus.name.clone(),
                about: scene.description.clone(),
                view: format!(
                    "camera {} m, pitch {}°, sun {}°, coverage {}",
                    scene.camera_altitude,
                    scene.camera_pitch_deg,
                    scene.sun_elevation_deg,
                    frame.genus.coverage
                ),
            });
        }
        nimbus_output::write_png(
            &tmp.join(SHEET),
            sheet.dimensions(),
            sheet.as_raw(),
            Overwrite::Force,
        )?;
        let index = index(&tiles, a, &gpu.info().to_string(), width, height);
        std::fs::write(tmp.join(INDEX), index).map_err(|e| CliError::Unknown {
            kind: "gallery index",
            given: format!("{} ({e})", tmp.join(INDEX).display()),
            known: "a writable output folder".into(),
        })?;
        Ok::<_, Box<dyn std::error::Error>>(tiles)
    })?;
    say!(
        "{} genera in {:.1} s; wrote {}/{INDEX}",
        tiles.len(),
        start.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

/// The Markdown grid: one cell per genus, its picture, name, what it shows and the view.
fn index(tiles: &[Tile], a: &GalleryArgs, adapter: &str, width: u32, height: u32) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<!-- Generated by Nimbus: nimbus gallery -->");
    match a.path {
        Some(p) => {
            let _ = writeln!(s, "# The genera, drawn by the `{p}` path\n");
        }
        None => {
            let _ = writeln!(s, "# The genera\n");
        }
    }
    let _ = writeln!(
        s,
        "Each genus from the view that shows its signature ({width}×{height}, {} frames, adapter: {adapter}), lowest clouds first; all of them in one picture: [{SHEET}]({SHEET}).\n",
        a.frames
    );
    let cols = a.columns.min(tiles.len().max(1));
    let _ = writeln!(s, "|{}", " |".repeat(cols));
    let _ = writeln!(s, "|{}", "---|".repeat(cols));
    for row in tiles.chunks(cols) {
        let cells: Vec<String> = row
            .iter()
            .map(|t| {
                format!(
                    "![{genus}]({file})<br>**{genus}**: {about}<br><sub>{view}</sub>",
                    genus = t.genus,
                    file = t.file,
                    about = t.about,
                    view = t.view
                )
            })
            .collect();
        let _ = writeln!(s, "| {} |", cells.join(" | "));
    }
    s
}
