//! Running a scene's formation automaton up to a time with the work shown: a `[formation]`
//! scene far into its timeline takes tens of thousands of steps over up to a million cells,
//! minutes on a software adapter. The step count and cell count are printed before the work and
//! a progress bar follows it, so a long run never looks like a hang.

use indicatif::{ProgressBar, ProgressStyle};
use nimbus_clouds::formation::Formation;
use nimbus_runtime::formation::FormationSim;
use nimbus_runtime::{Gpu, RuntimeError};

/// Steps below which the automaton runs without a bar (a blink on any adapter).
const QUIET_STEPS: u32 = 256;

/// Advances `sim` to what the weather at `seconds` reads (the step there and the one after),
/// printing the work first and showing its progress.
pub(crate) fn advance(
    gpu: &Gpu,
    sim: &mut FormationSim<'_>,
    settings: &Formation,
    seconds: f64,
) -> Result<(), RuntimeError> {
    let target = settings.step_at(seconds).0.saturating_add(1);
    let from = if target < sim.step() { 0 } else { sim.step() };
    let steps = target - from;
    if steps < QUIET_STEPS {
        return sim.advance_to(target);
    }
    say!(
        "formation: {steps} steps of the {c}x{c} automaton to reach second {seconds}",
        c = settings.cells
    );
    let bar = ProgressBar::new(u64::from(steps));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let chunk = (steps / 100).max(1);
    let mut at = from;
    while at < target {
        at = (at + chunk).min(target);
        sim.advance_to(at)?;
        // Submitted is not done: wait for the steps so the bar shows the work, not the queue.
        let _ = gpu.device().poll(wgpu::PollType::wait_indefinitely());
        bar.set_position(u64::from(at - from));
    }
    bar.finish_and_clear();
    Ok(())
}
