// The WebGL2 renderer every three.js test page draws with: a canvas of the query's size on the
// page, one pixel per texel, its buffer kept for the screenshot, and every shader error three
// reports added to the page's messages (so the driver fails the run).
import * as THREE from 'three';
import { height, width } from './query.mjs';

/** A WebGLRenderer on a new canvas; `options` add to (or override) the page defaults. */
export function canvasRenderer(result, options = {}) {
  const canvas = document.createElement('canvas');
  document.body.appendChild(canvas);
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true, ...options });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  renderer.debug.checkShaderErrors = true;
  renderer.debug.onShaderError = (gl, program, vs, fs) => {
    result.messages.push(`shader error: ${gl.getProgramInfoLog(program)} ${gl.getShaderInfoLog(vs)} ${gl.getShaderInfoLog(fs)}`);
  };
  return { canvas, renderer };
}
