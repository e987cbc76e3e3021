// Runs a three.js package's own NimbusClouds through a sequence of frames in Node, with a
// renderer that draws nothing and keeps the bytes of every cloud and resolve block the package
// hands three.js: what the package's JavaScript writes each frame, for comparison with what
// Nimbus's runtime writes for the same frames (shaders-gen/tests/frame_contract.rs).
//
//   node frame-sequence.mjs PACKAGE_DIR SEQUENCE.json > blocks.json
//
// SEQUENCE.json: { width, height, upscale, accumulate, seed, wind: [speed, from, top, topFrom],
// steps: [{ pitch, yaw, fov, altitude, time, renders }] }. The package folder must resolve
// `three` (a node_modules beside it). Prints [{ pass, hex }] in draw order.
import { readFile } from 'node:fs/promises';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { resolve } from 'node:path';

const [pkgDir, sequenceFile] = process.argv.slice(2);
if (!pkgDir || !sequenceFile) {
  console.error('usage: node frame-sequence.mjs PACKAGE_DIR SEQUENCE.json');
  process.exit(2);
}
const sequence = JSON.parse(await readFile(sequenceFile, 'utf8'));

// The package loads its files with fetch: answer file URLs from the disk. Its 2D textures are
// decoded by the browser; nothing here samples them.
globalThis.fetch = async (url) => new Response(await readFile(fileURLToPath(url)));
globalThis.createImageBitmap = async () => ({ width: 1, height: 1, close() {} });

const base = pathToFileURL(resolve(pkgDir) + '/');
const THREE = await import(pathToFileURL(resolve(pkgDir, 'node_modules/three/build/three.module.js')).href);
const { NimbusClouds } = await import(new URL('nimbus-clouds.js', base).href);

const hex = (floats) => Buffer.from(floats.buffer, floats.byteOffset, floats.byteLength).toString('hex');
const drawn = [];
const renderer = {
  target: null,
  getRenderTarget() { return this.target; },
  setRenderTarget(t) { this.target = t; },
  render(scene) {
    for (const mesh of scene.children) {
      const pass = mesh.material.name.replace(/^nimbus /, '');
      if (pass !== 'clouds' && pass !== 'resolve') continue;
      const block = mesh.material.uniformsGroups[0].uniforms[0].value;
      drawn.push({ pass, hex: hex(block) });
    }
  },
};

const clouds = await NimbusClouds.load(base);
// The runtime draws each atlas whole when it changes: so does the package here. With the
// cascades in rotation its kept tiles' transforms lag by design for a few frames after a move
// (browser_cli.rs holds the rotation to the whole redraw).
clouds.cascadeRotation = false;
clouds.upscale = Boolean(sequence.upscale);
clouds.accumulate = Boolean(sequence.accumulate);
clouds.seed = sequence.seed ?? 0;
clouds.setSize(sequence.width, sequence.height);
if (sequence.wind) clouds.setWind(...sequence.wind);
const degrees = Math.PI / 180;
for (const step of sequence.steps) {
  // Nimbus's camera convention: pitch up from the horizon, yaw clockwise from -z (north).
  const camera = new THREE.PerspectiveCamera(step.fov, sequence.width / sequence.height, 1, 1e6);
  camera.rotation.order = 'YXZ';
  camera.rotation.set(step.pitch * degrees, -step.yaw * degrees, 0);
  camera.position.set(0, step.altitude, 0);
  clouds.setCamera(camera);
  if (step.time !== undefined) clouds.setTime(step.time);
  for (let i = 0; i < step.renders; i++) clouds.render(renderer);
}
process.stdout.write(JSON.stringify(drawn));
