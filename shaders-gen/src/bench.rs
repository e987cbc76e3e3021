//! `nimbus bench`: how long code generation takes. It measures and prints; nothing asserts a time.

use std::time::{Duration, Instant};

use std::path::Path;

use nimbus_clouds::catalog::{catalog, cloud_catalog};
use nimbus_codegen::{Target, generate_variant};

use crate::error::CliError;
use nimbus_dsl::ShaderVariant;

use crate::data::load;

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn time<T>(
    iterations: u32,
    mut f: impl FnMut() -> Result<T, CliError>,
) -> Result<Duration, CliError> {
    // One untimed run warms caches and surfaces errors.
    f()?;
    let mut samples = Vec::with_capacity(iterations as usize);
    for _ in 0..iterations {
        let start = Instant::now();
        f()?;
        samples.push(start.elapsed());
    }
    Ok(median(samples))
}

fn ms(d: Duration) -> String {
    format!("{:.3}", d.as_secs_f64() * 1e3)
}

pub(crate) fn run(data: Option<&Path>, iterations: u32) -> Result<(), CliError> {
    let lib = load(data)?;
    let clouds = cloud_catalog(&lib);
    // Per-target rows for the previews and the shaders cumulus runs at each quality; every
    // distinct shader is timed once at the end.
    let mut rows = catalog();
    rows.extend(
        clouds
            .iter()
            .filter(|v| v.users.iter().any(|u| u.starts_with("cumulus.")))
            .cloned(),
    );
    let profile = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    println!("nimbus bench: median of {iterations} runs, {profile} build, times in ms");
    let mut header = format!("| {:<20} |", "variant");
    for t in Target::ALL {
        header.push_str(&format!(" {:>10} |", t.name()));
    }
    header.push_str(&format!(" {:>10} |", "all six"));
    println!("{header}");
    println!("|{}|", ["---"; 8].join("|"));
    let _ = &lib;
    for source in &rows {
        let mut row = format!("| {:<20} |", source.id());
        for t in Target::ALL {
            let d = time(iterations, || Ok(generate_variant(source, &[t])?))?;
            row.push_str(&format!(" {:>10} |", ms(d)));
        }
        let d = time(iterations, || Ok(generate_variant(source, &Target::ALL)?))?;
        row.push_str(&format!(" {:>10} |", ms(d)));
        println!("{row}");
    }
    let mut all = catalog();
    all.extend(clouds);
    let whole = time(iterations.min(3), || {
        for source in &all {
            generate_variant(source, &Target::ALL)?;
        }
        Ok(())
    })?;
    println!(
        "every distinct shader ({} x 6 targets, naga validation, no external tools): {} ms",
        all.len(),
        ms(whole)
    );
    println!(
        "(the wgsl column is record + specialise + print + naga parse/validate; other columns add one backend)"
    );
    Ok(())
}
