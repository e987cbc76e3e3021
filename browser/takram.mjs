// Renders @takram/three-clouds (with @takram/three-atmosphere, vanilla three.js + postprocessing)
// in the same headless Chromium as render.mjs, so that it can be timed against Nimbus in one run,
// and writes the frame as PNG with every console message and shader log beside it (OUT.png.log.json).
//
//   node takram.mjs OUT.png [key=value ...]
//     width=320 height=180 quality=low|medium|high|ultra coverage=0.4 sun=ELEVATION,AZIMUTH
//     altitude=2 pitch=12 yaw=0 fov=60 lat=35.6812 lon=139.7671 upscale=0|1 frames=1
//     bench=N warmup=M exposure=10 ground=1 albedo=0.1,0.1,0.08 clouds=1 stbn=URL
//
// Files are served on 127.0.0.1 only: this folder's node_modules under /node_modules/ (three,
// postprocessing and takram's packages with their assets), the page under /page/, and a
// spatiotemporal blue noise texture made by stbn.mjs under /generated/stbn.bin (npm ships none).
// Exits non-zero, saying why, when the page fails or anything was logged.
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { report, withPage } from './serve.mjs';
import { makeSTBN } from './stbn.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const [outPng, ...rest] = process.argv.slice(2);
if (!outPng || outPng.includes('=')) {
  console.error('usage: node takram.mjs OUT.png [width=320 height=180 quality=high coverage=0.4 sun=35,150 '
    + 'altitude=2 pitch=12 yaw=0 fov=60 upscale=0 frames=1 bench=N warmup=M]');
  process.exit(2);
}
const query = new URLSearchParams(rest.map((kv) => kv.split('=')));
const roots = {
  '/node_modules/': join(here, 'node_modules'),
  '/page/': join(here, 'page'),
};
const generated = { '/generated/stbn.bin': Buffer.from(makeSTBN()) };
const status = await withPage(roots, generated, {}, async (page, origin, logs) => {
  // Nothing but this server: any other request (a CDN, GitHub's media host) is refused and reported.
  await page.route((url) => url.hostname !== '127.0.0.1', (route) => {
    logs.push(`blocked: ${route.request().url()}`);
    route.abort();
  });
  await page.goto(`${origin}/page/takram.html?${query}`);
  return report(page, logs, outPng, Number(process.env.TIMEOUT_MS ?? 600000));
});
process.exit(status);
