//! `nimbus bench-frames`: milliseconds per frame of each quality preset, at full resolution
//! and temporally upscaled, on whatever adapter runs it, with ratios to `high` measured in the
//! same run (absolute times on a shared or software adapter are noisy; ratios less so).
//!
//! Each timed frame is one `render` call of one frame, as a game loop makes them: the shadow
//! atlas, the cloud pass (and the resolve when upscaled), and the readback that waits for the
//! GPU. Pipelines and textures are built in an untimed warm-up. Where the adapter has
//! timestamp queries, the preset table also gives the GPU's own time for the same frames (the
//! sum over the frame's passes): on a real GPU the readback and the call's overhead are most
//! of the wall time, so only the GPU's time says what the shaders cost there.

use std::path::Path as FilePath;
use std::time::Instant;

use nimbus_clouds::{Path, Quality, Toggle};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

use crate::render::{RenderArgs, frame};

/// The adapter every bench runs on, named in its output, checked for a picture this size.
fn adapter(width: u32, height: u32) -> Result<Gpu, Box<dyn std::error::Error>> {
    let gpu = Gpu::new()?;
    say!("adapter: {}", gpu.info());
    gpu.check_picture("the image", width, height)?;
    Ok(gpu)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median wall time (ms) of `iterations` render calls of `frame`, after one untimed call that
/// builds its pipelines and textures. With `continue_history` set, the untimed call starts the
/// history afresh and the timed ones continue it, as a game loop does.
fn time_frames(
    renderer: &mut Renderer<'_>,
    frame: &Frame,
    iterations: u32,
) -> Result<f64, Box<dyn std::error::Error>> {
    Ok(time_frames_gpu(renderer, frame, iterations)?.0)
}

/// [`time_frames`], and the median GPU time of the same calls where the adapter has timestamp
/// queries.
fn time_frames_gpu(
    renderer: &mut Renderer<'_>,
    frame: &Frame,
    iterations: u32,
) -> Result<(f64, Option<f64>), Box<dyn std::error::Error>> {
    let mut first = frame.clone();
    first.continue_history = false;
    renderer.render(&first)?;
    let mut times = Vec::new();
    let mut gpu = Vec::new();
    for _ in 0..iterations {
        let start = Instant::now();
        renderer.render(frame)?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
        gpu.extend(renderer.last_gpu_time_ms());
    }
    let gpu = (gpu.len() == times.len()).then(|| median(gpu));
    Ok((median(times), gpu))
}

pub(crate) fn run(
    data: Option<&FilePath>,
    args: &RenderArgs,
    iterations: u32,
    uber: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let base = frame(data, args)?;
    let gpu = adapter(base.width, base.height)?;
    say!(
        "scene: genus {}, {}x{}, {} timed frames per row (median)",
        base.genus.name,
        base.width,
        base.height,
        iterations
    );
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    let mut rows = Vec::new();
    let mut gpu_rows = Vec::new();
    for quality in Quality::ALL {
        for upscale in [false, true] {
            let f = preset_frame(&base, quality, upscale);
            let (wall, gpu) = time_frames_gpu(&mut renderer, &f, iterations)?;
            rows.push((quality, upscale, wall));
            gpu_rows.extend(gpu.map(|g| (quality, upscale, g)));
        }
    }
    say!();
    preset_table(&rows, "ms/frame", 1);
    if gpu_rows.len() == rows.len() {
        say!();
        say!("GPU time of the same frames (timestamp queries, the sum over the frame's passes):");
        preset_table(&gpu_rows, "GPU ms", 2);
    } else {
        say!();
        say!("(no GPU times: the adapter has no timestamp queries)");
    }
    let timed = gpu_rows.len() == rows.len();
    compare_paths(&mut renderer, &base, iterations, &rows, timed)?;
    if uber {
        compare_uber(&mut renderer, &base, iterations, |q| ms_of(&rows, q, false))?;
    }
    Ok(())
}

/// Each built path other than the volume at every preset, full resolution and upscaled,
/// against the volume's rows timed above; and what a frame costs when the path's bake must be
/// redrawn (the sun moved), against the same frame with the bake kept. With `gpu_timed` (the
/// adapter has timestamp queries) a last column gives the GPU's time of the full-resolution
/// and upscaled frames.
fn compare_paths(
    renderer: &mut Renderer<'_>,
    base: &Frame,
    iterations: u32,
    volume: &[(Quality, bool, f64)],
    gpu_timed: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    for path in Path::ALL.into_iter().filter(|p| *p != Path::Volume) {
        say!();
        say!("path `{path}`: {}", path.doc());
        let (gpu_head, gpu_rule) = if gpu_timed {
            (" GPU ms full res / upscaled |", "---:|")
        } else {
            ("", "")
        };
        say!(
            "| preset | full res ms/frame | ×volume | upscaled ms/frame | ×volume | full res, bake redrawn ms/frame |{gpu_head}"
        );
        say!("|---|---:|---:|---:|---:|---:|{gpu_rule}");
        for q in Quality::ALL {
            let mut ms = [0.0; 2];
            let mut gpu = [None; 2];
            for (i, upscale) in [false, true].into_iter().enumerate() {
                let mut f = preset_frame(base, q, upscale);
                f.features.path = path;
                (ms[i], gpu[i]) = time_frames_gpu(renderer, &f, iterations)?;
            }
            // A sun moving a little each frame: every frame's bake is out of date.
            let mut f = preset_frame(base, q, false);
            f.features.path = path;
            let mut times = Vec::new();
            for i in 0..iterations {
                f.sun_azimuth_deg += SUN_STEP_DEG * (i + 1) as f32;
                let start = Instant::now();
                renderer.render(&f)?;
                times.push(start.elapsed().as_secs_f64() * 1e3);
            }
            let moving = median(times);
            let gpu_cell = match gpu {
                [Some(full), Some(up)] => format!(" {full:.2} / {up:.2} |"),
                _ if gpu_timed => " – |".to_string(),
                _ => String::new(),
            };
            say!(
                "| {} | {:.1} | {:.2} | {:.1} | {:.2} | {moving:.1} |{gpu_cell}",
                q.name(),
                ms[0],
                ms[0] / ms_of(volume, q, false),
                ms[1],
                ms[1] / ms_of(volume, q, true),
            );
        }
    }
    Ok(())
}

/// How far the sun moves per frame in [`run_moving_sun`] (degrees of azimuth): a day's arc
/// over a few minutes of frames, enough that every frame changes what the atlas shows.
const SUN_STEP_DEG: f32 = 0.05;

/// A game loop whose sun moves every frame, per preset and resolution: the shadow atlas and
/// the air table redrawn whole every frame against cascades in rotation (a band of a tile and
/// a band of the table a frame: `Renderer::set_cascade_rotation`), and both cached (the sun
/// still) for reference.
pub(crate) fn run_moving_sun(
    data: Option<&FilePath>,
    args: &RenderArgs,
    iterations: u32,
) -> Result<(), Box<dyn std::error::Error>> {
    let base = frame(data, args)?;
    let gpu = adapter(base.width, base.height)?;
    say!(
        "scene: genus {}, {}x{}, the sun moving {SUN_STEP_DEG}° of azimuth a frame, {} timed \
         frames per cell (median)",
        base.genus.name,
        base.width,
        base.height,
        iterations
    );
    say!();
    say!(
        "| preset | upscaling | atlas cached | whole atlas every frame | a band a frame (rotation) | rotation ÷ whole |"
    );
    say!("|---|---|---:|---:|---:|---:|");
    for quality in Quality::ALL {
        for upscale in [false, true] {
            let f = preset_frame(&base, quality, upscale);
            let mut cells = Vec::new();
            for (moving, rotation) in [(false, false), (true, false), (true, true)] {
                let mut renderer = Renderer::new(&gpu, TextureSizes::default());
                renderer.set_cascade_rotation(rotation);
                let mut first = f.clone();
                first.continue_history = false;
                renderer.render(&first)?;
                let mut times = Vec::new();
                let mut g = f.clone();
                for _ in 0..iterations {
                    if moving {
                        g.sun_azimuth_deg += SUN_STEP_DEG;
                    }
                    let start = Instant::now();
                    renderer.render(&g)?;
                    times.push(start.elapsed().as_secs_f64() * 1e3);
                }
                cells.push(median(times));
            }
            say!(
                "| {} | {} | {:.1} | {:.1} | {:.1} | {:.2} |",
                quality.name(),
                if upscale { "on" } else { "off" },
                cells[0],
                cells[1],
                cells[2],
                cells[2] / cells[1]
            );
        }
    }
    Ok(())
}

/// The preset table of `rows` (ms per frame, each preset full resolution and upscaled) with
/// ratios to `high`: `unit` names the times, printed with `decimals` decimals.
fn preset_table(rows: &[(Quality, bool, f64)], unit: &str, decimals: usize) {
    let (high_full, high_up) = (
        ms_of(rows, Quality::High, false),
        ms_of(rows, Quality::High, true),
    );
    say!("| preset | full res {unit} | ×high | upscaled {unit} | ×high | upscaling speed-up |");
    say!("|---|---:|---:|---:|---:|---:|");
    for q in Quality::ALL {
        let (full, up) = (ms_of(rows, q, false), ms_of(rows, q, true));
        say!(
            "| {} | {full:.decimals$} | {:.2} | {up:.decimals$} | {:.2} | {:.2}× |",
            q.name(),
            full / high_full,
            up / high_up,
            full / up
        );
    }
}

/// The time of `q` (upscaled or not) among `rows`.
fn ms_of(rows: &[(Quality, bool, f64)], q: Quality, upscale: bool) -> f64 {
    rows.iter()
        .find(|(rq, ru, _)| *rq == q && *ru == upscale)
        .map_or(f64::NAN, |r| r.2)
}

/// Frames per state of [`run_effect_changes`]: enough that a compile in the background
/// finishes within the state on a software adapter.
const FRAMES_PER_STATE: usize = 8;

/// A game loop whose scene changes its effects: `base` (one frame per call, the history
/// continued), then one more toggle flipped every [`FRAMES_PER_STATE`] frames, each state a
/// key the renderer has not drawn with. Run twice on fresh renderers, compiling each new key
/// on the frame path (what a host without background compiles gets) and with no-stall (built
/// in the background, the key and the atlas drawn before standing in, a changed atlas redrawn
/// a band per frame: `Renderer::set_no_stall`), and reports each run's median frame, its worst
/// frame, and their ratio.
pub(crate) fn run_effect_changes(
    data: Option<&FilePath>,
    args: &RenderArgs,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut base = frame(data, args)?;
    base.frames = 1;
    base.continue_history = true;
    let gpu = adapter(base.width, base.height)?;
    // Every toggle a scene may switch (scene depth and the orthographic camera follow the
    // host's camera and depth, not the scene's effects).
    let toggles: Vec<Toggle> = Toggle::ALL
        .iter()
        .copied()
        .filter(|t| !matches!(t, Toggle::SceneDepth | Toggle::Orthographic))
        .collect();
    let mut states = vec![base.clone()];
    for &t in &toggles {
        let mut next = states[states.len() - 1].clone();
        let on = t.get(&next.features);
        t.set(&mut next.features, !on);
        states.push(next);
    }
    say!(
        "scene: genus {}, {} preset, {}x{}; {} states of {FRAMES_PER_STATE} frames, each \
         flipping one more toggle ({})",
        base.genus.name,
        base.quality.name(),
        base.width,
        base.height,
        states.len(),
        toggles
            .iter()
            .map(|t| t.name())
            .collect::<Vec<_>>()
            .join(", ")
    );
    say!();
    say!(
        "| compiles | median ms/frame | worst ms/frame | worst / median | frames drawn by a stand-in |"
    );
    say!("|---|---:|---:|---:|---:|");
    for background in [false, true] {
        let mut renderer = Renderer::new(&gpu, TextureSizes::default());
        renderer.set_no_stall(background);
        // The first frame builds what any first frame needs (textures, the first key): untimed.
        let mut first = base.clone();
        first.continue_history = false;
        renderer.render(&first)?;
        let mut times = Vec::new();
        let mut stand_ins = 0;
        for state in &states {
            for _ in 0..FRAMES_PER_STATE {
                let start = Instant::now();
                renderer.render(state)?;
                times.push(start.elapsed().as_secs_f64() * 1e3);
                stand_ins += usize::from(renderer.drew_stand_in());
            }
        }
        let worst = times.iter().copied().fold(0.0, f64::max);
        let median = median(times);
        say!(
            "| {} | {median:.1} | {worst:.1} | {:.2} | {stand_ins} |",
            if background {
                "no-stall"
            } else {
                "on the frame path"
            },
            worst / median
        );
    }
    Ok(())
}

/// `base` at preset `quality` with its features, one frame per call; upscaled frames continue
/// the history, as a game loop's do.
fn preset_frame(base: &Frame, quality: Quality, upscale: bool) -> Frame {
    let mut f = base.clone();
    f.quality = quality;
    f.features = quality.features();
    f.upscale = upscale;
    f.frames = 1;
    f.continue_history = upscale;
    f
}

/// Each preset at full resolution through the uber-shader (the same model with every key
/// choice a uniform and a run-time branch), against its specialised shader timed above.
fn compare_uber(
    renderer: &mut Renderer<'_>,
    base: &Frame,
    iterations: u32,
    specialised: impl Fn(Quality) -> f64,
) -> Result<(), Box<dyn std::error::Error>> {
    renderer.set_uber_shader(true);
    let mut rows = Vec::new();
    for quality in Quality::ALL {
        let f = preset_frame(base, quality, false);
        rows.push((quality, time_frames(renderer, &f, iterations)?));
    }
    renderer.set_uber_shader(false);
    say!();
    say!("| preset | specialised ms/frame | uber-shader ms/frame | uber / specialised |");
    say!("|---|---:|---:|---:|");
    for (q, uber) in rows {
        let spec = specialised(q);
        say!(
            "| {} | {spec:.1} | {uber:.1} | {:.2}× |",
            q.name(),
            uber / spec
        );
    }
    Ok(())
}

/// Every scene of the data folder: ms per frame of the variant the scene derives against the
/// all-effects variant of the same preset, measured in one run.
pub(crate) fn run_scenes(
    data: Option<&FilePath>,
    resolution: (u32, u32),
    iterations: u32,
) -> Result<(), Box<dyn std::error::Error>> {
    let lib = crate::data::load(data)?;
    let gpu = adapter(resolution.0, resolution.1)?;
    say!(
        "{}x{}, one full-resolution frame per render call, median of {iterations}",
        resolution.0,
        resolution.1
    );
    say!();
    say!("| scene | derived variant | derived ms | all-effects ms | derived / all |");
    say!("|---|---|---:|---:|---:|");
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    for (name, (_, scene)) in &lib.scenes {
        let genus = lib
            .genus(&scene.genus)
            .ok_or_else(|| format!("scene {name}: genus {} missing", scene.genus))?;
        let derived = Frame::from_scene(scene, genus, resolution.0, resolution.1);
        let mut all = derived.clone();
        all.features = scene.quality.features();
        all.features.octaves = derived.features.octaves;
        let d = time_frames(&mut renderer, &derived, iterations)?;
        let a = time_frames(&mut renderer, &all, iterations)?;
        say!(
            "| {name} | {} | {d:.1} | {a:.1} | {:.2} |",
            derived.variant().name(),
            d / a
        );
    }
    Ok(())
}
