// Renders a Nimbus webgpu package once through its own host module (nimbus-webgpu.js) on
// Chromium's WebGPU, from the camera the query string describes (as main.mjs does for three.js),
// and publishes the frame as a PNG data URL on `window.nimbus`. three.js is used here only for
// the camera's matrices, as an application would use its own math library. With `tower=x,z,
// side,height` (metres) and `color=rrggbb`, the page draws a scene of its own first, as an
// application would: that box, into the target and a depth32float depth buffer, which a package
// built with --enable scene-depth then reads (`depth=0` leaves the depth out: the control).
import * as THREE from 'three';
import { height, number, placeCamera, q, width } from './query.mjs';


async function run(result) {
  if (!navigator.gpu) throw new Error('no WebGPU in this browser');
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new Error('no WebGPU adapter');
  const info = adapter.info ?? {};
  result.renderer = `WebGPU: ${info.vendor ?? '?'} ${info.architecture ?? ''} ${info.description ?? ''}`.trim();
  const device = await adapter.requestDevice();
  device.addEventListener('uncapturederror', (e) => result.messages.push(`WebGPU error: ${e.error.message}`));
  const base = new URL(q.get('pkg') ?? '/pkg/', location.href);
  const { NimbusWebGPU } = await import(new URL('nimbus-webgpu.js', base).href);
  // An offscreen target the page reads back (a canvas's texture is the same to the host).
  const format = 'rgba8unorm';
  const clouds = await NimbusWebGPU.load(base, device, { format, pair: q.get('pair') ?? undefined });
  clouds.upscale = q.get('upscale') === '1';
  clouds.accumulate = !clouds.upscale && number('frames', 1) > 1;
  clouds.setSize(width, height);
  clouds.exposure = number('exposure', 8);
  // Nimbus's camera: pitch up from the horizon, yaw clockwise from -z (north), vertical fov.
  const camera = new THREE.PerspectiveCamera(number('fov', 60), width / height, 1, 1e6);
  placeCamera(camera, 12);
  camera.updateMatrixWorld();
  const view = new THREE.Matrix4().extractRotation(camera.matrixWorld).invert();
  const viewProjection = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, view);
  // WebGPU's clip space keeps z in [0, 1]: three's OpenGL projection remapped.
  const zToUnit = new THREE.Matrix4().set(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.5, 0.5, 0, 0, 0, 1);
  const projection = new THREE.Matrix4().multiplyMatrices(zToUnit, camera.projectionMatrix);
  const unitViewProjection = new THREE.Matrix4().multiplyMatrices(projection, view);
  clouds.setCamera({
    viewProjection: (clouds.readsDepth ? unitViewProjection : viewProjection).elements,
    position: camera.position.toArray(),
    projection: projection.elements,
    forward: camera.getWorldDirection(new THREE.Vector3()).toArray(),
    far: camera.far,
  });
  const target = device.createTexture({
    size: [width, height],
    format,
    usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC,
  });
  // With `first=1`, a frame is drawn at the package's sun before `sun` moves it (its shadow
  // atlas drawn whole), as main.mjs does; `rotation=0` redraws the whole atlas at once after
  // the move, by default a band of a cascade tile a frame, and `settle=N` draws N frames
  // before the published one.
  if (q.get('first') === '1') clouds.render(target.createView());
  if (q.get('rotation') === '0') clouds.cascadeRotation = false;
  if (q.has('sun')) clouds.setSun(...q.get('sun').split(',').map(Number));
  for (let i = 0; i < number('settle', 0); i++) clouds.render(target.createView());
  // The application's frame: its scene, then the clouds over it.
  const scene = q.has('tower') ? towerScene(device, format, target, unitViewProjection, camera.position) : null;
  const options = scene && q.get('depth') !== '0' ? { depth: scene.depth } : {};
  if (q.has('switch')) {
    // `switch=PAIR`: a game loop that starts loading another pair at frame `switch_at`, keeps
    // drawing this one until it is ready, then draws that one; each frame is timed to the
    // queue's completion (`compile=blocking` loads it with blocking pipeline creation).
    const count = number('frames', 16);
    const at = number('switch_at', 4);
    let current = clouds;
    let next = null;
    let loading = null;
    let swapped = -1;
    const times = [];
    for (let i = 0; i < count; i++) {
      if (i === at) {
        loading = NimbusWebGPU.load(base, device, { format, pair: q.get('switch'), compile: q.get('compile') ?? 'async' })
          .then((c) => { next = c; });
      }
      if (next && swapped < 0) {
        next.upscale = current.upscale;
        next.accumulate = current.accumulate;
        next.setSize(width, height);
        next.exposure = current.exposure;
        next.setCamera({
          viewProjection: viewProjection.elements,
          position: camera.position.toArray(),
          projection: projection.elements,
          forward: camera.getWorldDirection(new THREE.Vector3()).toArray(),
          far: camera.far,
        });
        current = next;
        swapped = i;
      }
      const t0 = performance.now();
      current.render(target.createView(), options);
      await device.queue.onSubmittedWorkDone();
      times.push(performance.now() - t0);
      // Let the load's promises run between frames, as a requestAnimationFrame loop would.
      await new Promise((r) => setTimeout(r, 0));
    }
    await loading;
    const sorted = [...times].sort((a, b) => a - b);
    result.ms = sorted[Math.floor(sorted.length / 2)];
    result.times = times;
    result.values = { swapped, worst: sorted[sorted.length - 1], median: result.ms };
  } else {
    for (let i = 0; i < number('frames', 1); i++) {
      scene?.draw();
      clouds.render(target.createView(), options);
    }
  }

  // `shadow=1`: the clouds' shadow on the scene (the scene_shadow pass), published as
  // `values.mask` (its red channel, first row the top one).
  if (q.get('shadow') === '1') {
    const mask = clouds.renderSceneShadow({ depth: scene.depth });
    result.values = { width, height, mask: await redOfHalfFloats(device, mask) };
  }

  // Read the frame back and publish it as a PNG.
  const bytesPerRow = Math.ceil((width * 4) / 256) * 256;
  const buffer = device.createBuffer({ size: bytesPerRow * height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
  const encoder = device.createCommandEncoder();
  encoder.copyTextureToBuffer({ texture: target }, { buffer, bytesPerRow }, [width, height]);
  device.queue.submit([encoder.finish()]);
  await buffer.mapAsync(GPUMapMode.READ);
  const rows = new Uint8Array(buffer.getMappedRange());
  const pixels = new Uint8ClampedArray(width * height * 4);
  for (let y = 0; y < height; y++) {
    pixels.set(rows.subarray(y * bytesPerRow, y * bytesPerRow + width * 4), y * width * 4);
  }
  buffer.unmap();
  // Opaque, as the display pass writes it for a frame with no engine scene behind.
  for (let i = 3; i < pixels.length; i += 4) pixels[i] = 255;
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  canvas.getContext('2d').putImageData(new ImageData(pixels, width, height), 0, 0);
  document.body.appendChild(canvas);
  result.png = canvas.toDataURL('image/png');
}

/** The red channel of an rgba16float texture, read back (first row the top one). */
async function redOfHalfFloats(device, texture) {
  const bytesPerRow = Math.ceil((width * 8) / 256) * 256;
  const buffer = device.createBuffer({ size: bytesPerRow * height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
  const encoder = device.createCommandEncoder();
  encoder.copyTextureToBuffer({ texture }, { buffer, bytesPerRow }, [width, height]);
  device.queue.submit([encoder.finish()]);
  await buffer.mapAsync(GPUMapMode.READ);
  const halves = new Uint16Array(buffer.getMappedRange());
  // IEEE half to number: sign, 5 exponent bits, 10 mantissa bits.
  const half = (h) => {
    const e = (h >> 10) & 31;
    const m = h & 1023;
    const v = e === 0 ? m * 2 ** -24 : e === 31 ? (m ? NaN : Infinity) : (1 + m / 1024) * 2 ** (e - 15);
    return h & 32768 ? -v : v;
  };
  const red = [];
  for (let y = 0; y < height; y++) for (let x = 0; x < width; x++) red.push(half(halves[(y * bytesPerRow) / 2 + x * 4]));
  buffer.unmap();
  return red;
}

/**
 * The application's own scene: a box standing on the ground (`tower=x,z,side,height`) in the
 * colour `color`, which `draw()` draws into `target` (cleared to black) and `depth` (a
 * depth32float texture). Positions are made relative to the camera on the CPU, so the
 * view-projection has no translation.
 */
function towerScene(device, format, target, viewProjection, eye) {
  const [x, z, side, tall] = q.get('tower').split(',').map(Number);
  const grey = parseInt(q.get('color') ?? '000000', 16);
  const rgb = [(grey >> 16) & 255, (grey >> 8) & 255, grey & 255].map((v) => v / 255);
  const corners = [];
  for (const cy of [0, tall]) for (const cz of [z - side / 2, z + side / 2]) for (const cx of [x - side / 2, x + side / 2]) {
    corners.push([cx - eye.x, cy - eye.y, cz - eye.z]);
  }
  // Twelve triangles of the box (corner index: x + 2 z + 4 y).
  const faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]];
  const vertices = new Float32Array(faces.flatMap(([a, b, c, d]) => [a, b, c, a, c, d].flatMap((i) => corners[i])));
  const buffer = device.createBuffer({ size: vertices.byteLength, usage: GPUBufferUsage.VERTEX | GPUBufferUsage.COPY_DST });
  device.queue.writeBuffer(buffer, 0, vertices);
  const uniforms = device.createBuffer({ size: 80, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
  device.queue.writeBuffer(uniforms, 0, new Float32Array([...viewProjection.elements, ...rgb, 1]));
  const module = device.createShaderModule({
    code: `
      struct Scene { view_projection: mat4x4<f32>, color: vec4<f32> }
      @group(0) @binding(0) var<uniform> scene: Scene;
      @vertex fn vs(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {
        return scene.view_projection * vec4<f32>(p, 1.0);
      }
      @fragment fn fs() -> @location(0) vec4<f32> { return scene.color; }`,
  });
  const pipeline = device.createRenderPipeline({
    layout: 'auto',
    vertex: { module, entryPoint: 'vs', buffers: [{ arrayStride: 12, attributes: [{ shaderLocation: 0, offset: 0, format: 'float32x3' }] }] },
    fragment: { module, entryPoint: 'fs', targets: [{ format }] },
    primitive: { topology: 'triangle-list' },
    depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
  });
  const depth = device.createTexture({
    size: [width, height],
    format: 'depth32float',
    usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING,
  });
  const group = device.createBindGroup({ layout: pipeline.getBindGroupLayout(0), entries: [{ binding: 0, resource: { buffer: uniforms } }] });
  const draw = () => {
    const encoder = device.createCommandEncoder();
    const pass = encoder.beginRenderPass({
      colorAttachments: [{ view: target.createView(), loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 0] }],
      depthStencilAttachment: { view: depth.createView(), depthLoadOp: 'clear', depthStoreOp: 'store', depthClearValue: 1 },
    });
    pass.setPipeline(pipeline);
    pass.setBindGroup(0, group);
    pass.setVertexBuffer(0, buffer);
    pass.draw(vertices.length / 3);
    pass.end();
    device.queue.submit([encoder.finish()]);
  };
  return { depth, draw };
}

const result = { done: false, error: null, png: null, messages: [] };
window.nimbus = result;
run(result)
  .catch((e) => { result.error = String(e && e.stack ? e.stack : e); })
  .finally(() => { result.done = true; });
