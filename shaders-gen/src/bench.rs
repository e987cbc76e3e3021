//! `nimbus bench`: how long code generation takes. It measures and prints; nothing asserts a time.

use std::time::{Duration, Instant};

use nimbus_codegen::{CodegenError, Target, catalog, generate_variant};

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn time<T>(
    iterations: u32,
    mut f: impl FnMut() -> Result<T, CodegenError>,
) -> Result<Duration, CodegenError> {
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

pub(crate) fn run(iterations: u32) -> Result<(), CodegenError> {
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
    for source in catalog() {
        let mut row = format!("| {:<20} |", source.key());
        for t in Target::ALL {
            let d = time(iterations, || generate_variant(&source, &[t]))?;
            row.push_str(&format!(" {:>10} |", ms(d)));
        }
        let d = time(iterations, || generate_variant(&source, &Target::ALL))?;
        row.push_str(&format!(" {:>10} |", ms(d)));
        println!("{row}");
    }
    let whole = time(iterations, || {
        for source in catalog() {
            generate_variant(&source, &Target::ALL)?;
        }
        Ok(())
    })?;
    println!(
        "whole check (every variant, every target, naga validation, no external tools): {} ms",
        ms(whole)
    );
    println!(
        "(the wgsl column is record + specialise + print + naga parse/validate; other columns add one backend)"
    );
    Ok(())
}
