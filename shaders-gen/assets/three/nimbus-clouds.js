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
//
// In the engine's own scene (a package built with --enable scene-depth; see tower.html): draw
// the scene's depth, `clouds.renderSceneShadow(renderer, { scene })` for the clouds' shadow on
// its objects (materials made with `clouds.shadowMaterial(material)` take it), the scene, then
// `clouds.render(renderer, null, { scene })` over it.

import * as THREE from 'three';
import { NimbusHost, loadPackage, widenTexels } from './nimbus-host.js';

/** GLSL as three's RawShaderMaterial takes it: three writes the #version line itself. */
function withoutVersion(source) {
  return source.replace(/^#version[^\n]*\n/, '');
}

/**
 * One noise texture, as half floats (`t.format`: R16F, or RGBA16F): 3D files widened through
 * the package's `texel_halves`, 2D images converted by WebGL's upload (each byte k to k/255).
 */
async function loadTexture(url, t, texelHalves) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${response.status}`);
  const channels = t.format === 'r16float' ? 1 : 4;
  let texture;
  if (t.dimension === '3d') {
    const data = new Uint8Array(await response.arrayBuffer());
    const [w, h, d] = t.size;
    const expected = w * h * d * channels;
    if (data.length !== expected) throw new Error(`${url}: ${data.length} bytes, expected ${expected}`);
    texture = new THREE.Data3DTexture(widenTexels(data, texelHalves), w, h, d);
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
  texture.format = channels === 1 ? THREE.RedFormat : THREE.RGBAFormat;
  texture.type = THREE.HalfFloatType;
  texture.internalFormat = channels === 1 ? 'R16F' : 'RGBA16F';
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
export class NimbusClouds extends NimbusHost {
  /**
   * Loads the package at `base` (a URL of its folder). `options.pair` picks a genus × preset
   * pair (`cumulus.high`); the first one otherwise.
   */
  static async load(base, options = {}) {
    const { pkg, pair, blocks, url, get } = await loadPackage(base, 'three', options);
    const textures = {};
    for (const t of pkg.textures) textures[t.name] = await loadTexture(url(t.file), t, pkg.texel_halves);
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
    super(pkg, pair, blocks);
    this.textures = textures;
    this.scene = new THREE.Scene();
    this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
    const geometry = new THREE.BufferGeometry();
    // The vertex shaders place the triangle from gl_VertexID; three needs a vertex count.
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    this.geometry = geometry;
    this.shadowTarget = pair.shadow_atlas
      ? hdrTarget(pair.shadow_atlas.width, pair.shadow_atlas.height, THREE.RepeatWrapping)
      : null;
    // Drawn in bands (cascades in rotation), a shadow tile or the air table is drawn into a
    // back target of the same size, made with the first band, then copied in (`drawPlan`).
    this.backs = {};
    this.airTarget = pair.air_table
      ? hdrTarget(pair.air_table.width, pair.air_table.height, THREE.RepeatWrapping)
      : null;
    this.bakeTarget = pair.cloud_bake
      ? hdrTarget(pair.cloud_bake.width, pair.cloud_bake.height, THREE.RepeatWrapping)
      : null;
    this.cloudTarget = hdrTarget(1, 1, THREE.ClampToEdgeWrapping);
    // The clouds' shadow on the engine's objects, one texel per pixel of its depth buffer.
    this.sceneShadowTarget = pair.passes.some((p) => p.pass === 'scene_shadow')
      ? hdrTarget(1, 1, THREE.ClampToEdgeWrapping)
      : null;
    // Temporal upscaling and accumulation: two full-size history targets, written in turn.
    this.history = [hdrTarget(1, 1, THREE.ClampToEdgeWrapping), hdrTarget(1, 1, THREE.ClampToEdgeWrapping)];
    this.latest = 0;
    // Texture uniforms that change from frame to frame (the history targets, the engine's
    // depth), by what they hold.
    this.dynamic = [];
    this.passes = {};
    for (const pass of pair.passes) this.passes[pass.pass] = this.makePass(pass, sources[pass.pass]);
    if (this.readsDepth) {
      // Over the engine's own scene the clouds stop at its depth and are drawn over its
      // picture, premultiplied: Nimbus's colour plus what its alpha leaves of the pixel there.
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

  /**
   * What a binding is bound to: the package names the resource (`holds.id`) and how a host
   * provides it (`holds.kind`, one of the package's resource kinds); the uniform blocks, the
   * textures and the targets are each kept by that id.
   */
  resourceFor(binding) {
    const { id, kind } = binding.holds;
    switch (kind) {
      case 'uniform block':
        return this.blocks[id] ?? null;
      case 'texture':
        return this.textures[id] ?? null;
      case 'target':
        return this.targets()[id]?.texture ?? null;
      default:
        return null; // samplers are the manifest's; the engine's depth comes with each frame
    }
  }

  /** The render targets by resource id (the display and resolve sources change per frame). */
  targets() {
    return {
      shadow_atlas: this.shadowTarget,
      air_table: this.airTarget,
      cloud_bake: this.bakeTarget,
      clouds_hdr: this.cloudTarget,
      shown: this.cloudTarget,
      history_read: this.history[0],
    };
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
          // The shadow and air passes draw from the host's copies of the cloud block
          // (`passBlocks`: `shadowTiles`, `airBands`).
          group.add(new THREE.Uniform(this.passBlocks[pass.pass]?.floats ?? resource.floats));
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

  /** The output size in pixels (see NimbusHost.setSize); the targets follow. */
  setSize(width, height) {
    super.setSize(width, height);
    this.cloudTarget.setSize(this.lowWidth, this.lowHeight);
    for (const h of this.history) h.setSize(width, height);
  }

  /**
   * Where the clouds are seen from: the engine's own camera (y up, metres; x east, -z north),
   * nothing re-derived by hand. Its world position is the viewpoint: `y` its altitude above
   * the ground (flying up into a cloud layer works like any other altitude), `x` and `z` where
   * it stands over the clouds. Its rotation and projection (field of view and aspect, or an
   * OrthographicCamera's box with a package built with --enable orthographic) give each
   * pixel's ray. Moving the altitude relights the sky at the new height; moving the camera
   * over the clouds redraws the shadow atlas around it.
   */
  setCamera(camera) {
    const orthographic = this.pair.camera === 'orthographic';
    if (Boolean(camera.isOrthographicCamera) !== orthographic) {
      throw new Error(
        `setCamera: the pair ${this.pair.pair} was built for a ${this.pair.camera} camera ` +
          `(${orthographic ? 'with' : 'without'} --enable orthographic), not a${camera.isOrthographicCamera ? 'n orthographic' : ' perspective'} one`,
      );
    }
    if (orthographic && camera.reversedDepth) {
      throw new Error('setCamera: a reversed-depth orthographic camera is not drawn yet');
    }
    camera.updateMatrixWorld();
    // The cloud shader takes directions: the view without its translation.
    const view = new THREE.Matrix4().extractRotation(camera.matrixWorld).invert();
    const viewProjection = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, view);
    this.setView({
      viewProjection: viewProjection.elements,
      position: new THREE.Vector3().setFromMatrixPosition(camera.matrixWorld).toArray(),
      projection: camera.projectionMatrix.elements,
      forward: camera.getWorldDirection(new THREE.Vector3()).toArray(),
      far: camera.far,
      reversed: Boolean(camera.reversedDepth),
    });
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
    const depth = options.depth ?? options.scene?.depthTexture ?? null;
    this.useDepth(renderer, depth, 'render');
    const index = this.beginFrame();
    const previous = renderer.getRenderTarget();
    this.drawShadowAtlas(renderer);
    this.drawAirTable(renderer);
    this.drawBake(renderer);
    this.draw(renderer, this.passes.clouds, this.cloudTarget);
    let shown = this.cloudTarget;
    if (this.temporal) {
      const read = this.latest;
      const write = 1 - read;
      this.resolveFrame(index);
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
    this.endFrame();
  }

  /** The engine's depth texture for this frame's passes, checked against the pair's key. */
  useDepth(renderer, depth, caller) {
    if (this.readsDepth) {
      if (!depth) {
        throw new Error(
          `${caller}: the pair ${this.pair.pair} reads the engine's depth (built with --enable scene-depth): ` +
            'pass { scene: aRenderTargetWithADepthTexture } or { depth: aDepthTexture }',
        );
      }
      // WebGL's depth range: NDC z in [-1, 1]; its textures' first row is the bottom one.
      this.setDepthEncoding({
        // three writes a logarithmic depth for perspective cameras only.
        logarithmic: Boolean(renderer.capabilities?.logarithmicDepthBuffer) && this.pair.camera !== 'orthographic',
        depthScale: 2,
        depthOffset: -1,
        width: depth.image.width,
        height: depth.image.height,
        flipY: true,
      });
      for (const d of this.dynamic) if (d.holds === 'scene_depth') d.uniform.value = depth;
    } else if (depth) {
      throw new Error(`${caller}: the pair ${this.pair.pair} was built without --enable scene-depth; it cannot read a depth buffer`);
    }
  }

  /** Redraws the air table, or a band of it, when the sun or the camera's altitude changed. */
  drawAirTable(renderer) {
    if (this.passes.air) this.drawPlan(renderer, 'air', this.airTarget, this.airBands());
  }

  /**
   * Draws pass `name` as `plan` says (`shadowTiles`, `airBands`): over each of its rectangles
   * into `target`, or into the pass's back target when `plan.back`; then `plan.copy` copied
   * from the back target into `target`.
   */
  drawPlan(renderer, name, target, plan) {
    if (plan.back && !this.backs[name]) {
      this.backs[name] = hdrTarget(target.width, target.height, THREE.RepeatWrapping);
    }
    const into = plan.back ? this.backs[name] : target;
    for (const [x, y, width, height] of plan.rects) {
      // WebGL's scissor counts rows from the bottom, as the pass's frag coords do.
      into.scissor.set(x, y, width, height);
      into.scissorTest = true;
      this.draw(renderer, this.passes[name], into);
    }
    into.scissorTest = false;
    if (plan.copy) {
      const [x, y, width, height] = plan.copy;
      // Texel rows counted from the first, as the scissor's.
      const region = new THREE.Box2(new THREE.Vector2(x, y), new THREE.Vector2(x + width, y + height));
      renderer.copyTextureToTexture(this.backs[name].texture, target.texture, region, new THREE.Vector2(x, y));
    }
  }

  /** Redraws the bake (pairs of a baked path) when what it depends on changed. */
  drawBake(renderer) {
    if (this.passes.bake && this.bakeOutOfDate()) {
      this.draw(renderer, this.passes.bake, this.bakeTarget);
    }
  }

  /**
   * Redraws what of the shadow atlas is out of date (the sun, the camera's place or the clouds
   * moved): the whole atlas, or with `cascadeRotation` a band of a tile a frame, drawn into the
   * back atlas and copied into the atlas when the tile is done (`shadowTiles`).
   */
  drawShadowAtlas(renderer) {
    if (this.passes.shadow) this.drawPlan(renderer, 'shadow', this.shadowTarget, this.shadowTiles());
  }

  /**
   * The clouds' shadow on the engine's objects, for this frame: call it after the engine's
   * depth is drawn (`options.scene`, a render target with a depthTexture, or `options.depth`)
   * and before the scene is lit; materials given to `shadowMaterial` then take it. Per pixel
   * of the depth buffer it is the sun's light through the clouds at the surface there (the
   * package's scene_shadow pass). Returns the texture it drew.
   */
  renderSceneShadow(renderer, options = {}) {
    if (!this.sceneShadowTarget) {
      throw new Error(
        `renderSceneShadow: the pair ${this.pair.pair} has no scene_shadow pass (it needs --enable scene-depth, ` +
          'a perspective camera and a shadow atlas)',
      );
    }
    const depth = options.depth ?? options.scene?.depthTexture ?? null;
    this.useDepth(renderer, depth, 'renderSceneShadow');
    const { width, height } = depth.image;
    if (this.sceneShadowTarget.width !== width || this.sceneShadowTarget.height !== height) {
      this.sceneShadowTarget.setSize(width, height);
    }
    const previous = renderer.getRenderTarget();
    this.drawPlan(renderer, 'shadow', this.shadowTarget, this.shadowTilesAhead());
    this.draw(renderer, this.passes.scene_shadow, this.sceneShadowTarget);
    renderer.setRenderTarget(previous);
    return this.sceneShadowTarget.texture;
  }

  /**
   * Makes `material` (three's lit materials: MeshStandardMaterial, MeshPhysicalMaterial,
   * MeshLambertMaterial, MeshPhongMaterial) take the clouds' shadow drawn by
   * `renderSceneShadow`: its direct light is scaled by the sun's light through the clouds in
   * its pixel, its ambient and environment light left as they are. The scene's sun should be
   * its only direct light, and the scene drawn at the depth buffer's size (one texel per
   * pixel). Returns the material.
   */
  shadowMaterial(material) {
    if (!this.sceneShadowTarget) {
      throw new Error(`shadowMaterial: the pair ${this.pair.pair} has no scene_shadow pass`);
    }
    const shadow = { value: this.sceneShadowTarget.texture };
    const previous = material.onBeforeCompile;
    material.onBeforeCompile = (shader, renderer) => {
      previous?.call(material, shader, renderer);
      shader.uniforms.nimbusSceneShadow = shadow;
      shader.fragmentShader = `uniform sampler2D nimbusSceneShadow;\n${shader.fragmentShader.replace(
        '#include <lights_fragment_end>',
        `#include <lights_fragment_end>
        {
          // The pass wrote its rows top first; gl_FragCoord counts them from the bottom.
          ivec2 nimbusSize = textureSize(nimbusSceneShadow, 0);
          ivec2 nimbusTexel = ivec2(int(gl_FragCoord.x), int(float(nimbusSize.y) - gl_FragCoord.y));
          float nimbusSun = texelFetch(nimbusSceneShadow, nimbusTexel, 0).r;
          reflectedLight.directDiffuse *= nimbusSun;
          reflectedLight.directSpecular *= nimbusSun;
        }`,
      )}`;
    };
    const key = material.customProgramCacheKey?.bind(material);
    material.customProgramCacheKey = () => `nimbus-scene-shadow ${key ? key() : ''}`;
    material.needsUpdate = true;
    return material;
  }

  dispose() {
    this.geometry.dispose();
    if (this.sceneShadowTarget) this.sceneShadowTarget.dispose();
    if (this.sceneCopy) {
      this.sceneCopy.geometry.dispose();
      this.sceneCopy.material.dispose();
    }
    this.cloudTarget.dispose();
    for (const h of this.history) h.dispose();
    if (this.shadowTarget) this.shadowTarget.dispose();
    for (const t of Object.values(this.backs)) t.dispose();
    if (this.airTarget) this.airTarget.dispose();
    if (this.bakeTarget) this.bakeTarget.dispose();
    for (const p of Object.values(this.passes)) p.material.dispose();
    for (const t of Object.values(this.textures)) t.dispose();
  }
}
