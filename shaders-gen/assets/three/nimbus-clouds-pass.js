// A three.js EffectComposer pass drawing Nimbus clouds (sky, clouds, ground) into the
// composer's buffer, as a background for the passes after it.
//
//   const clouds = await NimbusClouds.load(new URL('./', import.meta.url));
//   composer.addPass(new NimbusCloudsPass(clouds, camera));

import { Pass } from 'three/addons/postprocessing/Pass.js';

export class NimbusCloudsPass extends Pass {
  constructor(clouds, camera) {
    super();
    this.clouds = clouds;
    this.camera = camera;
  }

  setSize(width, height) {
    this.clouds.setSize(width, height);
  }

  render(renderer, writeBuffer) {
    this.clouds.setCamera(this.camera);
    this.clouds.render(renderer, this.renderToScreen ? null : writeBuffer);
  }

  dispose() {
    this.clouds.dispose();
  }
}
