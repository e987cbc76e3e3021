//! The command line: its arguments (clap) and which command each runs.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nimbus_clouds::{Quality, Toggle};
use nimbus_codegen::Target;
use nimbus_output::Overwrite;

use crate::{
    animate, bench, bench_frames, check, data, diff, emit, engine, explain, export_density,
    gallery, list, package, render, tradeoff,
};

/// Nimbus: volumetric-cloud shaders written once in Rust, emitted for every target.
#[derive(Parser)]
#[command(name = "nimbus", version, about)]
pub(crate) struct Cli {
    /// Folder holding `genera/*.toml` and `scenes/*.toml` (default: $NIMBUS_DATA, else the
    /// repository's examples/).
    #[arg(long, global = true)]
    data: Option<PathBuf>,
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// Which variants: a catalogue name, or a genus with a quality and toggles.
#[derive(Args)]
pub(crate) struct VariantArgs {
    /// A family (`preview`, `clouds`, `shadow`, ...) or one shader by its id (`preview-hg`,
    /// `clouds-detail-haze-...`), as `nimbus list` prints them; every variant when omitted.
    name: Option<String>,
    /// A cloud genus (a file in genera/); with no --quality, every quality preset.
    #[arg(short, long)]
    genus: Option<String>,
    /// Quality preset.
    #[arg(short, long, value_enum)]
    quality: Option<Quality>,
    #[command(flatten)]
    toggles: ToggleArgs,
}

/// A `--targets` value: one target, or every one.
#[derive(Clone, Copy, Debug)]
pub(crate) enum TargetChoice {
    All,
    One(Target),
}

impl clap::ValueEnum for TargetChoice {
    fn value_variants<'a>() -> &'a [Self] {
        static CHOICES: std::sync::OnceLock<Vec<TargetChoice>> = std::sync::OnceLock::new();
        CHOICES.get_or_init(|| {
            std::iter::once(TargetChoice::All)
                .chain(Target::ALL.map(TargetChoice::One))
                .collect()
        })
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        match self {
            TargetChoice::All => Some(clap::builder::PossibleValue::new("all")),
            TargetChoice::One(t) => clap::ValueEnum::to_possible_value(t),
        }
    }
}

impl TargetChoice {
    /// The targets the choices name, each once, in `Target::ALL` order.
    pub(crate) fn resolve(choices: &[TargetChoice]) -> Vec<Target> {
        Target::ALL
            .into_iter()
            .filter(|t| {
                choices.iter().any(|c| match c {
                    TargetChoice::All => true,
                    TargetChoice::One(o) => o == t,
                })
            })
            .collect()
    }
}

/// Effects switched on or off beyond the preset's.
#[derive(Args)]
pub(crate) struct ToggleArgs {
    /// Toggles to switch on beyond the preset's (comma-separated, see `nimbus list`).
    #[arg(long, value_delimiter = ',', value_enum, ignore_case = true)]
    pub(crate) enable: Vec<Toggle>,
    /// Toggles to switch off.
    #[arg(long, value_delimiter = ',', value_enum, ignore_case = true)]
    pub(crate) disable: Vec<Toggle>,
    /// Multiple-scattering octaves (1..=12).
    #[arg(long)]
    pub(crate) octaves: Option<u32>,
    /// How the clouds are drawn (see `nimbus list`): the ray-marched volume, or a path baked
    /// from the same model.
    #[arg(long, value_enum, ignore_case = true)]
    pub(crate) path: Option<nimbus_clouds::Path>,
}

impl VariantArgs {
    fn selection(&self) -> data::Selection<'_> {
        data::Selection {
            name: self.name.as_deref(),
            genus: self.genus.as_deref(),
            quality: self.quality,
            enable: &self.toggles.enable,
            disable: &self.toggles.disable,
            octaves: self.toggles.octaves,
            path: self.toggles.path,
        }
    }
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Generate, validate and write shaders (one file per target and entry point, plus a JSON
    /// binding manifest beside each GLSL/HLSL/MSL file).
    Emit {
        #[command(flatten)]
        variants: VariantArgs,
        /// Emit the variant a scene file derives (see `explain`) with its shadow pass.
        #[arg(long, conflicts_with_all = ["name", "genus", "quality"])]
        scene: Option<PathBuf>,
        /// Second of the scene's timeline whose variant to emit (its clock's sun, its weather):
        /// as `render --time` and `explain --time` take it.
        #[arg(
            long,
            requires = "scene",
            default_value_t = 0.0,
            allow_hyphen_values = true
        )]
        time: f64,
        /// Comma-separated targets, or all.
        #[arg(
            short,
            long,
            visible_alias = "target",
            value_delimiter = ',',
            value_enum,
            default_value = "all"
        )]
        targets: Vec<TargetChoice>,
        /// Write a package that engine runs with no Nimbus code: every pass in its language,
        /// the noise textures, uniform layouts and values, and a JSON pass graph (instead of
        /// plain shader files for --targets).
        #[arg(long, value_enum, conflicts_with = "targets")]
        engine: Option<engine::Engine>,
        /// Output folder (created; replaced only if it is empty or a previous Nimbus output).
        #[arg(short, long, default_value = "nimbus-out")]
        out: PathBuf,
        /// Replace the output folder even when Nimbus did not write it (its files are lost).
        #[arg(long)]
        force: bool,
    },
    /// Generate and validate variants for every target (naga, plus glslangValidator and
    /// spirv-val when installed); exits non-zero on any failure.
    Check {
        #[command(flatten)]
        variants: VariantArgs,
        /// Skip glslangValidator and spirv-val even when installed.
        #[arg(long)]
        no_external: bool,
    },
    /// Render a scene to PNG with the wgpu runtime (any adapter: a GPU, or lavapipe/llvmpipe).
    Render(Box<render::RenderArgs>),
    /// Render every genus from the view that shows its signature (the data folder's
    /// `gallery/` scenes) and write a Markdown grid of them.
    Gallery(Box<gallery::GalleryArgs>),
    /// Render a scene's timeline (the sun by its clock, the clouds drifting with its wind, its
    /// weather states one after another) as PNG frames, a GIF, and an MP4 where ffmpeg is
    /// installed.
    Animate(Box<animate::AnimateArgs>),
    /// Milliseconds per frame of every quality preset, full resolution and upscaled, as
    /// ratios to `high` (takes the same scene arguments as `render`).
    BenchFrames {
        #[command(flatten)]
        render: Box<render::RenderArgs>,
        /// Timed frames per row (the median is reported).
        #[arg(short = 'n', long, default_value_t = 5)]
        iterations: u32,
        /// Also time each preset through the uber-shader (every generation-time choice a
        /// uniform and a run-time branch) against its specialised shader.
        #[arg(long)]
        uber: bool,
        /// Instead of the presets: a game loop whose scene flips one more toggle every few
        /// frames, its worst frame against its median, with each new key compiled on the
        /// frame path and in the background.
        #[arg(long, conflicts_with = "uber")]
        effect_changes: bool,
        /// Instead of the presets as they stand: a sun that moves every frame, the shadow
        /// atlas and air table redrawn whole each frame against cascades in rotation (a band a
        /// frame).
        #[arg(long, conflicts_with_all = ["uber", "effect_changes"])]
        moving_sun: bool,
    },
    /// Time per frame of each example scene's derived variant against its all-effects
    /// variant, as a ratio.
    BenchScenes {
        /// Image size, WIDTHxHEIGHT.
        #[arg(short, long, default_value = "480x270")]
        resolution: String,
        /// Timed frames per variant (the median is reported).
        #[arg(short = 'n', long, default_value_t = 3)]
        iterations: u32,
    },
    /// What accuracy costs in time: every preset, and high minus each effect, on the canonical
    /// views against a converged reference; writes a Markdown report and an SVG plot.
    Tradeoff(Box<tradeoff::TradeoffArgs>),
    /// Write a scene's cloud density on a grid as a Mitsuba volume (.vol), for offline
    /// renderers.
    ExportDensity(Box<export_density::ExportDensityArgs>),
    /// Which effects a scene's variant simulates, each with the reason, and the variant key.
    Explain {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Second of the scene's timeline (its clock's sun, its weather), as `render --time`
        /// takes it.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        time: f64,
    },
    /// List genera, scene presets, quality presets, toggles, the distinct shaders (one per
    /// key) with the genus × preset pairs that share each, and targets.
    List,
    /// Which shaders (keys) and targets differ between two emitted folders, or two git
    /// revisions of the Nimbus checkout in the current directory (built with cargo), with the
    /// WGSL diff of each changed key.
    Diff {
        /// The old side: a folder written by `nimbus emit`, or a git revision of the checkout.
        old: PathBuf,
        /// The new side: a folder written by `nimbus emit`, or a git revision of the checkout.
        new: PathBuf,
        /// Only list the changed keys and targets, without the WGSL diffs.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Time generation per variant and target, and the whole `check`.
    Bench {
        /// Timed repetitions per measurement (the median is reported).
        #[arg(short, long, default_value_t = 20)]
        iterations: u32,
        /// Also generate and validate every reachable key (599,040 cloud keys and 16 shadow
        /// keys), on every core, and report the time (minutes on 2 cores).
        #[arg(long)]
        reachable: bool,
        /// With `--reachable`: generate only this many keys, spread evenly over all of them,
        /// and extrapolate the time of the whole set.
        #[arg(long, value_name = "KEYS", requires = "reachable")]
        sample: Option<usize>,
    },
}

/// Runs the command the process's arguments name; what the `nimbus` binary does.
pub fn main() -> ExitCode {
    crate::session::quiet_display_probes();
    let cli = Cli::parse();
    let data = cli.data.as_deref();
    let result: Result<(), Box<dyn std::error::Error>> = match &cli.command {
        Command::Emit {
            variants,
            scene,
            time,
            targets: _,
            engine: Some(engine),
            out,
            force,
        } => package::run(
            data,
            &variants.selection(),
            scene.as_deref().map(|s| (s, *time)),
            *engine,
            (out, Overwrite::forced(*force)),
        ),
        Command::Emit {
            variants,
            scene,
            time,
            targets,
            engine: None,
            out,
            force,
        } => emit::run(
            data,
            &variants.selection(),
            scene.as_deref().map(|s| (s, *time)),
            &TargetChoice::resolve(targets),
            (out, Overwrite::forced(*force)),
        ),
        Command::Check {
            variants,
            no_external,
        } => check::run(data, &variants.selection(), !no_external),
        Command::Render(args) => render::run(data, args),
        Command::Gallery(args) => gallery::run(data, args),
        Command::Animate(args) => animate::run(data, args),
        Command::BenchFrames {
            render,
            effect_changes: true,
            ..
        } => bench_frames::run_effect_changes(data, render),
        Command::BenchFrames {
            render,
            iterations,
            moving_sun: true,
            ..
        } => bench_frames::run_moving_sun(data, render, (*iterations).max(1)),
        Command::BenchFrames {
            render,
            iterations,
            uber,
            ..
        } => bench_frames::run(data, render, (*iterations).max(1), *uber),
        Command::BenchScenes {
            resolution,
            iterations,
        } => render::parse_resolution(resolution)
            .and_then(|r| bench_frames::run_scenes(data, r, (*iterations).max(1))),
        Command::Tradeoff(args) => tradeoff::run(data, args),
        Command::ExportDensity(args) => export_density::run(data, args),
        Command::Explain { scene, time } => explain::run(data, scene, *time),
        Command::List => list::run(data).map_err(Into::into),
        Command::Diff { old, new, quiet } => diff::run(old, new, *quiet),
        Command::Bench {
            iterations,
            reachable,
            sample,
        } => bench::run(data, (*iterations).max(1), *reachable, *sample).map_err(Into::into),
    };
    crate::data_folder::remove_private_examples();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Not `eprintln!`: a closed stderr must not turn an error into a panic.
            say_err!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
