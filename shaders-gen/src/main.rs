//! `nimbus`: emit, check, list and benchmark the generated shaders.

mod bench;
mod check;
mod emit;
mod list;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Nimbus: volumetric-cloud shaders written once in Rust, emitted for every target.
#[derive(Parser)]
#[command(name = "nimbus", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate, validate and write shaders (one file per target and entry point, plus a JSON
    /// binding manifest beside each GLSL/HLSL/MSL file).
    Emit {
        /// `module` or `module/variant` (see `nimbus list`); all variants when omitted.
        name: Option<String>,
        /// Comma-separated targets: wgsl, glsl-es300, glsl450, hlsl, msl, spirv, or all.
        #[arg(short, long, default_value = "all")]
        targets: String,
        /// Output folder (created; replaced only if it is empty or a previous Nimbus output).
        #[arg(short, long, default_value = "nimbus-out")]
        out: PathBuf,
    },
    /// Generate and validate every variant for every target (naga, plus glslangValidator and
    /// spirv-val when installed); exits non-zero on any failure.
    Check {
        /// Skip glslangValidator and spirv-val even when installed.
        #[arg(long)]
        no_external: bool,
    },
    /// List modules, variants and targets.
    List,
    /// Time generation per variant and target, and the whole `check`.
    Bench {
        /// Timed repetitions per measurement (the median is reported).
        #[arg(short, long, default_value_t = 20)]
        iterations: u32,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), Box<dyn std::error::Error>> = match cli.command {
        Command::Emit { name, targets, out } => {
            emit::run(name.as_deref(), &targets, &out).map_err(Into::into)
        }
        Command::Check { no_external } => check::run(!no_external),
        Command::List => {
            list::run();
            Ok(())
        }
        Command::Bench { iterations } => bench::run(iterations.max(1)).map_err(Into::into),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
