// Renders @takram/three-clouds (CloudsEffect, then AerialPerspectiveEffect with sky, sun light and
// sky light, then AgX tone mapping: the pipeline of takram's own Clouds-Vanilla story) from a
// camera on the ground, with every asset loaded from this server (no CDN), and publishes the
// frame (a PNG data URL), the shader messages and, with bench=N, the median ms/frame on `window`
// the way main.mjs does for Nimbus.
//
// Query: width, height, quality (low|medium|high|ultra), coverage, sun=ELEVATION,AZIMUTH (or
// elevation=, azimuth=; degrees, azimuth clockwise from north), altitude (m above the ellipsoid),
// pitch (up from the horizon), yaw (clockwise from north), fov (vertical, degrees), lat, lon
// (degrees; Tokyo by default), upscale (1/0: takram's temporal upscaling, off by default), frames (drawn before
// the screenshot), bench=N and warmup=M (time N frames after M), exposure, stbn (URL), ground=0
// (no ground disc), albedo=R,G,B (the ground's), clouds=0 (no CloudsEffect: a diagnostic),
// output=opacity (the clouds' opacity as grey, haze off: opacity.mjs).
import * as THREE from 'three';
import { drawOpacity } from './opacity.mjs';
import { publish } from './publish.mjs';
import { canvasRenderer } from './renderer.mjs';
import { timeFrames } from './timing.mjs';
import { EffectComposer, EffectPass, NormalPass, RenderPass, ToneMappingEffect, ToneMappingMode } from 'postprocessing';
import { AerialPerspectiveEffect, PrecomputedTexturesLoader } from '@takram/three-atmosphere';
import { CLOUD_SHAPE_DETAIL_TEXTURE_SIZE, CLOUD_SHAPE_TEXTURE_SIZE, CloudsEffect } from '@takram/three-clouds';
import { DataTextureLoader, Ellipsoid, Geodetic, STBNLoader, parseUint8Array, radians } from '@takram/three-geospatial';

const q = new URLSearchParams(location.search);
const number = (name, fallback) => (q.has(name) ? Number(q.get(name)) : fallback);
const width = number('width', 320);
const height = number('height', 180);
const quality = q.get('quality') ?? 'high';
const [sunElevation, sunAzimuth] = q.has('sun')
  ? q.get('sun').split(',').map(Number)
  : [number('elevation', 35), number('azimuth', 150)];


const node = '/node_modules/';
const cloudsAssets = `${node}@takram/three-clouds/assets/`;
const atmosphereAssets = `${node}@takram/three-atmosphere/assets/`;

// Texture settings as in takram's Clouds-Vanilla story (storybook/src/clouds/Clouds-Vanilla.tsx).
function tile(texture, is3D) {
  if (is3D) {
    texture.format = THREE.RedFormat;
    texture.minFilter = THREE.LinearFilter;
    texture.wrapR = THREE.RepeatWrapping;
  } else {
    texture.minFilter = THREE.LinearMipMapLinearFilter;
  }
  texture.magFilter = THREE.LinearFilter;
  texture.wrapS = THREE.RepeatWrapping;
  texture.wrapT = THREE.RepeatWrapping;
  texture.colorSpace = THREE.NoColorSpace;
  texture.needsUpdate = true;
  return texture;
}

const shapeLoader = (size) => new DataTextureLoader(THREE.Data3DTexture, parseUint8Array, { width: size, height: size, depth: size });

async function run(result) {
  const { messages } = result;
  const { canvas, renderer } = canvasRenderer(result, { depth: false });
  renderer.toneMapping = THREE.NoToneMapping;
  renderer.toneMappingExposure = number('exposure', 10);

  // Assets, all from this server. The precomputed atmosphere comes as the .bin files (half
  // floats); the loader's default format, 'exr', would go through three's EXRLoader.
  const [atmosphere, localWeather, shape, shapeDetail, turbulence, stbn] = await Promise.all([
    new Promise((ok, fail) => new PrecomputedTexturesLoader({ format: 'binary' }).setType(renderer)
      .load(atmosphereAssets, ok, undefined, fail)),
    new THREE.TextureLoader().loadAsync(`${cloudsAssets}local_weather.png`),
    shapeLoader(CLOUD_SHAPE_TEXTURE_SIZE).loadAsync(`${cloudsAssets}shape.bin`),
    shapeLoader(CLOUD_SHAPE_DETAIL_TEXTURE_SIZE).loadAsync(`${cloudsAssets}shape_detail.bin`),
    new THREE.TextureLoader().loadAsync(`${cloudsAssets}turbulence.png`),
    // No stbn.bin is published on npm; takram.mjs serves a generated one (see stbn.mjs).
    new STBNLoader().loadAsync(q.get('stbn') ?? '/generated/stbn.bin'),
  ]);

  // The camera: on the ground at lat/lon, pitched up from the horizon, yawed from north, in the
  // local east-north-up frame of the WGS84 ellipsoid. World space is ECEF (meters).
  const position = new Geodetic(radians(number('lon', 139.7671)), radians(number('lat', 35.6812)), number('altitude', 2)).toECEF();
  const east = new THREE.Vector3();
  const north = new THREE.Vector3();
  const up = new THREE.Vector3();
  Ellipsoid.WGS84.getEastNorthUpVectors(position, east, north, up);
  const enu = (azimuthDeg, elevationDeg) => {
    const a = radians(azimuthDeg);
    const e = radians(elevationDeg);
    return new THREE.Vector3()
      .addScaledVector(east, Math.cos(e) * Math.sin(a))
      .addScaledVector(north, Math.cos(e) * Math.cos(a))
      .addScaledVector(up, Math.sin(e));
  };
  const camera = new THREE.PerspectiveCamera(number('fov', 60), width / height, 1, 1e6);
  camera.position.copy(position);
  camera.up.copy(up);
  camera.lookAt(position.clone().add(enu(number('yaw', 0), number('pitch', 12))));
  camera.updateMatrixWorld();
  const sunDirection = enu(sunAzimuth, sunElevation);

  // The ground (ground=0 leaves it out): a flat disc of radius 100 km, 'altitude' meters below the
  // camera and tangent to the ellipsoid there, of Nimbus's ground albedo; AerialPerspectiveEffect
  // lights it (sunLight, skyLight) from the normal buffer, as it does takram's 3D tiles. With
  // none, everything below the horizon is left black: the sky's GROUND define only adds the
  // inscatter in front of the ellipsoid.
  const scene = new THREE.Scene();
  if (q.get('ground') !== '0') {
    const albedo = (q.get('albedo') ?? '0.1,0.1,0.08').split(',').map(Number);
    const disc = new THREE.Mesh(new THREE.CircleGeometry(1e5, 256),
      new THREE.MeshBasicMaterial({ color: new THREE.Color().setRGB(...albedo, THREE.LinearSRGBColorSpace) }));
    const surface = new Geodetic(radians(number('lon', 139.7671)), radians(number('lat', 35.6812)), 0).toECEF();
    disc.position.copy(surface);
    disc.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(east, north, up));
    scene.add(disc);
  }
  const aerialPerspective = new AerialPerspectiveEffect(camera);
  aerialPerspective.sky = true;
  aerialPerspective.sunLight = true;
  aerialPerspective.skyLight = true;
  const normalPass = new NormalPass(scene, camera);
  aerialPerspective.normalBuffer = normalPass.texture;

  const clouds = new CloudsEffect(camera);
  clouds.qualityPreset = quality;
  clouds.coverage = number('coverage', 0.4);
  clouds.temporalUpscale = q.get('upscale') === '1'; // Off unless upscale=1, as in main.mjs.
  // `output=opacity`: the clouds' opacity in place of the picture (opacity.mjs). The clouds
  // buffer's alpha holds the haze's too, so the haze is off for it (Nimbus's holds the clouds'
  // alone).
  const opacity = q.get('output') === 'opacity';
  if (opacity) clouds.haze = false;
  // CloudsEffect hands its buffers to AerialPerspectiveEffect through 'change' events.
  clouds.events.addEventListener('change', (event) => {
    if (event.property === 'atmosphereOverlay') aerialPerspective.overlay = clouds.atmosphereOverlay;
    if (event.property === 'atmosphereShadow') aerialPerspective.shadow = clouds.atmosphereShadow;
    if (event.property === 'atmosphereShadowLength') aerialPerspective.shadowLength = clouds.atmosphereShadowLength;
  });
  aerialPerspective.sunDirection.copy(sunDirection);
  clouds.sunDirection.copy(sunDirection);

  Object.assign(aerialPerspective, atmosphere);
  Object.assign(clouds, atmosphere);
  clouds.localWeatherTexture = tile(localWeather, false);
  clouds.shapeTexture = tile(shape, true);
  clouds.shapeDetailTexture = tile(shapeDetail, true);
  clouds.turbulenceTexture = tile(turbulence, false);
  clouds.stbnTexture = stbn;
  aerialPerspective.stbnTexture = stbn;

  // Radiance is stored in the frame buffers: half floats, as in takram's examples.
  const composer = new EffectComposer(renderer, { frameBufferType: THREE.HalfFloatType, multisampling: 0 });
  composer.addPass(new RenderPass(scene, camera));
  composer.addPass(normalPass);
  // clouds=0 (a diagnostic) leaves CloudsEffect out: the atmosphere and ground alone.
  composer.addPass(q.get('clouds') === '0' ? new EffectPass(camera, aerialPerspective) : new EffectPass(camera, clouds, aerialPerspective));
  composer.addPass(new EffectPass(camera, new ToneMappingEffect({ mode: ToneMappingMode.AGX })));
  composer.setSize(width, height, false);

  const gl = renderer.getContext();
  const frame = () => {
    composer.render(1 / 60);
    renderer.setRenderTarget(null);
  };
  if (q.has('bench')) {
    // Milliseconds per frame, measured as main.mjs measures Nimbus (timing.mjs).
    Object.assign(result, timeFrames(gl, frame, number('warmup', 3), number('bench', 10)));
  } else {
    for (let i = 0; i < number('frames', 1); i++) frame();
  }
  if (opacity) drawOpacity(renderer, clouds.cloudsPass.outputBuffer);
  return { gl, canvas };
}

publish(run);
