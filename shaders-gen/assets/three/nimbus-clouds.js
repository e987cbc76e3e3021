// Nimbus clouds for three.js: draws a Nimbus engine package (`nimbus emit --engine three`) with
// nothing but three.js. Shipped in every three.js package; it reads nimbus-package.json for the
// passes, their shaders and bindings, the textures and the uniform layouts, so it holds no
// knowledge of a particular genus or preset.
//
//   import { NimbusClouds } from './nimbus-clouds.js';
//   const clouds = await NimbusClouds.load(new URL('./', import.meta.url));
//   clouds.setSize(width, height);
//   clouds.setCamera(camera);            // a THREE.PerspectiveCamera; y is up, metres
//   clouds.setSun(elevation, azimuth);   // degrees; lighting and shadows follow
//   clouds.render(renderer);             // to the canvas, or clouds.render(renderer, target)
//
// Clouds that change, as a scene's `[wind]` and `[[weather]]` and `nimbus render --time` do
// (only uniforms change: no new shader, no pipeline switch):
//
//   clouds.setWind(6, 260, 20, 280);     // m/s and where it blows from (degrees clockwise from
//                                        // north), near the ground and at 10 km (default: same)
//   clouds.setWeather(0.35, { at: 7200 });  // coverage reached by second 7200, a smoothstep ramp
//                                        // from the state before; { over: 600 } ramps over the
//                                        // last 600 s (from now when `at` is left out)
//   clouds.setTime(9000);                // seconds since the timeline's start: the clouds drift
//                                        // with the wind and the coverage follows its states
//
// The wind's velocity and the weather's ramp are the JavaScript twins of Nimbus's own shader
// functions (nimbus-wind.js, used through nimbus-timeline.js). In an EffectComposer, use
// `NimbusCloudsPass` from './nimbus-clouds-pass.js'.

import * as THREE from 'three';
import { cloud_frame, resolve_frame } from './nimbus-frame.js';
import { sun_direction, sun_light } from './nimbus-sun.js';
import { NimbusTimeline } from './nimbus-timeline.js';
import { facing_altitude } from './nimbus-wind.js';

/** The bytes of a hex string. */
function fromHex(hex) {
  const bytes = new Uint8Array(hex.length / 2);
  for (let i = 0; i < bytes.length; i++) bytes[i] = parseInt(hex.substr(2 * i, 2), 16);
  return bytes;
}

/** A uniform block: its bytes, with float and uint views, and member offsets by path. */
class Block {
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
}

/** GLSL as three's RawShaderMaterial takes it: three writes the #version line itself. */
function withoutVersion(source) {
  return source.replace(/^#version[^\n]*\n/, '');
}

async function loadTexture(url, t) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${response.status}`);
  let texture;
  if (t.dimension === '3d') {
    const data = new Uint8Array(await response.arrayBuffer());
    const [w, h, d] = t.size;
    if (data.length !== w * h * d * 4) throw new Error(`${url}: ${data.length} bytes, expected ${w * h * d * 4}`);
    texture = new THREE.Data3DTexture(data, w, h, d);
    texture.wrapR = THREE.RepeatWrapping;
  } else {
    // Texel values are data, not colours: no premultiplication, no colour conversion.
    const bitmap = await createImageBitmap(await response.blob(), {
      premultiplyAlpha: 'none',
      colorSpaceConversion: 'none',
      imageOrientation: 'from-image',
    });
    texture = new THREE.Texture(bitmap);
    texture.flipY = false;
  }
  texture.format = THREE.RGBAFormat;
  texture.type = THREE.UnsignedByteType;
  texture.colorSpace = THREE.NoColorSpace;
  texture.premultiplyAlpha = false;
  texture.generateMipmaps = false;
  texture.minFilter = THREE.LinearFilter;
  texture.magFilter = THREE.LinearFilter;
  texture.wrapS = THREE.RepeatWrapping;
  texture.wrapT = THREE.RepeatWrapping;
  texture.unpackAlignment = 1;
  texture.needsUpdate = true;
  return texture;
}

function hdrTarget(width, height, wrap) {
  return new THREE.WebGLRenderTarget(width, height, {
    type: THREE.HalfFloatType,
    format: THREE.RGBAFormat,
    depthBuffer: false,
    stencilBuffer: false,
    generateMipmaps: false,
    // Every pass samples these at texel centres, where linear equals nearest.
    minFilter: THREE.LinearFilter,
    magFilter: THREE.LinearFilter,
    wrapS: wrap,
    wrapT: wrap,
  });
}

/** The three.js side of one Nimbus package pair: its passes, targets, textures and uniforms. */
export class NimbusClouds {
  /**
   * Loads the package at `base` (a URL of its folder). `options.pair` picks a genus × preset
   * pair (`cumulus.high`); the first one otherwise.
   */
  static async load(base, options = {}) {
    const url = (path) => new URL(path, base).href;
    const get = async (path, as) => {
      const r = await fetch(url(path));
      if (!r.ok) throw new Error(`${url(path)}: ${r.status}`);
      return as === 'json' ? r.json() : r.text();
    };
    const pkg = await get('nimbus-package.json', 'json');
    if (pkg.engine !== 'three') throw new Error(`this package is for ${pkg.engine}, not three`);
    const pair = options.pair ? pkg.pairs.find((p) => p.pair === options.pair) : pkg.pairs[0];
    if (!pair) {
      throw new Error(`no pair ${options.pair}; the package has ${pkg.pairs.map((p) => p.pair).join(', ')}`);
    }
    const blocks = {
      pair: new Block(await get(pair.uniforms, 'json')),
      resolve: new Block(await get('uniforms/resolve.json', 'json')),
      display: new Block(await get('uniforms/display.json', 'json')),
    };
    // A pair built with `--enable scene-depth` reads the engine's depth buffer and its
    // encoding (the camera's projection).
    const readsDepth = pair.passes.some((p) => p.bindings.some((b) => b.holds.id === 'scene'));
    if (readsDepth) blocks.scene = new Block(await get('uniforms/scene.json', 'json'));
    const textures = {};
    for (const t of pkg.textures) textures[t.name] = await loadTexture(url(t.file), t);
    const sources = {};
    for (const pass of pair.passes) {
      const file = (stage) => pass.files.find((f) => f.stage === stage).file;
      sources[pass.pass] = {
        vertex: await get(file('vertex')),
        fragment: await get(file('fragment')),
      };
    }
    return new NimbusClouds(pkg, pair, blocks, textures, sources);
  }

  constructor(pkg, pair, blocks, textures, sources) {
    this.package = pkg;
    this.pair = pair;
    this.blocks = blocks;
    this.textures = textures;
    this.frame = 0;
    this.width = 0;
    this.height = 0;
    this.shadowDirty = true;
    this.shaderErrors = [];
    // Seconds since the timeline's start, and its wind and weather states (none: still air, the
    // package's coverage).
    this.time = 0;
    this.timeline = new NimbusTimeline(blocks.pair.float('media.coverage'));
    this.scene = new THREE.Scene();
    this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
    const geometry = new THREE.BufferGeometry();
    // The vertex shaders place the triangle from gl_VertexID; three needs a vertex count.
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    this.geometry = geometry;
    this.shadowTarget = pair.shadow_atlas
      ? hdrTarget(pair.shadow_atlas.width, pair.shadow_atlas.height, THREE.RepeatWrapping)
      : null;
    this.cloudTarget = hdrTarget(1, 1, THREE.ClampToEdgeWrapping);
    // Temporal upscaling and accumulation: two full-size history targets, written in turn.
    this.history = [hdrTarget(1, 1, THREE.ClampToEdgeWrapping), hdrTarget(1, 1, THREE.ClampToEdgeWrapping)];
    this.latest = 0;
    this.upscale = false;
    this.accumulate = false;
    this.seed = 0;
    this.viewProjection = new THREE.Matrix4();
    this.previousViewProjection = null;
    // Texture uniforms that change from frame to frame (the history targets, the engine's
    // depth), by what they hold.
    this.dynamic = [];
    // Over the engine's own scene: the clouds stop at its depth and are drawn over its picture
    // (premultiplied: the display pass keeps alpha, blended over what is there).
    this.readsDepth = Boolean(blocks.scene);
    this.cameraFar = 1e6;
    this.reversedDepth = false;
    this.passes = {};
    for (const pass of pair.passes) this.passes[pass.pass] = this.makePass(pass, sources[pass.pass]);
    if (this.readsDepth) {
      // Premultiplied over the engine's picture: Nimbus's colour plus what its alpha leaves of
      // the pixel already there.
      blocks.display.setFloats('keep_alpha', [1]);
      const m = this.passes.display.material;
      m.blending = THREE.CustomBlending;
      m.blendSrc = THREE.OneFactor;
      m.blendDst = THREE.OneMinusSrcAlphaFactor;
      m.blendSrcAlpha = THREE.ZeroFactor;
      m.blendDstAlpha = THREE.OneFactor;
      // The engine's picture, drawn by three.js itself (its own tone mapping and output colour
      // space) before the clouds go over it.
      this.sceneCopy = new THREE.Mesh(
        new THREE.PlaneGeometry(2, 2),
        new THREE.MeshBasicMaterial({ depthTest: false, depthWrite: false }),
      );
      this.sceneCopy.position.z = -0.5;
      this.sceneCopy.frustumCulled = false;
    }
    // The display pass's source: the cloud target, or the history target resolve wrote.
    const display = pair.passes.find((p) => p.pass === 'display');
    this.displaySource = display.bindings
      .filter((b) => b.kind === 'texture')
      .flatMap((b) => b.in_files)
      .find((n) => n.combined_sampler).combined_sampler;
  }

  /** What a binding is bound to, by the stable id the package gives its resource. */
  resourceFor(binding) {
    const id = binding.holds.id;
    switch (id) {
      case 'pair':
      case 'resolve':
      case 'display':
        return this.blocks[id];
      case 'shadow_atlas':
        return this.shadowTarget.texture;
      case 'clouds_hdr':
      case 'shown':
        return this.cloudTarget.texture;
      case 'history_read':
        return this.history[0].texture;
      case 'scene':
        return this.blocks.scene;
      case 'scene_depth':
        return null; // the engine's depth texture, given with each frame
      default:
        return this.textures[id] ?? null;
    }
  }

  makePass(pass, source) {
    const uniforms = {};
    const groups = [];
    for (const b of pass.bindings) {
      if (b.kind === 'sampler') continue;
      const resource = this.resourceFor(b);
      for (const named of b.in_files) {
        if (b.kind === 'uniform' && named.name) {
          const group = new THREE.UniformsGroup();
          group.setName(named.name);
          // The block's bytes as they are: three writes a typed array into the buffer verbatim.
          group.add(new THREE.Uniform(resource.floats));
          group.setUsage(THREE.DynamicDrawUsage);
          groups.push(group);
        } else if (named.combined_sampler) {
          const uniform = { value: resource };
          uniforms[named.combined_sampler] = uniform;
          if (b.holds.id === 'history_read' || b.holds.id === 'scene_depth') {
            this.dynamic.push({ pass: pass.pass, uniform, holds: b.holds.id });
          }
        }
      }
    }
    const material = new THREE.RawShaderMaterial({
      name: `nimbus ${pass.pass}`,
      glslVersion: THREE.GLSL3,
      vertexShader: withoutVersion(source.vertex),
      fragmentShader: withoutVersion(source.fragment),
      uniforms,
      // The GLSL vertex shader flips y for OpenGL clip space, which turns the triangle
      // clockwise: draw both faces.
      side: THREE.DoubleSide,
      depthTest: false,
      depthWrite: false,
      blending: THREE.NoBlending,
    });
    material.uniformsGroups = groups;
    const mesh = new THREE.Mesh(this.geometry, material);
    mesh.frustumCulled = false;
    return { mesh, groups, material };
  }

  /**
   * The output size in pixels. With `upscale` set, the cloud pass shades one pixel in sixteen
   * per frame and the resolve pass rebuilds the rest from the history (16 frames shade every
   * pixel once); with `accumulate`, full-resolution frames are averaged. Both reset the
   * history, as does a new size.
   */
  setSize(width, height) {
    this.width = width;
    this.height = height;
    for (const block of [this.blocks.pair, this.blocks.display, this.blocks.resolve]) {
      block.setFloats('resolution', [width, height]);
    }
    // The cloud pass's target: the size the resolve reads it at (one pixel per 4×4 block
    // upscaled), as the frame sequence gives it.
    const [lowWidth, lowHeight] = resolve_frame(0, this.upscale ? 1 : 0, 0, [0, 0, 0, 0], [0, 0, 0, 0], 0, [width, height]).low_resolution;
    this.lowWidth = lowWidth;
    this.lowHeight = lowHeight;
    this.cloudTarget.setSize(lowWidth, lowHeight);
    for (const h of this.history) h.setSize(width, height);
    this.frame = 0;
  }

  /**
   * Where the clouds are seen from: the engine's own camera (y up, metres; x east, -z north),
   * nothing re-derived by hand. Its world position is the viewpoint: `y` its altitude above
   * the ground (flying up into a cloud layer works like any other altitude), `x` and `z` where
   * it stands over the clouds. Its rotation and projection (field of view, aspect) give each
   * pixel's ray. Moving the altitude relights the sky at the new height; moving the camera
   * over the clouds redraws the shadow atlas around it.
   */
  setCamera(camera) {
    camera.updateMatrixWorld();
    // The cloud shader takes directions: the view without its translation.
    const view = new THREE.Matrix4().extractRotation(camera.matrixWorld).invert();
    this.viewProjection.multiplyMatrices(camera.projectionMatrix, view);
    const inverse = this.viewProjection.clone().invert();
    const u = this.blocks.pair;
    u.setFloats('inverse_view_projection', inverse.elements);
    if (this.blocks.scene) {
      // The engine camera's depth encoding: its projection's z and w rows, its forward axis.
      const sc = this.blocks.scene;
      const e = camera.projectionMatrix.elements;
      sc.setFloats('view_projection', this.viewProjection.elements);
      sc.setFloats('forward', camera.getWorldDirection(new THREE.Vector3()).toArray());
      sc.setFloats('projection_zw', [e[10], e[14], e[11], e[15]]);
      this.cameraFar = camera.far;
      this.reversedDepth = Boolean(camera.reversedDepth);
    }
    const position = new THREE.Vector3().setFromMatrixPosition(camera.matrixWorld);
    const altitude = Math.max(position.y, 0);
    const offset = [position.x, 0, position.z];
    const at = u.word('camera_offset');
    const moved = !Object.is(Math.fround(altitude), u.float('camera_altitude'))
      || offset.some((v, i) => !Object.is(Math.fround(v), u.floats[at + i]));
    if (moved) {
      u.setFloats('camera_altitude', [altitude]);
      u.setFloats('camera_offset', offset);
      // The sun's and sky's light at the camera and the cascades around it follow.
      this.relight();
    }
  }

  /**
   * Moves the sun: `elevation` above the horizon and `azimuth` clockwise from north (-z), in
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
    const u = this.blocks.pair;
    return Array.from(u.floats.subarray(u.word('light.sun_direction'), u.word('light.sun_direction') + 3));
  }

  /** Recomputes what the sun decides for the block as it stands (sun, camera altitude). */
  relight() {
    const u = this.blocks.pair;
    const light = sun_light(u.toObject(), this.sunDirection);
    u.setFloats('light.sun_direction', light.sun_direction);
    u.setFloats('light.sun_irradiance', light.sun_irradiance);
    u.setFloats('light.sky_irradiance', light.sky_irradiance);
    u.setFloats('shadow.matrix', light.shadow_matrix.flat());
    u.setFloats('shadow.inverse_matrix', light.shadow_inverse_matrix.flat());
    this.shadowDirty = true;
  }

  /**
   * The wind, as a scene's `[wind]` gives it: `speed` in m/s near the ground and `directionDeg`,
   * where it blows from, in degrees clockwise from north (270: a westerly, blowing east);
   * `topSpeed` and `topDirectionDeg` at 10 km (the ground's by default), linear in altitude
   * between. The clouds drift with it as `setTime` moves the clock (the drift is redone at the
   * current time now).
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
    const members = [['media.wind_drift', 2], ['media.wind_shear_drift', 2], ['media.coverage', 1]];
    const words = () => members.flatMap(([m, n]) => Array.from(u.floats.subarray(u.word(m), u.word(m) + n)));
    const before = words();
    u.setFloats('media.wind_drift', at.wind_drift);
    u.setFloats('media.wind_shear_drift', at.wind_shear_drift);
    u.setFloats('media.coverage', [at.coverage]);
    // The shadow atlas holds the clouds where they were: redraw it when they moved or changed.
    if (words().some((v, i) => !Object.is(v, before[i]))) this.shadowDirty = true;
  }

  /** Linear radiance is scaled by this before the tone curve (8 in `nimbus render`). */
  set exposure(value) {
    this.blocks.display.setFloats('exposure', [value]);
  }

  get exposure() {
    return this.blocks.display.float('exposure');
  }

  draw(renderer, pass, target) {
    for (const g of pass.groups) g.uniforms[0].needsUpdate = true;
    this.scene.children.length = 0;
    this.scene.add(pass.mesh);
    renderer.setRenderTarget(target);
    renderer.render(this.scene, this.camera);
  }

  /**
   * Draws one frame into `target` (a WebGLRenderTarget), or the canvas when it is null.
   *
   * A package built with `--enable scene-depth` draws the clouds into the engine's own scene:
   * `options.scene` is the render target the scene was drawn into (with a `depthTexture`):
   * its picture is drawn first, then the clouds over it, stopped by its depth. Or give
   * `options.depth` (a DepthTexture) alone and the clouds are drawn over what `target` holds.
   */
  render(renderer, target = null, options = {}) {
    if (!this.width) throw new Error('call setSize before render');
    const depth = options.depth ?? options.scene?.depthTexture ?? null;
    if (this.readsDepth) {
      if (!depth) {
        throw new Error(
          `render: the pair ${this.pair.pair} reads the engine's depth (built with --enable scene-depth): ` +
            'pass { scene: aRenderTargetWithADepthTexture } or { depth: aDepthTexture }',
        );
      }
      const sc = this.blocks.scene;
      const logarithmic = Boolean(renderer.capabilities?.logarithmicDepthBuffer);
      sc.setUint('encoding', logarithmic ? 1 : 0);
      sc.setFloats('log_range', [Math.log2(this.cameraFar + 1)]);
      // WebGL's depth range: NDC z in [-1, 1], unless reversed (glClipControl, [0, 1]).
      sc.setFloats('depth_scale', [this.reversedDepth ? 1 : 2]);
      sc.setFloats('depth_offset', [this.reversedDepth ? 0 : -1]);
      sc.setFloats('clear_depth', [this.reversedDepth ? 0 : 1]);
      sc.setFloats('resolution', [depth.image.width, depth.image.height]);
      sc.setFloats('flip_y', [1]);
      for (const d of this.dynamic) if (d.holds === 'scene_depth') d.uniform.value = depth;
    } else if (depth) {
      throw new Error(`render: the pair ${this.pair.pair} was built without --enable scene-depth; it cannot read a depth buffer`);
    }
    const temporal = this.upscale || this.accumulate;
    // Frames counted since the history started; a frame nothing resolves is always frame 0
    // (the same picture for the same inputs, as `nimbus render` draws it).
    const index = temporal ? this.frame : 0;
    const upscale = this.upscale ? 1 : 0;
    const u = this.blocks.pair;
    // What the frame sequence writes into the cloud block: the twin of the runtime's own.
    u.assign(cloud_frame(index, this.seed, upscale));
    const previous = renderer.getRenderTarget();
    if (this.passes.shadow && this.shadowDirty) {
      this.draw(renderer, this.passes.shadow, this.shadowTarget);
      this.shadowDirty = false;
    }
    this.draw(renderer, this.passes.clouds, this.cloudTarget);
    let shown = this.cloudTarget;
    const drift = [...u.floats.subarray(u.word('media.wind_drift'), u.word('media.wind_drift') + 2),
      ...u.floats.subarray(u.word('media.wind_shear_drift'), u.word('media.wind_shear_drift') + 2)];
    if (temporal) {
      const read = this.latest;
      const write = 1 - read;
      const r = this.blocks.resolve;
      const before = index === 0 ? this.viewProjection : this.previousViewProjection;
      const inverse = this.viewProjection.clone().invert();
      r.setFloats('inverse_view_projection', inverse.elements);
      r.setFloats('previous_view_projection', before.elements);
      // The history is read where the wind had the clouds it shows (the slab's face towards
      // the camera), so drifting clouds do not smear.
      const altitude = facing_altitude(
        u.float('camera_altitude'), u.float('march.min_height'), u.float('march.max_height'));
      const moved = before.equals(this.viewProjection) ? 0 : 1;
      const previousDrift = index === 0 ? drift : this.previousDrift;
      r.assign(resolve_frame(index, upscale, moved, drift, previousDrift, altitude, [this.width, this.height]));
      r.setFloats('cloud_altitude', [altitude]);
      r.setFloats('camera_altitude', [u.float('camera_altitude')]);
      r.setFloats('planet_radius', [u.float('march.radius')]);
      for (const d of this.dynamic) {
        if (d.holds === 'history_read') d.uniform.value = this.history[read].texture;
      }
      this.draw(renderer, this.passes.resolve, this.history[write]);
      this.latest = write;
      shown = this.history[write];
    }
    this.passes.display.mesh.material.uniforms[this.displaySource].value = shown.texture;
    if (options.scene && this.sceneCopy) {
      const material = this.sceneCopy.material;
      if (material.map !== options.scene.texture) {
        material.map = options.scene.texture;
        material.needsUpdate = true;
      }
      this.scene.children.length = 0;
      this.scene.add(this.sceneCopy);
      renderer.setRenderTarget(target);
      renderer.render(this.scene, this.camera);
    }
    // Over the engine's picture, the clouds are blended onto it: nothing is cleared.
    const autoClear = renderer.autoClear;
    if (this.readsDepth) renderer.autoClear = false;
    this.draw(renderer, this.passes.display, target);
    renderer.autoClear = autoClear;
    renderer.setRenderTarget(previous);
    this.previousViewProjection = this.viewProjection.clone();
    this.previousDrift = drift;
    this.frame += 1;
  }

  dispose() {
    this.geometry.dispose();
    if (this.sceneCopy) {
      this.sceneCopy.geometry.dispose();
      this.sceneCopy.material.dispose();
    }
    this.cloudTarget.dispose();
    for (const h of this.history) h.dispose();
    if (this.shadowTarget) this.shadowTarget.dispose();
    for (const p of Object.values(this.passes)) p.material.dispose();
    for (const t of Object.values(this.textures)) t.dispose();
  }
}
