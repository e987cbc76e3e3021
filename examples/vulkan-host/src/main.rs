//! `nimbus-vulkan-host PACKAGE_DIR OUT.png`: draws a frame of a Nimbus Vulkan package with the
//! Vulkan API alone and writes it as PNG.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// A folder written by `nimbus emit --engine vulkan`.
    package: PathBuf,
    /// The PNG to write.
    out: PathBuf,
    /// The genus × preset pair (the package's first by default).
    #[arg(long)]
    pair: Option<String>,
    /// Replace OUT.png when it exists.
    #[arg(long)]
    force: bool,
    /// Picture size, `WIDTHxHEIGHT`.
    #[arg(short, long, default_value = "640x360", value_parser = size)]
    resolution: (u32, u32),
}

fn size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT"))?;
    let n = |v: &str| {
        v.parse::<u32>()
            .ok()
            .filter(|n| (1..=16384).contains(n))
            .ok_or_else(|| format!("`{v}` in `{s}` is not a size from 1 to 16384"))
    };
    Ok((n(w)?, n(h)?))
}

fn main() -> ExitCode {
    let args = Args::parse();
    if args.out.exists() && !args.force {
        eprintln!(
            "error: `{}` exists; pass --force to replace it",
            args.out.display()
        );
        return ExitCode::FAILURE;
    }
    let (w, h) = args.resolution;
    match nimbus_vulkan_host::render(&args.package, args.pair.as_deref(), w, h) {
        Ok(p) => {
            let written = image::RgbaImage::from_raw(p.width, p.height, p.rgba)
                .ok_or_else(|| "the picture has the wrong size".to_string())
                .and_then(|img| img.save(&args.out).map_err(|e| e.to_string()));
            match written {
                Ok(()) => {
                    println!(
                        "drew {}×{} on {} into {}",
                        w,
                        h,
                        p.device,
                        args.out.display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: cannot write `{}`: {e}", args.out.display());
                    ExitCode::FAILURE
                }
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
