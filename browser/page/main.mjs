// Renders a Nimbus three.js package once, from the camera the query string describes, and
// publishes the result (a PNG data URL) and every shader message three logged on `window`.
import * as THREE from 'three';
import { drawOpacity } from './opacity.mjs';
import { publish } from './publish.mjs';
import { canvasRenderer } from './renderer.mjs';
import { height, number, placeCamera, q, width } from './query.mjs';
import { timeFrames } from './timing.mjs';



async function run(result) {
  const { messages } = result;
  const base = new URL(q.get('pkg') ?? '/pkg/', location.href);
  const { NimbusClouds } = await import(new URL('nimbus-clouds.js', base).href);
  const { canvas, renderer } = canvasRenderer(result);
  const clouds = await NimbusClouds.load(base, { pair: q.get('pair') ?? undefined });
  clouds.upscale = q.get('upscale') === '1';
  clouds.accumulate = !clouds.upscale && number('frames', 1) > 1;
  clouds.setSize(width, height);
  clouds.exposure = number('exposure', 8);
  // Nimbus's camera: pitch up from the horizon, yaw clockwise from -z (north), vertical fov.
  const camera = new THREE.PerspectiveCamera(number('fov', 60), width / height, 1, 1e6);
  placeCamera(camera, 12);
  clouds.setCamera(camera);
  // With `first=1`, a frame is drawn before the sun or the clock moves (its shadow atlas, and a
  // baked path's bake, then stale), and the frame sequence restarts (setSize) so the frame
  // after matches a one-frame render.
  if (q.get('first') === '1') {
    clouds.render(renderer);
    clouds.setSize(width, height);
  }
  if (q.has('sun')) {
    const [elevation, azimuth] = q.get('sun').split(',').map(Number);
    clouds.setSun(elevation, azimuth);
  }
  // A scene's [wind] and [[weather]] (`speed,from[,top,topFrom]`; `coverage,at[,over];...`),
  // then its clock: the package's own setWind, setWeather and setTime.
  if (q.has('wind')) clouds.setWind(...q.get('wind').split(',').map(Number));
  for (const state of q.get('weather')?.split(';') ?? []) {
    const [coverage, at, over] = state.split(',').map(Number);
    clouds.setWeather(coverage, { at, over });
  }
  if (q.has('time')) clouds.setTime(number('time', 0));
  // `rotation=0` redraws every out-of-date cascade tile at once; by default a band of one a
  // frame, and `settle=N` draws N frames first (a band each) before the published one.
  if (q.get('rotation') === '0') clouds.cascadeRotation = false;
  for (let i = 0; i < number('settle', 0); i++) clouds.render(renderer);
  const gl = renderer.getContext();
  if (q.has('bench')) {
    // Milliseconds per frame (timing.mjs). The shadow atlas (as @takram/three-clouds
    // redraws its own) and the air table are redrawn every frame with shadow=every, as for
    // a sun that moves every frame; else only when stale.
    const draw = () => {
      if (q.get('shadow') === 'every') {
        clouds.shadowDirty = true;
        clouds.airDirty = true;
        // A baked path's bake follows the sun too.
        clouds.bakeDrawn = null;
      }
      clouds.render(renderer);
    };
    Object.assign(result, timeFrames(gl, draw, number('warmup', 3), number('bench', 10)));
  } else {
    for (let i = 0; i < number('frames', 1); i++) clouds.render(renderer);
  }
  // `output=opacity`: the clouds' opacity in place of the picture (opacity.mjs); the cloud
  // target holds it at full resolution (upscaling and accumulation off).
  if (q.get('output') === 'opacity') drawOpacity(renderer, clouds.cloudTarget.texture, { flipY: true });
  return { gl, canvas };
}

publish(run);
