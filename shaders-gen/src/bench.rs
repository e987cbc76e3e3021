//! `nimbus bench`: how long code generation takes. It measures and prints; nothing asserts a time.

use std::time::{Duration, Instant};

use std::path::Path;

use nimbus_clouds::catalog::{ShaderKey, catalog, cloud_catalog};
use nimbus_clouds::{CloudKey, ShadowKey};
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

pub(crate) fn run(data: Option<&Path>, iterations: u32, reachable: bool) -> Result<(), CliError> {
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
        "(the wgsl column is record + specialise + print + naga parse/validate; other columns add one backend)"
    );
    if reachable {
        every_reachable_key()?;
    }
    Ok(())
}

/// Generates every reachable cloud and shadow key, WGSL (the printed, naga-validated gate of
/// every target) and then all six targets, split over the machine's cores.
fn every_reachable_key() -> Result<(), CliError> {
    let keys: Vec<ShaderKey> = CloudKey::reachable()
        .into_iter()
        .map(ShaderKey::Clouds)
        .chain(ShadowKey::reachable().into_iter().map(ShaderKey::Shadow))
        .collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    for (what, targets) in [
        ("WGSL + naga validation", &[Target::Wgsl][..]),
        ("all six targets", &Target::ALL[..]),
    ] {
        let start = Instant::now();
        let chunk = keys.len().div_ceil(threads);
        let failures: Vec<String> = std::thread::scope(|scope| {
            let handles: Vec<_> = keys
                .chunks(chunk)
                .map(|part| {
                    scope.spawn(move || {
                        part.iter()
                            .filter_map(|k| {
                                generate_variant(k, targets)
                                    .err()
                                    .map(|e| format!("{}: {e}", k.id()))
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| {
                    h.join()
                        .unwrap_or_else(|_| vec!["a thread panicked".into()])
                })
                .collect()
        });
        let secs = start.elapsed().as_secs_f64();
        say!(
            "every reachable key ({} keys, {what}, {threads} thread(s)): {secs:.1} s, {:.2} ms per key per core, {} failure(s)",
            keys.len(),
            secs * 1e3 * threads as f64 / keys.len() as f64,
            failures.len()
        );
        for f in failures.iter().take(5) {
            say_err!("FAIL {f}");
        }
    }
    Ok(())
}
