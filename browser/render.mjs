// Renders a Nimbus three.js package in headless Chromium (Debian's, driven by playwright-core)
// and writes the frame as PNG, with every console message and shader log beside it.
//
//   node render.mjs PACKAGE_DIR OUT.png [key=value ...]   (width, height, pitch, yaw, fov, pair,
//                                                          sun, wind, weather, time, frames, upscale,
//                                                          altitude; page=scene: tower, log, depth)
//
// Files are served on 127.0.0.1 only: the package under /pkg/, three.js under /three/, the
// page under /page/. Exits non-zero, saying why, when the page fails or anything was logged.
import { join, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { report, withPage } from './serve.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const [pkgDir, outPng, ...rest] = process.argv.slice(2);
if (!pkgDir || !outPng) {
  console.error('usage: node render.mjs PACKAGE_DIR OUT.png [width=160 height=90 pitch=12 yaw=0 fov=60 pair=NAME]');
  process.exit(2);
}
const query = new URLSearchParams(rest.map((kv) => kv.split('=')));
const roots = {
  '/pkg/': resolve(pkgDir),
  '/three/': join(here, 'node_modules', 'three'),
  '/page/': join(here, 'page'),
};
// `page=webgpu`: the webgpu package through its own host module, on Chromium's WebGPU.
const webgpu = query.get('page') === 'webgpu';
const status = await withPage(roots, {}, {}, async (page, origin, logs) => {
  // `page=scene`: the clouds inside a three.js scene (page/scene.html); the package alone
  // otherwise.
  const name = query.get('page') ?? 'index';
  await page.goto(`${origin}/page/${name}.html?${query}`);
  return report(page, logs, outPng);
}, { webgpu });
process.exit(status);
