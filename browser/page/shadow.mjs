// The clouds' shadow on a three.js scene's objects: a flat white ground (`ground=SIZE`, metres
// square) under the package's clouds, lit by a directional light from the clouds' sun and by
// nothing else. The package (built with --enable scene-depth) draws the scene's depth, then
// its scene_shadow pass; the ground is drawn lit with a MeshStandardMaterial given to
// `clouds.shadowMaterial`, and with the same material untouched. Publishes, in `values`, the
// pass's output (`mask`, red, first row the top one as the pass writes it) and both renders'
// red in linear light (`lit`, `unlit`, first row the bottom one as WebGL reads it); the canvas
// shows the shadowed ground with the clouds over it. `shadow=0` leaves the material untouched
// in the `lit` render too (the control).
import * as THREE from 'three';
import { publish } from './publish.mjs';
import { canvasRenderer } from './renderer.mjs';
import { height, number, placeCamera, q, width } from './query.mjs';

/** The red channel of a float render target, as WebGL reads it (first row the bottom one). */
function red(renderer, target) {
  const rgba = new Float32Array(width * height * 4);
  renderer.readRenderTargetPixels(target, 0, 0, width, height, rgba);
  return Array.from({ length: width * height }, (_, i) => rgba[i * 4]);
}

function floatTarget(options = {}) {
  return new THREE.WebGLRenderTarget(width, height, { type: THREE.FloatType, ...options });
}

async function run(result) {
  const base = new URL(q.get('pkg') ?? '/pkg/', location.href);
  const { NimbusClouds } = await import(new URL('nimbus-clouds.js', base).href);
  const { canvas, renderer } = canvasRenderer(result);

  const clouds = await NimbusClouds.load(base);
  clouds.setSize(width, height);
  if (q.has('sun')) clouds.setSun(...q.get('sun').split(',').map(Number));

  // The user's scene: the ground, and the sun as its only light.
  const size = number('ground', 60000);
  const plain = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 1, metalness: 0 });
  const shadowed = plain.clone();
  if (q.get('shadow') !== '0') clouds.shadowMaterial(shadowed);
  const ground = new THREE.Mesh(new THREE.PlaneGeometry(size, size), shadowed);
  ground.rotation.x = -Math.PI / 2;
  const sun = new THREE.DirectionalLight(0xffffff, 2);
  sun.position.fromArray(clouds.sunDirection);
  const scene = new THREE.Scene();
  scene.add(ground, sun);
  const camera = new THREE.PerspectiveCamera(number('fov', 60), width / height, 1, 1e6);
  placeCamera(camera, -10);
  clouds.setCamera(camera);

  // The scene's depth, the clouds' shadow on it, then the scene lit.
  const target = floatTarget({ depthTexture: new THREE.DepthTexture(width, height, THREE.FloatType) });
  renderer.setRenderTarget(target);
  renderer.render(scene, camera);
  const mask = clouds.renderSceneShadow(renderer, { scene: target });
  // The pass's output copied as it is (row for row) into a float target WebGL can read.
  const copy = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), new THREE.MeshBasicMaterial({ map: mask }));
  const flat = new THREE.Scene();
  flat.add(copy);
  const ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  copy.position.z = -0.5;
  const maskCopy = floatTarget();
  renderer.setRenderTarget(maskCopy);
  renderer.render(flat, ortho);
  const lit = floatTarget();
  renderer.setRenderTarget(lit);
  renderer.render(scene, camera);
  ground.material = plain;
  const unlit = floatTarget();
  renderer.setRenderTarget(unlit);
  renderer.render(scene, camera);
  result.values = {
    width,
    height,
    mask: red(renderer, maskCopy),
    lit: red(renderer, lit),
    unlit: red(renderer, unlit),
  };

  // The picture: the shadowed ground, the clouds over it.
  ground.material = shadowed;
  renderer.setRenderTarget(target);
  renderer.render(scene, camera);
  clouds.render(renderer, null, { scene: target });
  return { gl: renderer.getContext(), canvas };
}

publish(run);
