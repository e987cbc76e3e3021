// Nimbus timeline: what a scene's `[wind]` and `[[weather]]` (within one genus) make of the
// cloud block's uniforms at a time, as `nimbus render --time` does. No three.js: NimbusClouds
// (nimbus-clouds.js) drives its uniforms with it, and any JavaScript host can.
//
//   import { NimbusTimeline } from './nimbus-timeline.js';
//   const timeline = new NimbusTimeline(0.25);            // the coverage at second 0
//   timeline.setWind(6, 260, 20, 280);                     // m/s, from (degrees), ground and 10 km
//   timeline.setWeather(0.35, { at: 7200 });               // reached by second 7200
//   const { wind_drift, wind_shear_drift, coverage } = timeline.at(9000);
//
// The wind's velocity and the drift it makes, and the weather's progress and ramp, are the
// JavaScript twins of Nimbus's own `#[shader_fn]`s (nimbus-wind.js, generated): no formula is
// typed twice. What is here is the bookkeeping: the states in time order, and which two the
// time falls between.

import { weather_coverage, weather_progress, wind_drift, wind_velocity } from './nimbus-wind.js';

export class NimbusTimeline {
  /** A still timeline whose coverage is `coverage` (0..1) until a weather state changes it. */
  constructor(coverage) {
    this.coverage = coverage;
    this.wind = null;
    this.states = [];
  }

  /**
   * The wind, as a scene's `[wind]` gives it: `speed` (m/s) near the ground and `directionDeg`,
   * where it blows from, degrees clockwise from north (270: a westerly, blowing east);
   * `topSpeed` and `topDirectionDeg` at 10 km (the ground's by default: no shear). Linear in
   * altitude between the two.
   */
  setWind(speed, directionDeg, topSpeed = speed, topDirectionDeg = directionDeg) {
    for (const [name, v] of [['speed', speed], ['directionDeg', directionDeg], ['topSpeed', topSpeed], ['topDirectionDeg', topDirectionDeg]]) {
      if (!Number.isFinite(v)) throw new Error(`setWind: ${name} must be a finite number, got ${v}`);
    }
    this.wind = { speed, directionDeg, topSpeed, topDirectionDeg };
  }

  /**
   * A weather state, as a scene's `[[weather]]` within the pair's genus: by `at` seconds the
   * coverage has become `coverage` (0..1), ramping smoothly (smoothstep) from the state before
   * it — from that state's time (second 0 and the starting coverage for the first), or over the
   * last `over` seconds before `at` when `over` is given. Without `at`, the state is reached
   * `over` seconds (default 0: at once) after `now`. A state at the time of another one is a cut.
   */
  setWeather(coverage, { at, over, now = 0 } = {}) {
    if (!(coverage >= 0 && coverage <= 1)) throw new Error(`setWeather: coverage must be in [0, 1], got ${coverage}`);
    if (over !== undefined && !(over >= 0)) throw new Error(`setWeather: over must be 0 or more seconds, got ${over}`);
    const when = at ?? now + (over ?? 0);
    if (!Number.isFinite(when)) throw new Error(`setWeather: at must be a finite number of seconds, got ${when}`);
    // Kept in time order; a state at the time of another one comes after it.
    const index = this.states.findIndex((s) => s.at > when);
    const state = { at: when, coverage, over };
    if (index === -1) this.states.push(state);
    else this.states.splice(index, 0, state);
  }

  /** Forgets every weather state: the starting coverage holds again. */
  clearWeather() {
    this.states = [];
  }

  /** The coverage `seconds` after the start, as Nimbus's timeline gives it. */
  coverageAt(seconds) {
    const next = this.states.findIndex((s) => s.at > seconds);
    if (next === -1) return this.states.length ? this.states[this.states.length - 1].coverage : this.coverage;
    const from = next === 0 ? { at: 0, coverage: this.coverage } : this.states[next - 1];
    const to = this.states[next];
    const progress = weather_progress(seconds, from.at, to.at, to.over ?? -1);
    return weather_coverage(from.coverage, to.coverage, progress);
  }

  /**
   * The drift `seconds` after the start: `wind_drift`, how far the air near the ground has
   * travelled (m, x east, z south), and `wind_shear_drift`, how much farther per metre of
   * altitude — the cloud block's `media.wind_drift` and `media.wind_shear_drift`. Zero without
   * a wind.
   */
  driftAt(seconds) {
    if (!this.wind) return { wind_drift: [0, 0], wind_shear_drift: [0, 0] };
    const w = this.wind;
    const [x, z, shearX, shearZ] = wind_drift(
      wind_velocity(w.speed, w.directionDeg),
      wind_velocity(w.topSpeed, w.topDirectionDeg),
      seconds,
    );
    return { wind_drift: [x, z], wind_shear_drift: [shearX, shearZ] };
  }

  /** The uniforms `seconds` after the start: `wind_drift`, `wind_shear_drift` and `coverage`. */
  at(seconds) {
    return { ...this.driftAt(seconds), coverage: this.coverageAt(seconds) };
  }
}
