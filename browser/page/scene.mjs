// Nimbus clouds inside a three.js scene: a tower (`tower=x,z,width,height`, metres) stands
// in the cloud layer; the scene is drawn into a render target with a depth texture, and the
// package (built with --enable scene-depth) draws the clouds over it, stopped by its depth.
// `log=1` uses three's logarithmic depth buffer; `ortho=H` an orthographic camera; `frames=N` accumulates N frames; `depth=0` draws the clouds the old way, over
// everything (the control). Publishes the frame like main.mjs.
import * as THREE from 'three';
import { publish } from './publish.mjs';
import { canvasRenderer } from './renderer.mjs';
import { height, number, placeCamera, q, width } from './query.mjs';


async function run(result) {
  const { messages } = result;
  const base = new URL(q.get('pkg') ?? '/pkg/', location.href);
  const { NimbusClouds } = await import(new URL('nimbus-clouds.js', base).href);
  const { canvas, renderer } = canvasRenderer(result, { logarithmicDepthBuffer: q.get('log') === '1' });

  // The user's scene: a tower, and the camera that sees it.
  const scene = new THREE.Scene();
  const [x, z, side, tall] = (q.get('tower') ?? '0,-8000,1500,4000').split(',').map(Number);
  // `color=rrggbb`: the tower's colour as the canvas shows it (black by default).
  const color = parseInt(q.get('color') ?? '000000', 16);
  const tower = new THREE.Mesh(new THREE.BoxGeometry(side, tall, side), new THREE.MeshBasicMaterial({ color }));
  tower.position.set(x, tall / 2, z);
  scene.add(tower);
  // `ortho=H`: an orthographic camera seeing H metres top to bottom.
  const extent = number('ortho', 0);
  const camera = extent > 0
    ? new THREE.OrthographicCamera(-extent * width / height / 2, extent * width / height / 2, extent / 2, -extent / 2, 1, 1e6)
    : new THREE.PerspectiveCamera(number('fov', 60), width / height, 1, 1e6);
  placeCamera(camera, 10);
  const target = new THREE.WebGLRenderTarget(width, height, {
    type: THREE.HalfFloatType,
    depthTexture: new THREE.DepthTexture(width, height, THREE.FloatType),
  });

  const clouds = await NimbusClouds.load(base);
  const frames = number('frames', 1);
  clouds.accumulate = frames > 1;
  clouds.setSize(width, height);
  clouds.exposure = number('exposure', 8);
  if (q.has('sun')) clouds.setSun(...q.get('sun').split(',').map(Number));
  renderer.setRenderTarget(target);
  renderer.render(scene, camera);
  renderer.setRenderTarget(null);
  clouds.setCamera(camera);
  for (let i = 0; i < frames; i++) {
    if (q.get('depth') === '0') clouds.render(renderer);
    else clouds.render(renderer, null, { scene: target });
  }
  return { gl: renderer.getContext(), canvas };
}

publish(run);
