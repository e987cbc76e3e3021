// Renders a Nimbus webgpu package once through its own host module (nimbus-webgpu.js) on
// Chromium's WebGPU, from the camera the query string describes (as main.mjs does for three.js),
// and publishes the frame as a PNG data URL on `window.nimbus`. three.js is used here only for
// the camera's matrices, as an application would use its own math library.
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
  clouds.setCamera({ viewProjection: viewProjection.elements, position: camera.position.toArray() });
  if (q.has('sun')) clouds.setSun(...q.get('sun').split(',').map(Number));
  const target = device.createTexture({
    size: [width, height],
    format,
    usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC,
  });
  for (let i = 0; i < number('frames', 1); i++) clouds.render(target.createView());

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

const result = { done: false, error: null, png: null, messages: [] };
window.nimbus = result;
run(result)
  .catch((e) => { result.error = String(e && e.stack ? e.stack : e); })
  .finally(() => { result.done = true; });
