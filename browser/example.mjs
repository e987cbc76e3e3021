// Opens a three.js package's example.html in headless Chromium, with three.js served from this
// folder's node_modules in place of the CDN the page names, and writes two screenshots taken a
// moment apart (the sun moves between them) and the page's messages.
//
//   node example.mjs PACKAGE_DIR OUT_PREFIX [PAGE]
//
// PAGE is example.html by default; tower.html (packages built with --enable scene-depth) is
// waited for until it has drawn two frames.
import { readFile, writeFile } from 'node:fs/promises';
import { join, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { expected, withPage } from './serve.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const [pkgDir, prefix, pageName = 'example.html'] = process.argv.slice(2);
if (!pkgDir || !prefix) {
  console.error('usage: node example.mjs PACKAGE_DIR OUT_PREFIX');
  process.exit(2);
}
const three = join(here, 'node_modules', 'three');
const viewport = { viewport: { width: 640, height: 360 } };
const status = await withPage({ '/': resolve(pkgDir) }, {}, viewport, async (page, origin, logs) => {
  // The page imports three.js from unpkg: answer those requests from node_modules.
  await page.route('https://unpkg.com/three@*/**', async (route) => {
    const rest = new URL(route.request().url()).pathname.split('/').slice(2).join('/');
    try {
      await route.fulfill({ body: await readFile(join(three, rest)), contentType: 'text/javascript' });
    } catch {
      await route.fulfill({ status: 404 });
    }
  });
  await page.goto(`${origin}/${pageName}`);
  await page.waitForSelector('#pair:not(:empty), body[data-frames]', { timeout: 120000 });
  await page.waitForTimeout(1500);
  // A page screenshot clipped to the canvas, not the canvas element's own: that one first waits
  // for the element to hold still over two animation frames, and a SwiftShader frame on a busy
  // machine can take longer than its 30 s wait (a failed CI run saw exactly that).
  const box = await page.locator('canvas').boundingBox();
  const shoot = (path) => page.screenshot({ path, clip: box, timeout: 120000 });
  await shoot(`${prefix}-1.png`);
  await page.waitForTimeout(3000);
  await shoot(`${prefix}-2.png`);
  const azimuth = (await page.$('#azimuth')) ? await page.inputValue('#azimuth') : null;
  const frames = await page.evaluate(() => document.body.dataset.frames ?? null);
  const problems = logs.filter((l) => /^(error|warning|pageerror|http)/.test(l) && !expected(l));
  await writeFile(`${prefix}.log.json`, JSON.stringify({ problems, azimuth, frames }, null, 2));
  console.log(`azimuth after the run: ${azimuth}; frames drawn: ${frames}`);
  if (problems.length > 0) {
    console.error(problems.join('\n'));
    return 1;
  }
  return 0;
});
process.exit(status);
