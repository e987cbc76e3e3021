// Nimbus host state: what any JavaScript host of a Nimbus engine package keeps and writes into
// the uniform blocks — the camera, the sun, the timeline and the frame sequence — with no
// graphics API. nimbus-clouds.js (three.js) and nimbus-webgpu.js (WebGPU) draw with it; the
// formulas themselves are the JavaScript twins of Nimbus's Rust host functions
// (nimbus-frame.js, nimbus-sun.js, nimbus-wind.js), printed from the same source the wgpu
// runtime runs.

import { cloud_frame, resolve_frame } from './nimbus-frame.js';
import {
  anchored_tiles, atlas_columns, atlas_rows, band_redraw, redrawn_tiles, shadow_anchor, sun_direction, sun_light, tiles_out_of_date,
} from './nimbus-sun.js';
import { NimbusTimeline } from './nimbus-timeline.js';
import { facing_altitude } from './nimbus-wind.js';

/** The bytes of a hex string. */
function fromHex(hex) {
  const bytes = new Uint8Array(hex.length / 2);
  for (let i = 0; i < bytes.length; i++) bytes[i] = parseInt(hex.substr(2 * i, 2), 16);
  return bytes;
}

/** A uniform block: its bytes, with float and uint views, and member offsets by path. */
export class Block {
  constructor(json) {
    this.bytes = fromHex(json.bytes_hex);
    this.floats = new Float32Array(this.bytes.buffer);
    this.uints = new Uint32Array(this.bytes.buffer);
    this.ints = new Int32Array(this.bytes.buffer);
    this.members = json.members;
    this.offsets = new Map(json.members.map((m) => [m.member, m.offset / 4]));
    this.types = new Map(json.members.map((m) => [m.member, m.type]));
  }

  /**
   * Writes each field of `values` (a result of a generated host function, whose fields are
   * named after the block's members) into the member of that name: numbers and arrays, as
   * the member's type stores them.
   */
  assign(values) {
    for (const [member, value] of Object.entries(values)) {
      const at = this.word(member);
      const words = [value].flat(2);
      const type = this.types.get(member);
      const view = /u32/.test(type) ? this.uints : /i32/.test(type) ? this.ints : this.floats;
      view.set(words, at);
    }
  }

  /**
   * The block as the JavaScript twins of shader functions take it: nested objects by field
   * name, arrays for vectors and fixed arrays, matrices as arrays of columns.
   */
  toObject() {
    const root = {};
    for (const m of this.members) {
      const at = m.offset / 4;
      const count = m.value.length;
      const view = /u32/.test(m.type) ? this.uints : /i32/.test(m.type) ? this.ints : this.floats;
      const words = Array.from(view.subarray(at, at + count));
      let leaf;
      if (m.type.startsWith('mat')) {
        const n = Math.sqrt(count);
        leaf = Array.from({ length: n }, (_, c) => words.slice(c * n, c * n + n));
      } else {
        leaf = m.type.startsWith('vec') ? words : words[0];
      }
      // `groups[1].min_height` → root.groups[1].min_height
      const keys = m.member.split('.').flatMap((p) => p.split(/\[|\]/).filter((k) => k !== ''));
      let node = root;
      keys.forEach((key, i) => {
        const last = i === keys.length - 1;
        const nextIsIndex = !last && /^\d+$/.test(keys[i + 1]);
        if (last) node[key] = leaf;
        else node = node[key] ??= nextIsIndex ? [] : {};
      });
    }
    return root;
  }

  word(path) {
    const w = this.offsets.get(path);
    if (w === undefined) throw new Error(`the uniform block has no member ${path}`);
    return w;
  }

  setFloats(path, values) {
    this.floats.set(values, this.word(path));
  }

  setUint(path, value) {
    this.uints[this.word(path)] = value >>> 0;
  }

  float(path) {
    return this.floats[this.word(path)];
  }

  uint(path) {
    return this.uints[this.word(path)];
  }

  /** `n` floats from member `path` on, as an array. */
  vector(path, n) {
    const at = this.word(path);
    return Array.from(this.floats.subarray(at, at + n));
  }
}

/** The inverse of a 4×4 matrix given column by column (16 numbers). */
export function invert(m) {
  const [a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23, a30, a31, a32, a33] = m;
  const b00 = a00 * a11 - a01 * a10;
  const b01 = a00 * a12 - a02 * a10;
  const b02 = a00 * a13 - a03 * a10;
  const b03 = a01 * a12 - a02 * a11;
  const b04 = a01 * a13 - a03 * a11;
  const b05 = a02 * a13 - a03 * a12;
  const b06 = a20 * a31 - a21 * a30;
  const b07 = a20 * a32 - a22 * a30;
  const b08 = a20 * a33 - a23 * a30;
  const b09 = a21 * a32 - a22 * a31;
  const b10 = a21 * a33 - a23 * a31;
  const b11 = a22 * a33 - a23 * a32;
  const det = b00 * b11 - b01 * b10 + b02 * b09 + b03 * b08 - b04 * b07 + b05 * b06;
  if (!det) throw new Error('the view-projection matrix cannot be inverted');
  const d = 1 / det;
  return [
    (a11 * b11 - a12 * b10 + a13 * b09) * d, (a02 * b10 - a01 * b11 - a03 * b09) * d,
    (a31 * b05 - a32 * b04 + a33 * b03) * d, (a22 * b04 - a21 * b05 - a23 * b03) * d,
    (a12 * b08 - a10 * b11 - a13 * b07) * d, (a00 * b11 - a02 * b08 + a03 * b07) * d,
    (a32 * b02 - a30 * b05 - a33 * b01) * d, (a20 * b05 - a22 * b02 + a23 * b01) * d,
    (a10 * b10 - a11 * b08 + a13 * b06) * d, (a01 * b08 - a00 * b10 - a03 * b06) * d,
    (a30 * b04 - a31 * b02 + a33 * b00) * d, (a21 * b02 - a20 * b04 - a23 * b00) * d,
    (a11 * b07 - a10 * b09 - a12 * b06) * d, (a00 * b09 - a01 * b07 + a02 * b06) * d,
    (a31 * b01 - a30 * b03 - a32 * b00) * d, (a20 * b03 - a21 * b01 + a22 * b00) * d,
  ];
}

/**
 * The bytes of a texture file (`bytes`, RGBA8) as the half floats a host uploads (a
 * Uint16Array of binary16 bits), each byte through the package's `texel_halves` table: Nimbus's
 * runtime holds its textures so, because a GPU that filters an 8-bit texture in 8-bit
 * arithmetic rounds the filtered value and the coverage threshold keeps the rounding as a halo.
 */
export function widenTexels(bytes, texelHalves) {
  if (!texelHalves || texelHalves.length !== 256) {
    throw new Error('nimbus-package.json: texel_halves must hold 256 half floats (one per byte value)');
  }
  const table = Uint16Array.from(texelHalves);
  const halves = new Uint16Array(bytes.length);
  for (let i = 0; i < bytes.length; i += 1) halves[i] = table[bytes[i]];
  return halves;
}

/**
 * Fetches the package description at `base` for `engine`, its pair (`options.pair`, or the
 * first) and the pair's uniform blocks. `get(path, 'json' | 'text' | 'bytes')` fetches any
 * other file of the package.
 */
export async function loadPackage(base, engine, options = {}) {
  const url = (path) => new URL(path, base).href;
  const get = async (path, as = 'text') => {
    const r = await fetch(url(path));
    if (!r.ok) throw new Error(`${url(path)}: ${r.status}`);
    if (as === 'json') return r.json();
    if (as === 'bytes') return new Uint8Array(await r.arrayBuffer());
    if (as === 'blob') return r.blob();
    return r.text();
  };
  const pkg = await get('nimbus-package.json', 'json');
  if (pkg.engine !== engine) throw new Error(`this package is for ${pkg.engine}, not ${engine}`);
  const pair = options.pair ? pkg.pairs.find((p) => p.pair === options.pair) : pkg.pairs[0];
  if (!pair) {
    throw new Error(`no pair ${options.pair}; the package has ${pkg.pairs.map((p) => p.pair).join(', ')}`);
  }
  const blocks = {
    pair: new Block(await get(pair.uniforms, 'json')),
    resolve: new Block(await get('uniforms/resolve.json', 'json')),
    display: new Block(await get('uniforms/display.json', 'json')),
  };
  // A pair built with `--enable scene-depth` reads the engine's depth buffer and its encoding
  // (the camera's projection).
  if (pair.passes.some((p) => p.bindings.some((b) => b.holds.id === 'scene'))) {
    blocks.scene = new Block(await get('uniforms/scene.json', 'json'));
  }
  return { pkg, pair, blocks, url, get };
}

const same = (a, b) => a.length === b.length && a.every((v, i) => Object.is(v, b[i]));

/**
 * The word indices of `block` outside the members `ignores` names (each a dotted path, with
 * everything under it): what a path's bake depends on.
 */
function wordsOutside(block, ignores) {
  const ignored = (path) =>
    ignores.some((m) => path === m || path.startsWith(`${m}.`) || path.startsWith(`${m}[`));
  return block.members
    .filter((m) => !ignored(m.member))
    .flatMap((m) => Array.from({ length: m.value.length }, (_, i) => m.offset / 4 + i));
}

/**
 * The draw of one frame's band (`band_redraw`) of tiles `width` × `height`: its rows into the
 * back target, and with the tile's last band the tile copied into the target the clouds read.
 */
function bandPlan(step, width, height) {
  return {
    rects: step.height ? [[step.x, step.y + step.top, width, step.height]] : [],
    back: step.height > 0,
    copy: step.last ? [step.x, step.y, width, height] : null,
  };
}

/**
 * What a host of one package pair keeps between frames and writes into its blocks: no
 * graphics API. Engine hosts extend it with their passes, targets and textures.
 */
export class NimbusHost {
  constructor(pkg, pair, blocks) {
    this.package = pkg;
    this.pair = pair;
    this.blocks = blocks;
    this.frame = 0;
    this.width = 0;
    this.height = 0;
    this.lowWidth = 1;
    this.lowHeight = 1;
    this.upscaleOn = false;
    this.accumulateOn = false;
    this.seed = 0;
    this.shadowDirty = true;
    // Cascades in rotation (`shadowTiles`): with a sun, camera or wind that moves every frame,
    // the shadow atlas's out-of-date tiles are redrawn one after another, each in bands of rows
    // over several frames, each tile read through the transform it was drawn with, and the
    // air table in bands likewise (`airBands`); off, every tile is redrawn whenever anything
    // it shows moved, and the whole table.
    this.cascadeRotation = true;
    // The tiles as drawn, relative to the clouds' anchor (null: none drawn yet), where the
    // redraw in rotation stands (`band_redraw`), and the tiles of the sun as it is now.
    this.tiles = null;
    this.redraw = { stale: 0, tile: 0, band: 0, next: 0 };
    this.shadowAhead = false;
    // The blocks the shadow and air passes draw from (`passBlocks`, by pass): the pair block
    // as it was when the tile in progress began (its bands all drawn from it), or as it is
    // for a whole redraw; for the shadow tile, with the sun's lookup and the clouds' anchor of
    // that moment, which the tile keeps once done.
    const copy = () => {
      const bytes = new Uint8Array(blocks.pair.bytes.length);
      return { bytes, floats: new Float32Array(bytes.buffer) };
    };
    this.passBlocks = { shadow: copy(), air: copy() };
    this.banded = null;
    const columns = (v) => [0, 4, 8, 12].map((i) => v.slice(i, i + 4));
    this.currentTiles = {
      u: columns(blocks.pair.vector('shadow.lookup.u', 16)),
      v: columns(blocks.pair.vector('shadow.lookup.v', 16)),
    };
    // The air table follows the sun and the camera's altitude (`airBands`): drawn whole
    // first, then with `cascadeRotation` in bands as a shadow tile is.
    this.airDirty = true;
    this.airRedraw = { stale: 0, tile: 0, band: 0, next: 0 };
    this.airDrawn = false;
    // The bake (pairs of a baked path: slices, impostor, mesh, blob2d) follows every member of the block but
    // those the package says it ignores: the words it depends on, and those it was last drawn
    // from.
    this.bakeWords = pair.cloud_bake ? wordsOutside(blocks.pair, pair.cloud_bake.ignores) : null;
    this.bakeDrawn = null;
    // Seconds since the timeline's start, and its wind and weather states (none: still air,
    // the package's coverage).
    this.time = 0;
    this.timeline = new NimbusTimeline(blocks.pair.float('media.coverage'));
    // The camera's view-projection without translation (16 numbers, column by column), and
    // the last frame's, for the resolve's reprojection.
    this.viewProjection = Array.from({ length: 16 }, (_, i) => (i % 5 === 0 ? 1 : 0));
    this.previousViewProjection = null;
    this.previousDrift = null;
    this.readsDepth = Boolean(blocks.scene);
    this.cameraFar = 1e6;
    this.reversedDepth = false;
  }

  /**
   * Shade one pixel in sixteen per frame and rebuild the rest from the history. Changing it
   * restarts the history (and resizes the targets once sized).
   */
  get upscale() {
    return this.upscaleOn;
  }

  set upscale(on) {
    this.upscaleOn = Boolean(on);
    if (this.width) this.setSize(this.width, this.height);
  }

  /** Average full-resolution frames while the camera holds still; restarts the history. */
  get accumulate() {
    return this.accumulateOn;
  }

  set accumulate(on) {
    this.accumulateOn = Boolean(on);
    if (this.width) this.setSize(this.width, this.height);
  }

  /** Whether frames are resolved from a history (upscaled or accumulated). */
  get temporal() {
    return this.upscale || this.accumulate;
  }

  /**
   * The output size in pixels. With `upscale` set, the cloud pass shades one pixel in sixteen
   * per frame and the resolve pass rebuilds the rest from the history; with `accumulate`,
   * full-resolution frames are averaged. Both restart the history, as a new size does.
   */
  setSize(width, height) {
    this.width = width;
    this.height = height;
    for (const block of [this.blocks.pair, this.blocks.display, this.blocks.resolve]) {
      block.setFloats('resolution', [width, height]);
    }
    // The cloud pass's target: the size the resolve reads it at, as the frame sequence gives it.
    const [w, h] = resolve_frame(0, this.upscale ? 1 : 0, 0, [0, 0, 0, 0], [0, 0, 0, 0], 0, [width, height]).low_resolution;
    this.lowWidth = w;
    this.lowHeight = h;
    this.frame = 0;
  }

  /**
   * Where the clouds are seen from (y up, metres; x east, −z north): `viewProjection`, the
   * camera's projection × its view without translation (16 numbers, column by column);
   * `position`, its place in the world (y is its altitude above the ground). With scene depth,
   * `projection` (16 numbers), `forward` (a unit vector), `far` and `reversed` say how the
   * engine's depth buffer encodes distance. A new altitude relights the sky there.
   */
  setView({ viewProjection, position, projection, forward, far = 1e6, reversed = false }) {
    this.viewProjection = Array.from(viewProjection);
    const u = this.blocks.pair;
    u.setFloats('inverse_view_projection', invert(this.viewProjection));
    if (this.blocks.scene && projection) {
      const sc = this.blocks.scene;
      const e = projection;
      sc.setFloats('view_projection', this.viewProjection);
      sc.setFloats('forward', forward);
      sc.setFloats('projection_zw', [e[10], e[14], e[11], e[15]]);
      this.cameraFar = far;
      this.reversedDepth = reversed;
    }
    const altitude = Math.max(position[1], 0);
    const offset = [position[0], 0, position[2]];
    const moved = !Object.is(Math.fround(altitude), u.float('camera_altitude'))
      || !same(offset.map(Math.fround), u.vector('camera_offset', 3));
    if (moved) {
      u.setFloats('camera_altitude', [altitude]);
      u.setFloats('camera_offset', offset);
      // The sun's and sky's light at the camera and the cascades around it follow.
      this.relight();
    }
  }

  /**
   * Moves the sun: `elevation` above the horizon and `azimuth` clockwise from north (−z), in
   * degrees, as Nimbus's scenes give them. The sun's and sky's irradiance and the shadow
   * cascades follow, from the JavaScript twin of Nimbus's own `sun_light`; the shadow atlas is
   * redrawn on the next frame.
   */
  setSun(elevation, azimuth) {
    this.blocks.pair.setFloats('light.sun_direction', sun_direction(elevation, azimuth));
    this.relight();
  }

  /** The sun's direction (unit, x east, y up, z south): where a scene's own sun light goes. */
  get sunDirection() {
    return this.blocks.pair.vector('light.sun_direction', 3);
  }

  /** Recomputes what the sun decides for the block as it stands (sun, camera altitude). */
  relight() {
    const u = this.blocks.pair;
    const light = sun_light(u.toObject(), this.sunDirection);
    u.setFloats('light.sun_direction', light.sun_direction);
    u.setFloats('light.sun_irradiance', light.sun_irradiance);
    u.setFloats('light.sky_irradiance', light.sky_irradiance);
    u.setFloats('shadow.inverse_matrix', light.shadow_inverse_matrix.flat());
    this.currentTiles = light.shadow_lookup;
    this.shadowDirty = true;
    this.airDirty = true;
  }

  /**
   * Whether the bake must be redrawn this frame (pairs of a baked path): a block
   * member it depends on changed since it was drawn. Marks it drawn.
   */
  bakeOutOfDate() {
    if (!this.bakeWords) return false;
    const words = this.blocks.pair.uints;
    const now = this.bakeWords.map((w) => words[w]);
    if (this.bakeDrawn && same(now, this.bakeDrawn)) return false;
    this.bakeDrawn = now;
    return true;
  }

  /**
   * What the shadow pass draws this frame, with the block's `shadow.lookup` written for the
   * tiles as they will be read: call it before the blocks are uploaded. Returns `rects`, the
   * rectangles `[x, y, width, height]` to draw the shadow pass over (atlas texels, its
   * frag-coord space: WebGPU's from the top, WebGL's from the bottom, as the pass reads them),
   * each alone, from `passBlocks.shadow`; into the back atlas when `back`, and then, when `copy` is
   * a rectangle, that rectangle copied from the back atlas into the atlas the clouds read.
   *
   * `shadowDirty` makes every tile out of date. A tile redrawn takes the sun's transform as it
   * was when its drawing began, kept relative to the clouds' anchor (`redrawn_tiles`); the
   * others are read where their clouds are now (`anchored_tiles`), however the camera or the
   * wind moved since they were drawn. With `cascadeRotation`, once every tile has been drawn,
   * the out-of-date tiles are redrawn in turn, each in bands of rows over several frames
   * (`band_redraw`: a bounded share of the atlas a frame, whatever the preset), into a back
   * atlas, from a copy of the block taken at its first band, and copied into the atlas the
   * clouds read with its last: a sun that moves every frame costs a band a frame rather than
   * the whole atlas, and no frame reads a tile half drawn. Without it, every tile is redrawn
   * at once whenever one is out of date.
   */
  shadowTiles() {
    const u = this.blocks.pair;
    const block = this.passBlocks.shadow.bytes;
    const count = u.uint('shadow.cascade_count');
    const side = u.float('shadow.map_size');
    if (this.shadowDirty) {
      this.redraw = tiles_out_of_date(this.redraw, count);
      this.shadowDirty = false;
    }
    const anchor = shadow_anchor(u.vector('camera_offset', 3), u.float('camera_altitude'), u.vector('media.wind_drift', 2));
    let plan = { rects: [], back: false, copy: null };
    if (this.shadowAhead) {
      // Planned already this frame (`renderSceneShadow` before `render`): one band a frame,
      // the lookup written again below for the camera as it is now.
      this.shadowAhead = false;
    } else if (!this.cascadeRotation || !this.tiles) {
      // Out of date, or left half drawn by a rotation since switched off.
      if (this.redraw.stale !== 0 || this.redraw.band !== 0) {
        // The whole atlas in one draw (its empty corner draws nothing), every tile for the
        // sun as it is, around the camera; a tile in progress is dropped.
        this.tiles = redrawn_tiles(this.currentTiles, this.currentTiles, anchor, [1, 1, 1, 1]);
        this.redraw = { stale: 0, tile: 0, band: 0, next: 0 };
        plan.rects.push([0, 0, side * atlas_columns(count), side * atlas_rows(count)]);
      }
    } else {
      const step = band_redraw(this.redraw, count, side, side);
      this.redraw = step.state;
      if (step.first) {
        block.set(u.bytes);
        this.banded = { current: this.currentTiles, anchor };
      }
      plan = bandPlan(step, side, side);
      if (step.last) {
        // Lanes past the cascade count hold no tile: they follow the sun, as a whole
        // redraw's do.
        const mask = [0, 1, 2, 3].map((k) => (k >= count || k === step.tile ? 1 : 0));
        this.tiles = redrawn_tiles(this.tiles, this.banded.current, this.banded.anchor, mask);
      }
    }
    const lookup = anchored_tiles(this.tiles ?? this.currentTiles, anchor);
    u.setFloats('shadow.lookup.u', lookup.u.flat());
    u.setFloats('shadow.lookup.v', lookup.v.flat());
    if (plan.rects.length && !plan.back) block.set(u.bytes);
    return plan;
  }

  /**
   * What the air pass draws this frame, as `shadowTiles` gives it for the shadow pass (drawn
   * from `passBlocks.air`): the whole table the first time and whenever it is out of date
   * without `cascadeRotation`; with it, in bands (`band_redraw`, one tile) into the back
   * table, from a copy of the block taken at the first band, the whole table copied in with
   * the last. `airDirty` makes it out of date.
   */
  airBands() {
    const u = this.blocks.pair;
    const block = this.passBlocks.air.bytes;
    const { width, height } = this.pair.air_table;
    if (this.airDirty) {
      this.airRedraw = tiles_out_of_date(this.airRedraw, 1);
      this.airDirty = false;
    }
    if (!this.cascadeRotation || !this.airDrawn) {
      // Out of date, or left half drawn by a rotation since switched off.
      if (!this.airRedraw.stale && !this.airRedraw.band) return { rects: [], back: false, copy: null };
      this.airRedraw = { stale: 0, tile: 0, band: 0, next: 0 };
      this.airDrawn = true;
      block.set(u.bytes);
      // A bake reads the table too: a new one bakes it again.
      this.bakeDrawn = null;
      return { rects: [[0, 0, width, height]], back: false, copy: null };
    }
    const step = band_redraw(this.airRedraw, 1, width, height);
    this.airRedraw = step.state;
    if (step.first) block.set(u.bytes);
    // The table copied in reaches the passes frames after the block's sun moved: a bake
    // that reads it is baked again.
    if (step.last) this.bakeDrawn = null;
    return bandPlan(step, width, height);
  }

  /**
   * `shadowTiles` for a pass drawn before the frame's `render` (the scene's shadow): the
   * frame's band is drawn then, and `render`'s own call draws none.
   */
  shadowTilesAhead() {
    this.shadowAhead = false;
    const plan = this.shadowTiles();
    this.shadowAhead = true;
    return plan;
  }

  /**
   * The wind, as a scene's `[wind]` gives it: `speed` in m/s near the ground and `directionDeg`,
   * where it blows from, in degrees clockwise from north (270: a westerly, blowing east);
   * `topSpeed` and `topDirectionDeg` at 10 km (the ground's by default), linear in altitude
   * between. The clouds drift with it as `setTime` moves the clock.
   */
  setWind(speed, directionDeg, topSpeed = speed, topDirectionDeg = directionDeg) {
    this.timeline.setWind(speed, directionDeg, topSpeed, topDirectionDeg);
    this.setTime(this.time);
  }

  /**
   * A weather state, as a scene's `[[weather]]` within this pair's genus: by `at` seconds (on
   * `setTime`'s clock) the coverage has become `coverage` (0..1), ramping smoothly (smoothstep,
   * as Nimbus's timeline) from the state before it — from that state's time (second 0 and the
   * package's coverage for the first), or over the last `over` seconds before `at` when `over`
   * is given. Without `at` the state is reached `over` seconds after the current time (at once
   * without `over`). Only `media.coverage` changes; the shadow atlas is redrawn.
   */
  setWeather(coverage, { at, over } = {}) {
    this.timeline.setWeather(coverage, { at, over, now: this.time });
    this.setTime(this.time);
  }

  /** Forgets every weather state: the package's coverage holds again. */
  clearWeather() {
    this.timeline.clearWeather();
    this.setTime(this.time);
  }

  /**
   * Moves the clock to `seconds` since the timeline's start (as `nimbus render --time`): sets
   * `media.wind_drift` and `media.wind_shear_drift` from the wind and `media.coverage` from the
   * weather states. The shadow atlas is redrawn on the next frame when any of them changed.
   */
  setTime(seconds) {
    if (!Number.isFinite(seconds)) throw new Error(`setTime: seconds must be a finite number, got ${seconds}`);
    this.time = seconds;
    const at = this.timeline.at(seconds);
    const u = this.blocks.pair;
    const before = this.drift().concat(u.float('media.coverage'));
    u.setFloats('media.wind_drift', at.wind_drift);
    u.setFloats('media.wind_shear_drift', at.wind_shear_drift);
    u.setFloats('media.coverage', [at.coverage]);
    // The shadow atlas holds the clouds where they were: redraw it when they moved or changed.
    if (!same(this.drift().concat(u.float('media.coverage')), before)) this.shadowDirty = true;
  }

  /** The clouds' drift as the frame sequence packs it: ground x, z; per metre of altitude. */
  drift() {
    const u = this.blocks.pair;
    return u.vector('media.wind_drift', 2).concat(u.vector('media.wind_shear_drift', 2));
  }

  /** Linear radiance is scaled by this before the tone curve (8 in `nimbus render`). */
  set exposure(value) {
    this.blocks.display.setFloats('exposure', [value]);
  }

  get exposure() {
    return this.blocks.display.float('exposure');
  }

  /**
   * How the engine's depth texture of `width` × `height` texels encodes distance: a projection's
   * depth in the API's range (`depthScale`, `depthOffset`: NDC z = depth × scale + offset; 2
   * and −1 in WebGL, 1 and 0 in WebGPU), or three's logarithmic buffer; `flipY` where its first
   * row is the bottom one.
   */
  setDepthEncoding({ logarithmic = false, depthScale, depthOffset, width, height, flipY }) {
    const sc = this.blocks.scene;
    sc.setUint('encoding', logarithmic ? 1 : 0);
    sc.setFloats('log_range', [Math.log2(this.cameraFar + 1)]);
    sc.setFloats('depth_scale', [this.reversedDepth ? 1 : depthScale]);
    sc.setFloats('depth_offset', [this.reversedDepth ? 0 : depthOffset]);
    sc.setFloats('clear_depth', [this.reversedDepth ? 0 : 1]);
    sc.setFloats('resolution', [width, height]);
    sc.setFloats('flip_y', [flipY ? 1 : 0]);
  }

  /**
   * Starts a frame: the frame sequence's members of the cloud block. Frames are counted since
   * the history started; a frame nothing resolves is always frame 0 (the same picture for the
   * same inputs, as `nimbus render` draws it). Returns the frame's index.
   */
  beginFrame() {
    if (!this.width) throw new Error('call setSize before render');
    if (this.temporal && this.pair.camera === 'orthographic') {
      // The resolve reprojects rays from one point, which parallel rays are not.
      throw new Error(`render: the pair ${this.pair.pair} has an orthographic camera, drawn one frame at a time: set upscale and accumulate off`);
    }
    const index = this.temporal ? this.frame : 0;
    this.blocks.pair.assign(cloud_frame(index, this.seed, this.upscale ? 1 : 0));
    return index;
  }

  /**
   * The resolve block for frame `index`: reprojection from the last frame's camera, and the
   * history read where the wind had the clouds it shows (the slab's face towards the camera),
   * so drifting clouds do not smear.
   */
  resolveFrame(index) {
    const u = this.blocks.pair;
    const r = this.blocks.resolve;
    const before = index === 0 ? this.viewProjection : this.previousViewProjection;
    r.setFloats('inverse_view_projection', invert(this.viewProjection));
    r.setFloats('previous_view_projection', before);
    const altitude = facing_altitude(
      u.float('camera_altitude'), u.float('march.min_height'), u.float('march.max_height'));
    const moved = same(before, this.viewProjection) ? 0 : 1;
    const drift = this.drift();
    const previousDrift = index === 0 ? drift : this.previousDrift;
    r.assign(resolve_frame(index, this.upscale ? 1 : 0, moved, drift, previousDrift, altitude, [this.width, this.height]));
    r.setFloats('cloud_altitude', [altitude]);
    r.setFloats('camera_altitude', [u.float('camera_altitude')]);
    r.setFloats('planet_radius', [u.float('march.radius')]);
  }

  /** Ends a frame: what the next one reprojects from. */
  endFrame() {
    this.previousViewProjection = this.viewProjection.slice();
    this.previousDrift = this.drift();
    this.frame += 1;
  }
}
