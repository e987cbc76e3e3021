// `output=opacity` on either renderer page: the clouds' opacity (1 − transmittance, the alpha of
// the target the clouds are drawn into) shown as grey over the whole canvas. The benchmark
// matches the two libraries' clouds by it: the share of the light behind them that the clouds
// hide does not depend on how each library lights or tone-maps them, and it does not saturate
// the way a count of pixels that differ from a clear sky does.
import * as THREE from 'three';

/**
 * Draws the alpha of `texture` (a render target's) to the canvas, 0 black to 1 white; `flipY`
 * for a target whose first row is the top of the picture (Nimbus's: its shaders count pixels
 * from the top, as WGSL does).
 */
export function drawOpacity(renderer, texture, { flipY = false } = {}) {
  const material = new THREE.ShaderMaterial({
    uniforms: { map: { value: texture }, flipY: { value: flipY ? 1 : 0 } },
    vertexShader: 'uniform float flipY;\nvarying vec2 vUv;\n'
      + 'void main() { vUv = vec2(uv.x, mix(uv.y, 1.0 - uv.y, flipY)); gl_Position = vec4(position.xy, 0.0, 1.0); }',
    fragmentShader: 'uniform sampler2D map;\nvarying vec2 vUv;\n'
      + 'void main() { gl_FragColor = vec4(vec3(texture2D(map, vUv).a), 1.0); }',
    depthTest: false,
    depthWrite: false,
  });
  const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
  const scene = new THREE.Scene();
  scene.add(quad);
  renderer.setRenderTarget(null);
  renderer.render(scene, new THREE.Camera());
  material.dispose();
  quad.geometry.dispose();
}
