// The browser benchmark (not a test): Nimbus's three.js package and @takram/three-clouds
// (page/takram.mjs) at each quality preset, with temporal upscaling off and on, in the same
// headless Chromium as the browser test and in one run, 640×360, the same camera, sun and
// coverage value, median ms/frame over timed frames after warm-up; Nimbus's shadow atlas drawn
// every frame (as takram does) and cached. Writes a Markdown table to stdout.
//
//   npm run bench            (uses ../target/release/nimbus; NIMBUS=path to override;
//                             BENCH_PRESETS=ultra,high for some presets only)
//
// Timings on SwiftShader (a CPU WebGL) are only comparable within one run.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const nimbus = process.env.NIMBUS ?? resolve(here, '../target/release/nimbus');
const work = mkdtempSync(join(tmpdir(), 'nimbus-bench-'));
const frames = Number(process.env.BENCH_FRAMES ?? 5);
// The scenes match: the same camera and sun, and Nimbus's `takram-default` genus, which is
// takram's four default layers. Coverage means nearly the same in both then: the fraction of
// pixels above the horizon that differ by more than 12/255 from a coverage-0 render of the same
// view (low preset, 640×360) is 0.877 for Nimbus and 0.902 for takram at 0.6 (measured once
// on this machine; TAKRAM_COVERAGE overrides takram's).
const takramCoverage = process.env.TAKRAM_COVERAGE ?? '0.6';
const rows = [];
const median = (text) => Number(/median ms\/frame: ([0-9.]+)/.exec(text)?.[1]);
const presets = (process.env.BENCH_PRESETS ?? 'low,medium,high,ultra').split(',');
for (const quality of presets) {
  const scene = join(work, `${quality}.toml`);
  writeFileSync(scene, [
    `name = "${quality}"`, 'description = "The browser benchmark\'s scene."',
    'genus = "takram-default"', `quality = "${quality}"`, 'coverage = 0.6', 'sun_elevation_deg = 35.0',
    'sun_azimuth_deg = 150.0', 'camera_altitude = 2.0', 'camera_pitch_deg = 10.0', '',
  ].join('\n'));
  const pkg = join(work, `package-${quality}`);
  execFileSync(nimbus, ['emit', '--engine', 'three', '--scene', scene, '-o', pkg], { stdio: ['ignore', 'ignore', 'inherit'] });
  for (const upscale of [false, true]) {
    const row = { quality, upscale };
    for (const shadow of ['every', 'cached']) {
      const out = join(work, `${quality}-${upscale}-${shadow}.png`);
      const args = ['render.mjs', pkg, out, 'width=640', 'height=360', 'pitch=10', `bench=${frames}`,
        'warmup=2', `shadow=${shadow}`, `upscale=${upscale ? 1 : 0}`];
      row[shadow] = median(execFileSync('node', args, { cwd: here, encoding: 'utf8' }));
    }
    const out = join(work, `${quality}-${upscale}-takram.png`);
    const args = ['takram.mjs', out, 'width=640', 'height=360', `quality=${quality}`, `coverage=${takramCoverage}`,
      'sun=35,150', 'altitude=2', 'pitch=10', 'yaw=0', 'fov=60', `upscale=${upscale ? 1 : 0}`,
      `bench=${frames}`, 'warmup=2'];
    row.takram = median(execFileSync('node', args, { cwd: here, encoding: 'utf8' }));
    rows.push(row);
    console.error(`${quality} upscale=${upscale}: Nimbus ${row.every} / ${row.cached} ms, takram ${row.takram} ms`);
  }
}
console.log('| preset | upscaling | Nimbus, atlas every frame | Nimbus, atlas cached | @takram/three-clouds | Nimbus ÷ takram (every frame / cached) |');
console.log('|---|---|---|---|---|---|');
for (const r of rows) {
  const ratio = (x) => (x / r.takram).toFixed(2);
  console.log(`| ${r.quality} | ${r.upscale ? 'on' : 'off'} | ${r.every.toFixed(1)} | ${r.cached.toFixed(1)} | ${r.takram.toFixed(1)} | ${ratio(r.every)} / ${ratio(r.cached)} |`);
}
