// The browser benchmark (not a test): Nimbus's three.js package at each quality preset, with
// temporal upscaling off and on, in the same headless Chromium as the browser test, 640×360,
// median ms/frame over timed frames after warm-up, the shadow atlas drawn every frame and
// cached. Writes a Markdown table to stdout.
//
//   npm run bench            (uses ../target/release/nimbus; NIMBUS=path to override)
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
const rows = [];
for (const quality of ['low', 'medium', 'high']) {
  const scene = join(work, `${quality}.toml`);
  writeFileSync(scene, [
    `name = "${quality}"`, 'description = "The browser benchmark\'s scene."',
    'genus = "cumulus"', `quality = "${quality}"`, 'coverage = 0.6', 'sun_elevation_deg = 35.0',
    'sun_azimuth_deg = 150.0', 'camera_altitude = 2.0', 'camera_pitch_deg = 10.0', '',
  ].join('\n'));
  const pkg = join(work, `package-${quality}`);
  execFileSync(nimbus, ['emit', '--engine', 'three', '--scene', scene, '-o', pkg], { stdio: ['ignore', 'ignore', 'inherit'] });
  for (const upscale of [false, true]) {
    for (const shadow of ['every', 'cached']) {
      const out = join(work, `${quality}-${upscale}-${shadow}.png`);
      const args = ['render.mjs', pkg, out, 'width=640', 'height=360', 'pitch=10', `bench=${frames}`,
        'warmup=2', `shadow=${shadow}`, `upscale=${upscale ? 1 : 0}`];
      const text = execFileSync('node', args, { cwd: here, encoding: 'utf8' });
      const ms = Number(/median ms\/frame: ([0-9.]+)/.exec(text)?.[1]);
      rows.push({ quality, upscale, shadow, ms });
      console.error(`${quality} upscale=${upscale} shadow=${shadow}: ${ms} ms`);
    }
  }
}
console.log('| preset | upscaling | shadow atlas | Nimbus ms/frame |');
console.log('|---|---|---|---|');
for (const r of rows) console.log(`| ${r.quality} | ${r.upscale ? 'on' : 'off'} | ${r.shadow} | ${r.ms.toFixed(1)} |`);
