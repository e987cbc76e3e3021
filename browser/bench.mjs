// The browser benchmark (not a test): Nimbus's three.js package and @takram/three-clouds
// (page/takram.mjs) at each quality preset, with temporal upscaling off and on, in the same
// headless Chromium as the browser test and in one run, 640×360, the same camera and sun and
// the same clouds' opacity (matched below), median ms/frame over timed frames after warm-up;
// Nimbus's shadow atlas and air table drawn every frame (as for a sun that moves each frame;
// takram redraws its shadow map every frame) and cached. Writes a Markdown table to stdout.
//
//   npm run bench            (uses ../target/release/nimbus; NIMBUS=path to override;
//                             BENCH_PRESETS=ultra,high for some presets only)
//
// Timings on SwiftShader (a CPU WebGL) are only comparable within one run.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { inflateSync } from 'node:zlib';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const nimbus = process.env.NIMBUS ?? resolve(here, '../target/release/nimbus');
const work = mkdtempSync(join(tmpdir(), 'nimbus-bench-'));
const frames = Number(process.env.BENCH_FRAMES ?? 5);
// The scenes match: the same camera and sun, and Nimbus's `takram-default` genus, which is
// takram's four default layers. The two libraries' coverages do not mean the same sky (takram's
// 0.6 is a thin overcast, Nimbus's a thick one), so the bench matches them itself before it
// times anything: takram keeps its own default, 0.6, and Nimbus's coverage is bisected until its
// clouds hide as much of what lies behind them as takram's do: the mean opacity of the clouds
// (1 − transmittance, the alpha of the target each library draws its clouds into; takram's
// without its haze) over the pixels above the horizon, `low`, 640×360 (`output=opacity` on both
// pages, page/opacity.mjs). NIMBUS_COVERAGE skips the search. It used to count the pixels that
// differ from a clear render by more than 12/255: that saturated (0.998 in both libraries) once
// the clouds' shadows dimmed the clear air between them, so the bisection found the lowest
// coverage that saturated it, and moved whenever the air's light changed.
const takramCoverage = 0.6;
const view = { width: 640, height: 360, pitch: 10, fov: 60 };
const rows = [];
const median = (text) => Number(/median ms\/frame: ([0-9.]+)/.exec(text)?.[1]);
const presets = (process.env.BENCH_PRESETS ?? 'low,medium,high,ultra').split(',');

/** Decodes an 8-bit, non-interlaced RGB or RGBA PNG (what Chromium's canvas writes). */
function decodePng(bytes) {
  let at = 8;
  let width = 0;
  let height = 0;
  let channels = 4;
  const idat = [];
  while (at < bytes.length) {
    const length = bytes.readUInt32BE(at);
    const type = bytes.toString('ascii', at + 4, at + 8);
    const data = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      if (data[8] !== 8 || data[12] !== 0) throw new Error('only 8-bit non-interlaced PNGs');
      channels = { 2: 3, 6: 4 }[data[9]];
      if (!channels) throw new Error(`PNG colour type ${data[9]}`);
    } else if (type === 'IDAT') idat.push(data);
    at += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const out = new Uint8Array(height * stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    for (let x = 0; x < stride; x++) {
      const v = raw[y * (stride + 1) + 1 + x];
      const a = x >= channels ? out[y * stride + x - channels] : 0;
      const b = y > 0 ? out[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? out[(y - 1) * stride + x - channels] : 0;
      let p = 0;
      if (filter === 1) p = a;
      else if (filter === 2) p = b;
      else if (filter === 3) p = (a + b) >> 1;
      else if (filter === 4) {
        const e = a + b - c;
        const [pa, pb, pc] = [Math.abs(e - a), Math.abs(e - b), Math.abs(e - c)];
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      out[y * stride + x] = (v + p) & 255;
    }
  }
  return { width, height, channels, data: out };
}

/** The mean of an `output=opacity` picture's grey over the pixels above the horizon (0–1). */
function meanOpacity(png) {
  const a = decodePng(readFileSync(png));
  // The horizon's row: the camera pitched up `pitch` with a vertical field of view `fov`.
  const tan = (deg) => Math.tan((deg * Math.PI) / 180);
  const horizon = Math.floor((a.height / 2) * (1 + tan(view.pitch) / tan(view.fov / 2)));
  let sum = 0;
  for (let y = 0; y < horizon; y++) {
    for (let x = 0; x < a.width; x++) sum += a.data[(y * a.width + x) * a.channels];
  }
  return sum / (255 * horizon * a.width);
}

const size = [`width=${view.width}`, `height=${view.height}`, `pitch=${view.pitch}`, `fov=${view.fov}`];
const takramAt = (out, c) => execFileSync('node', ['takram.mjs', out, ...size, 'quality=low', `coverage=${c}`,
  'sun=35,150', 'altitude=2', 'yaw=0', 'upscale=0', 'output=opacity'], { cwd: here, encoding: 'utf8' });

/** takram's clouds' mean opacity at its coverage, and Nimbus's coverage of the same opacity. */
function matchedNimbusCoverage() {
  const takramOpacity = join(work, 'takram-opacity.png');
  takramAt(takramOpacity, takramCoverage);
  const target = meanOpacity(takramOpacity);
  const scene = join(work, 'opacity.toml');
  writeFileSync(scene, [
    'name = "opacity"', 'description = "The browser benchmark\'s cloud match."',
    'genus = "takram-default"', 'quality = "low"', 'sun_elevation_deg = 35.0',
    'sun_azimuth_deg = 150.0', 'camera_altitude = 2.0', `camera_pitch_deg = ${view.pitch}.0`, '',
  ].join('\n'));
  const pkg = join(work, 'package-opacity');
  execFileSync(nimbus, ['emit', '--engine', 'three', '--scene', scene, '-o', pkg], { stdio: ['ignore', 'ignore', 'inherit'] });
  // The package's own weather control sets the coverage (`setWeather`).
  const opacityAt = (c) => {
    const out = join(work, `nimbus-opacity-${c.toFixed(4)}.png`);
    execFileSync('node', ['render.mjs', pkg, out, ...size, `weather=${c}`, 'output=opacity'],
      { cwd: here, encoding: 'utf8' });
    return meanOpacity(out);
  };
  let [lo, hi] = [0.0, 1.0];
  for (let i = 0; i < 10; i++) {
    const mid = (lo + hi) / 2;
    if (opacityAt(mid) < target) lo = mid;
    else hi = mid;
  }
  const matched = (lo + hi) / 2;
  return { target, matched, reached: opacityAt(matched) };
}

let coverage = process.env.NIMBUS_COVERAGE;
if (coverage === undefined) {
  const m = matchedNimbusCoverage();
  coverage = m.matched.toFixed(4);
  console.error(`the clouds' mean opacity above the horizon: takram ${m.target.toFixed(3)} at coverage `
    + `${takramCoverage}; Nimbus ${m.reached.toFixed(3)} at coverage ${coverage} (bisected)`);
}

for (const quality of presets) {
  const scene = join(work, `${quality}.toml`);
  writeFileSync(scene, [
    `name = "${quality}"`, 'description = "The browser benchmark\'s scene."',
    'genus = "takram-default"', `quality = "${quality}"`, `coverage = ${coverage}`, 'sun_elevation_deg = 35.0',
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
// The paths other than the volume, each at `low` (the cheapest picture of each), against the
// volume's `low` timed above: the same scene, drawn by another path (BENCH_PATHS=slices,...;
// BENCH_PATHS= for none). `every` rebakes the path's own tables each frame as for a sun that
// moves every frame; `cached` bakes them once.
const paths = (process.env.BENCH_PATHS ?? 'slices,impostor,mesh,blob2d').split(',').filter((p) => p);
const pathRows = [];
for (const path of paths) {
  const scene = join(work, `path-${path}.toml`);
  writeFileSync(scene, [
    `name = "path-${path}"`, 'description = "The browser benchmark\'s scene, drawn by another path."',
    'genus = "takram-default"', 'quality = "low"', `coverage = ${coverage}`, 'sun_elevation_deg = 35.0',
    'sun_azimuth_deg = 150.0', 'camera_altitude = 2.0', 'camera_pitch_deg = 10.0', '[features]',
    `path = "${path}"`, '',
  ].join('\n'));
  const pkg = join(work, `package-path-${path}`);
  execFileSync(nimbus, ['emit', '--engine', 'three', '--scene', scene, '-o', pkg], { stdio: ['ignore', 'ignore', 'inherit'] });
  for (const upscale of [false, true]) {
    const row = { path, upscale };
    for (const shadow of ['every', 'cached']) {
      const out = join(work, `path-${path}-${upscale}-${shadow}.png`);
      const args = ['render.mjs', pkg, out, 'width=640', 'height=360', 'pitch=10', `bench=${frames}`,
        'warmup=2', `shadow=${shadow}`, `upscale=${upscale ? 1 : 0}`];
      row[shadow] = median(execFileSync('node', args, { cwd: here, encoding: 'utf8' }));
    }
    pathRows.push(row);
    console.error(`path ${path} upscale=${upscale}: ${row.every} / ${row.cached} ms`);
  }
}

console.log('| preset | upscaling | Nimbus, atlas every frame | Nimbus, atlas cached | @takram/three-clouds | Nimbus ÷ takram (every frame / cached) |');
console.log('|---|---|---|---|---|---|');
for (const r of rows) {
  const ratio = (x) => (x / r.takram).toFixed(2);
  console.log(`| ${r.quality} | ${r.upscale ? 'on' : 'off'} | ${r.every.toFixed(1)} | ${r.cached.toFixed(1)} | ${r.takram.toFixed(1)} | ${ratio(r.every)} / ${ratio(r.cached)} |`);
}
if (pathRows.length) {
  console.log();
  console.log('| path (at `low`) | upscaling | every frame | cached | volume `low`, cached | ÷ volume `low` (every frame / cached) |');
  console.log('|---|---|---|---|---|---|');
  for (const r of pathRows) {
    const low = rows.find((v) => v.quality === 'low' && v.upscale === r.upscale);
    const ratio = (x) => (low ? (x / low.cached).toFixed(2) : '–');
    console.log(`| ${r.path} | ${r.upscale ? 'on' : 'off'} | ${r.every.toFixed(1)} | ${r.cached.toFixed(1)} | ${low ? low.cached.toFixed(1) : '–'} | ${ratio(r.every)} / ${ratio(r.cached)} |`);
  }
}
