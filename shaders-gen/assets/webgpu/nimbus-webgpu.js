// Nimbus clouds for WebGPU: draws a Nimbus engine package (`nimbus emit --engine webgpu`) with
// the WebGPU API alone. Shipped in every webgpu package; it reads nimbus-package.json for the
// passes, their WGSL, entry points and bind-group layouts (in the API's own terms), the
// textures and the uniform blocks, so it holds no knowledge of a genus or a preset. The camera,
// the sun, the timeline and the frame sequence are NimbusHost's (nimbus-host.js), shared with
// the three.js host.
//
//   import { NimbusWebGPU } from './nimbus-webgpu.js';
//   const device = await (await navigator.gpu.requestAdapter()).requestDevice();
//   const context = canvas.getContext('webgpu');
//   const format = navigator.gpu.getPreferredCanvasFormat();
//   context.configure({ device, format });
//   const clouds = await NimbusWebGPU.load(new URL('./', import.meta.url), device, { format });
//   clouds.setSize(canvas.width, canvas.height);
//   clouds.setCamera({ viewProjection, position });   // 16 numbers (projection × view without
//                                                     // translation, column-major); [x, y, z] m
//   clouds.setSun(30, 150);                           // degrees: elevation, azimuth from north
//   clouds.render(context.getCurrentTexture().createView());
//
// In the engine's own scene (a package built with --enable scene-depth): setCamera also takes
// the camera's `projection`, `forward`, `far` and `reversed`; draw the scene's depth, then
// `clouds.renderSceneShadow({ depth })` for the clouds' shadow on its objects (red: the sun's
// light through the clouds at each pixel's surface), the scene, and `clouds.render(view,
// { depth })` over it.

import { NimbusHost, loadPackage, widenTexels } from './nimbus-host.js';

/** Every intermediate target: linear HDR radiance, alpha the clouds' opacity. */
const HDR = 'rgba16float';

/**
 * One noise texture, as half floats (`t.format`: `r16float`, one channel, or `rgba16float`):
 * 3D files widened through the package's `texel_halves`, 2D images converted by the copy (each
 * byte k to k/255).
 */
async function loadTexture(device, get, t, texelHalves) {
  const [w, h, d = 1] = t.size;
  const texture = device.createTexture({
    label: t.name,
    size: [w, h, d],
    dimension: t.dimension,
    format: t.format,
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST | GPUTextureUsage.RENDER_ATTACHMENT,
  });
  if (t.dimension === '3d') {
    const channels = t.format === 'r16float' ? 1 : 4;
    const data = await get(t.file, 'bytes');
    const expected = w * h * d * channels;
    if (data.length !== expected) throw new Error(`${t.file}: ${data.length} bytes, expected ${expected}`);
    const halves = widenTexels(data, texelHalves);
    device.queue.writeTexture({ texture }, halves, { bytesPerRow: w * 2 * channels, rowsPerImage: h }, [w, h, d]);
  } else {
    // Texel values are data, not colours: no premultiplication, no colour conversion.
    const bitmap = await createImageBitmap(await get(t.file, 'blob'), {
      premultiplyAlpha: 'none',
      colorSpaceConversion: 'none',
    });
    device.queue.copyExternalImageToTexture({ source: bitmap }, { texture }, [w, h]);
  }
  return texture;
}

/** The WebGPU side of one Nimbus package pair: its pipelines, targets, textures and buffers. */
export class NimbusWebGPU extends NimbusHost {
  /**
   * Loads the package at `base` (a URL of its folder) onto `device`. `options.pair` picks a
   * genus × preset pair (`cumulus.high`; the first otherwise), `options.format` the format of
   * the texture `render` draws into (the canvas's preferred format by default). Pipelines are
   * compiled with createRenderPipelineAsync: keep drawing the current pair until the promise
   * resolves, then swap (`options.compile: 'blocking'` compiles with createRenderPipeline).
   */
  static async load(base, device, options = {}) {
    const { pkg, pair, blocks, get } = await loadPackage(base, 'webgpu', options);
    if (pair.camera === 'orthographic') {
      throw new Error(`the pair ${pair.pair} has an orthographic camera, which the WebGPU host does not draw yet`);
    }
    const textures = {};
    for (const t of pkg.textures) textures[t.name] = await loadTexture(device, get, t, pkg.texel_halves);
    const modules = {};
    for (const pass of pair.passes) {
      const code = await get(pass.files[0].file);
      modules[pass.pass] = device.createShaderModule({ label: pass.shader, code });
    }
    const format = options.format ?? navigator.gpu.getPreferredCanvasFormat();
    // Every pass's pipeline compiled asynchronously and together: the browser may compile them
    // off the thread that draws, so an application that loads another pair (a new preset, a
    // new genus) keeps drawing the current one until this promise resolves, then swaps.
    // `compile: 'blocking'` creates them with createRenderPipeline instead, the compile landing
    // on the device's queue at once (to compare the two).
    const create = options.compile === 'blocking'
      ? async (descriptor) => device.createRenderPipeline(descriptor)
      : (descriptor) => device.createRenderPipelineAsync(descriptor);
    const passes = {};
    await Promise.all(pair.passes.map(async (pass) => {
      const layout = device.createBindGroupLayout({ label: pass.pass, entries: pass.bind_group_layout.entries });
      const display = pass.pass === 'display';
      // The clouds go over the engine's picture premultiplied; elsewhere every pass replaces.
      const over = display && Boolean(blocks.scene)
        ? {
          color: { srcFactor: 'one', dstFactor: 'one-minus-src-alpha' },
          alpha: { srcFactor: 'zero', dstFactor: 'one' },
        }
        : undefined;
      const pipeline = await create({
        label: pass.shader,
        layout: device.createPipelineLayout({ bindGroupLayouts: [layout] }),
        vertex: { module: modules[pass.pass], entryPoint: pass.entry_points.vertex },
        fragment: {
          module: modules[pass.pass],
          entryPoint: pass.entry_points.fragment,
          targets: [{ format: display ? format : HDR, blend: over }],
        },
        primitive: { topology: 'triangle-list' },
      });
      passes[pass.pass] = { pass, layout, pipeline };
    }));
    return new NimbusWebGPU(device, pkg, pair, blocks, textures, passes, format);
  }

  constructor(device, pkg, pair, blocks, textures, passes, format) {
    super(pkg, pair, blocks);
    this.device = device;
    this.textures = textures;
    this.format = format;
    this.buffers = {};
    for (const [name, block] of Object.entries(blocks)) {
      this.buffers[name] = device.createBuffer({
        label: `${name} block`,
        // Whole 16-byte words.
        size: Math.ceil(block.bytes.length / 16) * 16,
        usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
      });
    }
    // The shadow and air passes draw from the host's copies of the cloud block (`passBlocks`:
    // `shadowTiles`, `airBands`), each in a buffer of its own.
    this.passBuffers = {};
    for (const [name, block] of Object.entries(this.passBlocks)) {
      this.passBuffers[name] = device.createBuffer({
        label: `${name} block`,
        size: Math.ceil(block.bytes.length / 16) * 16,
        usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
      });
    }
    const atlas = pair.shadow_atlas;
    this.shadowTarget = atlas ? this.target('shadow atlas', atlas.width, atlas.height, GPUTextureUsage.COPY_DST) : null;
    const air = this.pair.air_table;
    this.airTarget = air ? this.target('air table', air.width, air.height, GPUTextureUsage.COPY_DST) : null;
    // Drawn in bands (cascades in rotation), a shadow tile or the air table is drawn into a
    // back target of the same size, made with the first band, then copied in (`drawPlan`).
    this.backs = {};
    // The bake of a baked path (slices, impostor, mesh, blob2d), redrawn when the block members it depends on
    // change (NimbusHost.bakeOutOfDate).
    const bake = this.pair.cloud_bake;
    this.bakeTarget = bake ? this.target('cloud bake', bake.width, bake.height) : null;
    // The clouds' shadow on the engine's objects (pairs with a scene_shadow pass), sized to
    // the engine's depth when it is first drawn.
    this.sceneShadowTarget = null;
    this.depthView = null;
    if (this.readsDepth) {
      // Over the engine's picture: premultiplied clouds, the picture's alpha kept.
      blocks.display.setFloats('keep_alpha', [1]);
    }
    this.cloudTarget = null;
    this.history = [null, null];
    this.latest = 0;
    this.samplers = new Map();
    this.passes = passes;
  }

  target(label, width, height, usage = 0) {
    return this.device.createTexture({
      label,
      size: [width, height],
      format: HDR,
      usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING | usage,
    });
  }

  /** The output size in pixels (see NimbusHost.setSize); the targets follow. */
  setSize(width, height) {
    super.setSize(width, height);
    for (const t of [this.cloudTarget, ...this.history]) t?.destroy();
    this.cloudTarget = this.target('clouds', this.lowWidth, this.lowHeight);
    this.history = [this.target('history A', width, height), this.target('history B', width, height)];
  }

  /**
   * Where the clouds are seen from: `viewProjection`, the camera's projection × its view
   * without translation (16 numbers, column by column: a WebGPU projection, depth 0..1), and
   * `position`, its place in the world (y up, metres: y is its altitude; x east, −z north).
   * A pair that reads the engine's depth also needs `projection` (the camera's 16 numbers),
   * `forward` (its unit view direction), `far` and `reversed` (a reversed-Z buffer, depth 1 at
   * the near plane): how the depth buffer encodes distance.
   */
  setCamera({ viewProjection, position, projection, forward, far, reversed }) {
    if (this.readsDepth && !(projection && forward)) {
      throw new Error(`setCamera: the pair ${this.pair.pair} reads the engine's depth: give projection and forward too`);
    }
    this.setView({ viewProjection, position, projection, forward, far, reversed });
  }

  /**
   * The engine's depth for this frame: a GPUTexture (`depth32float`, `depth24plus` or
   * `r32float`, one texel per output pixel, first row at the top as WebGPU has it), read
   * through a depth-only view for depth formats; or `{ texture, view }` with a view of your
   * own.
   */
  useDepth(depth, caller) {
    if (!this.readsDepth) {
      if (depth) throw new Error(`${caller}: the pair ${this.pair.pair} was built without --enable scene-depth; it cannot read a depth buffer`);
      return;
    }
    if (!depth) {
      throw new Error(`${caller}: the pair ${this.pair.pair} reads the engine's depth (built with --enable scene-depth): pass { depth: aGPUTexture }`);
    }
    const texture = depth.texture ?? depth;
    const view = depth.texture ? depth.view : depth.createView(
      texture.format.startsWith('depth') ? { aspect: 'depth-only' } : {},
    );
    // WebGPU's depth range: NDC z in [0, 1]; its textures' first row is the top one.
    this.setDepthEncoding({ depthScale: 1, depthOffset: 0, width: texture.width, height: texture.height, flipY: false });
    this.depthView = view;
    this.depthSize = [texture.width, texture.height];
  }

  /**
   * The clouds' shadow on the engine's objects for this frame (pairs with a scene_shadow
   * pass): call it after the engine's depth is drawn (`options.depth`, as `render` takes it)
   * and before its materials are lit. Per pixel of the depth buffer, the red channel is the
   * sun's light through the clouds at the surface there; the engine's materials scale their
   * direct sunlight by it. Returns the GPUTexture (`rgba16float`).
   */
  renderSceneShadow(options = {}) {
    if (!this.passes.scene_shadow) {
      throw new Error(`renderSceneShadow: the pair ${this.pair.pair} has no scene_shadow pass (it needs --enable scene-depth, a perspective camera and a shadow atlas)`);
    }
    this.useDepth(options.depth, 'renderSceneShadow');
    const [w, h] = this.depthSize;
    if (!this.sceneShadowTarget || this.sceneShadowTarget.width !== w || this.sceneShadowTarget.height !== h) {
      this.sceneShadowTarget?.destroy();
      // Copyable too: an engine may keep it with its own lighting inputs.
      this.sceneShadowTarget = this.target('scene shadow', w, h, GPUTextureUsage.COPY_SRC);
    }
    const queue = this.device.queue;
    const encoder = this.device.createCommandEncoder({ label: 'nimbus scene shadow' });
    const plan = this.passes.shadow ? this.shadowTilesAhead() : null;
    for (const [name, block] of Object.entries(this.blocks)) queue.writeBuffer(this.buffers[name], 0, block.bytes);
    this.drawShadowAtlas(encoder, plan);
    this.draw(encoder, 'scene_shadow', this.sceneShadowTarget.createView());
    queue.submit([encoder.finish()]);
    return this.sceneShadowTarget;
  }

  /**
   * Redraws the air table, or a band of it, when the sun or the camera's altitude changed
   * (`airBands`, called before the blocks were written).
   */
  drawAirTable(encoder, plan) {
    this.drawPlan(encoder, 'air', this.airTarget, plan);
  }

  /**
   * Draws pass `name` as `plan` says (`shadowTiles`, `airBands`) from its copy of the block:
   * over each of its rectangles into `target`, or into the pass's back target when
   * `plan.back`; then `plan.copy` copied from the back target into `target`.
   */
  drawPlan(encoder, name, target, plan) {
    if (!plan || !plan.rects.length) return;
    this.device.queue.writeBuffer(this.passBuffers[name], 0, this.passBlocks[name].bytes);
    if (plan.back && !this.backs[name]) {
      this.backs[name] = this.target(`${name} back`, target.width, target.height, GPUTextureUsage.COPY_SRC);
    }
    const into = plan.back ? this.backs[name] : target;
    for (const rect of plan.rects) this.draw(encoder, name, into.createView(), null, null, rect);
    if (plan.copy) {
      const [x, y, width, height] = plan.copy;
      encoder.copyTextureToTexture(
        { texture: this.backs[name], origin: [x, y] },
        { texture: target, origin: [x, y] },
        [width, height],
      );
    }
  }

  /** Redraws the bake (pairs of a baked path) when what it depends on changed. */
  drawBake(encoder) {
    if (this.passes.bake && this.bakeOutOfDate()) {
      this.draw(encoder, 'bake', this.bakeTarget.createView());
    }
  }

  /**
   * Draws what `plan` says of the shadow atlas (`shadowTiles`, called before the blocks were
   * written: it writes the tiles' lookup): the whole atlas, or a band of a tile into the back
   * atlas, copied into the atlas when the tile is done.
   */
  drawShadowAtlas(encoder, plan) {
    this.drawPlan(encoder, 'shadow', this.shadowTarget, plan);
  }

  /** A sampler as the pass's layout describes it, made once. */
  sampler(entry) {
    const key = JSON.stringify(entry.samplerDescriptor);
    if (!this.samplers.has(key)) this.samplers.set(key, this.device.createSampler(entry.samplerDescriptor));
    return this.samplers.get(key);
  }

  /**
   * A bind group for `pass`: each binding bound by the resource the package names there
   * (`holds.id`), provided as its kind says (`holds.kind`).
   */
  bindGroup({ pass, layout }, shown, historyRead) {
    const targets = {
      shadow_atlas: this.shadowTarget,
      air_table: this.airTarget,
      cloud_bake: this.bakeTarget,
      clouds_hdr: this.cloudTarget,
      history_read: historyRead,
      shown,
    };
    const entries = pass.bindings.map((b) => {
      const layoutEntry = pass.bind_group_layout.entries.find((e) => e.binding === b.binding);
      const { id, kind } = b.holds;
      let resource;
      if (kind === 'sampler') resource = this.sampler(layoutEntry);
      else if (kind === 'uniform block' && this.passBuffers[pass.pass]) resource = { buffer: this.passBuffers[pass.pass] };
      else if (kind === 'uniform block' && this.buffers[id]) resource = { buffer: this.buffers[id] };
      else if (kind === 'texture' && this.textures[id]) resource = this.textures[id].createView();
      else if (kind === 'target' && targets[id]) resource = targets[id].createView();
      else if (kind === 'engine depth' && this.depthView) resource = this.depthView;
      else throw new Error(`${pass.pass}: nothing to bind to ${b.name} (${kind} ${id})`);
      return { binding: b.binding, resource };
    });
    return this.device.createBindGroup({ label: pass.pass, layout, entries });
  }

  draw(encoder, name, view, shown = null, historyRead = null, rect = null) {
    const p = this.passes[name];
    // Over the engine's picture the display pass blends onto what the view holds; a tile of
    // the shadow atlas (`rect`) leaves the others as they are.
    const keep = (name === 'display' && this.readsDepth) || rect !== null;
    const pass = encoder.beginRenderPass({
      label: name,
      colorAttachments: [{ view, loadOp: keep ? 'load' : 'clear', storeOp: 'store', clearValue: [0, 0, 0, 0] }],
    });
    if (rect) pass.setScissorRect(...rect);
    pass.setPipeline(p.pipeline);
    pass.setBindGroup(0, this.bindGroup(p, shown, historyRead));
    pass.draw(3);
    pass.end();
  }

  /**
   * Draws one frame into `view` (a GPUTextureView of `options.format`, e.g. the canvas's). A
   * pair built with `--enable scene-depth` draws the clouds over what `view` holds (the
   * engine's picture), stopped by `options.depth` (the engine's depth texture, see useDepth).
   */
  render(view, options = {}) {
    this.useDepth(options.depth, 'render');
    const index = this.beginFrame();
    const queue = this.device.queue;
    const encoder = this.device.createCommandEncoder({ label: 'nimbus frame' });
    let shown = this.cloudTarget;
    let read = null;
    if (this.temporal) {
      this.resolveFrame(index);
      read = this.history[this.latest];
      shown = this.history[1 - this.latest];
    }
    const plan = this.passes.shadow ? this.shadowTiles() : null;
    const air = this.passes.air ? this.airBands() : null;
    for (const [name, block] of Object.entries(this.blocks)) queue.writeBuffer(this.buffers[name], 0, block.bytes);
    this.drawShadowAtlas(encoder, plan);
    this.drawAirTable(encoder, air);
    this.drawBake(encoder);
    this.draw(encoder, 'clouds', this.cloudTarget.createView());
    if (this.temporal) {
      this.draw(encoder, 'resolve', shown.createView(), null, read);
      this.latest = 1 - this.latest;
    }
    this.draw(encoder, 'display', view, shown);
    queue.submit([encoder.finish()]);
    this.endFrame();
  }

  dispose() {
    for (const t of [this.cloudTarget, ...this.history, this.shadowTarget, ...Object.values(this.backs), this.airTarget, this.bakeTarget, this.sceneShadowTarget]) t?.destroy();
    for (const t of Object.values(this.textures)) t.destroy();
    for (const b of Object.values(this.buffers)) b.destroy();
    for (const b of Object.values(this.passBuffers)) b.destroy();
  }
}
