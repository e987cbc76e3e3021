//! `nimbus bench`: how long code generation takes. It measures and prints; nothing asserts a time.

use std::time::{Duration, Instant};

use std::path::Path;

use nimbus_clouds::catalog::{ShaderKey, catalog, cloud_catalog};
use nimbus_clouds::{CloudKey, ShadowKey};
use rayon::prelude::*;

use nimbus_codegen::{Target, generate_variant, lower_and_validate, print_and_validate, validate};

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

pub(crate) fn run(
    data: Option<&Path>,
    iterations: u32,
    reachable: bool,
    sample: Option<usize>,
) -> Result<(), CliError> {
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
    say!("nimbus bench: median of {iterations} runs, {profile} build, times in ms");
    let mut header = format!("| {:<20} |", "variant");
    for t in Target::ALL {
        header.push_str(&format!(" {:>10} |", t.name()));
    }
    header.push_str(&format!(" {:>10} |", "all six"));
    say!("{header}");
    say!("|{}|", ["---"; 8].join("|"));
    let _ = &lib;
    for source in &rows {
        let mut row = format!("| {:<20} |", source.id());
        for t in Target::ALL {
            let d = time(iterations, || Ok(generate_variant(source, &[t])?))?;
            row.push_str(&format!(" {:>10} |", ms(d)));
        }
        let d = time(iterations, || Ok(generate_variant(source, &Target::ALL)?))?;
        row.push_str(&format!(" {:>10} |", ms(d)));
        say!("{row}");
    }
    let mut all = catalog();
    all.extend(clouds);
    let whole = time(iterations.min(3), || {
        for source in &all {
            generate_variant(source, &Target::ALL)?;
        }
        Ok(())
    })?;
    say!(
        "every distinct shader ({} x 6 targets, naga validation, no external tools): {} ms",
        all.len(),
        ms(whole)
    );
    say!(
        "(the wgsl column is record + specialise + share + rename + print + lowering to naga + validation; other columns add one backend)"
    );
    let high = rows.iter().find(|v| {
        matches!(v.key, ShaderKey::Clouds(_)) && v.users.iter().any(|u| u == "cumulus.high")
    });
    if let Some(high) = high {
        breakdown(high, iterations)?;
    }
    if reachable {
        every_reachable_key(sample)?;
    }
    Ok(())
}

/// Where one key's WGSL time goes, and what the gate cost when the printed text was parsed
/// back instead of lowering the IR (measured here, in the same run).
fn breakdown(source: &impl ShaderVariant, iterations: u32) -> Result<(), CliError> {
    let record = time(iterations, || Ok(source.record()?))?;
    let whole = time(iterations, || {
        Ok(print_and_validate(source.record()?, &source.variant())?)
    })?;
    let (ir, wgsl, spans, _) = print_and_validate(source.record()?, &source.variant())?;
    let variant = source.variant();
    let lowered = time(iterations, || {
        Ok(lower_and_validate(&ir, &wgsl, &spans, &variant)?)
    })?;
    let parsed = time(iterations, || {
        Ok(validate(&wgsl, &spans, &ir.name, &variant)?)
    })?;
    say!(
        "{}: record {} ms; specialise + share + rename + print {} ms; lower + validate {} ms (parsing the printed WGSL back and validating it instead: {} ms, {:.1}x)",
        source.id(),
        ms(record),
        ms(whole.saturating_sub(record).saturating_sub(lowered)),
        ms(lowered),
        ms(parsed),
        parsed.as_secs_f64() / lowered.as_secs_f64().max(1e-9)
    );
    Ok(())
}

/// Generates every reachable cloud and shadow key, WGSL (the printed, naga-validated gate of
/// every target) and then all six targets, split over the machine's cores.
fn every_reachable_key(sample: Option<usize>) -> Result<(), CliError> {
    let all: Vec<ShaderKey> = CloudKey::reachable()
        .into_iter()
        .map(ShaderKey::Clouds)
        .chain(ShadowKey::reachable().into_iter().map(ShaderKey::Shadow))
        .collect();
    let total = all.len();
    // An even spread: every n-th key, so each toggle set, octave count and phase kind shows.
    let step = sample.map_or(1, |n| total.div_ceil(n.max(1)));
    let keys: Vec<ShaderKey> = all.into_iter().step_by(step).collect();
    // The keys and each key's own targets share one pool (rayon), so a key's parallel work
    // steals from the others' instead of oversubscribing the cores.
    let threads = rayon::current_num_threads();
    for (what, targets) in [
        ("WGSL + naga validation", &[Target::Wgsl][..]),
        ("all six targets", &Target::ALL[..]),
    ] {
        let start = Instant::now();
        let failures: Vec<String> = keys
            .par_iter()
            .filter_map(|k| {
                match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    generate_variant(k, targets)
                })) {
                    Ok(Ok(_)) => None,
                    Ok(Err(e)) => Some(format!("{}: {e}", k.id())),
                    Err(_) => Some(format!("{}: generation panicked", k.id())),
                }
            })
            .collect();
        let secs = start.elapsed().as_secs_f64();
        let per_key = secs * 1e3 * threads as f64 / keys.len() as f64;
        if keys.len() == total {
            say!(
                "every reachable key ({total} keys, {what}, {threads} thread(s)): {secs:.1} s, {per_key:.2} ms per key per core, {} failure(s)",
                failures.len()
            );
        } else {
            say!(
                "{} of the {total} reachable keys, evenly spread ({what}, {threads} thread(s)): {secs:.1} s, {per_key:.2} ms per key per core, {} failure(s); all {total} would take {:.0} s",
                keys.len(),
                failures.len(),
                per_key * total as f64 / threads as f64 / 1e3
            );
        }
        for f in failures.iter().take(5) {
            say_err!("FAIL {f}");
        }
    }
    Ok(())
}
