// Renders a Nimbus three.js package in headless Chromium (Debian's, driven by playwright-core)
// and writes the frame as PNG, with every console message and shader log beside it.
//
//   node render.mjs PACKAGE_DIR OUT.png [key=value ...]   (width, height, pitch, yaw, fov, pair)
//
// Files are served on 127.0.0.1 only: the package under /pkg/, three.js under /three/, the
// page under /page/. Exits non-zero, saying why, when the page fails or anything was logged.
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { extname, join, normalize, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

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
const types = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.png': 'image/png', '.frag': 'text/plain', '.vert': 'text/plain',
};

const server = createServer(async (req, res) => {
  const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
  if (path === '/favicon.ico') {
    res.writeHead(204).end();
    return;
  }
  const prefix = Object.keys(roots).find((p) => path.startsWith(p));
  const file = prefix && normalize(join(roots[prefix], path.slice(prefix.length)));
  if (!file || !file.startsWith(roots[prefix])) {
    res.writeHead(404).end();
    return;
  }
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[extname(file)] ?? 'application/octet-stream' }).end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const port = server.address().port;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: [
    '--no-sandbox', '--disable-gpu-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--ignore-gpu-blocklist', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run', '--disable-quic',
  ],
});
let status = 0;
try {
  const page = await browser.newPage();
  const logs = [];
  page.on('console', (m) => logs.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  page.on('response', (r) => { if (r.status() >= 400) logs.push(`http ${r.status()}: ${r.url()}`); });
  await page.goto(`http://127.0.0.1:${port}/page/index.html?${query}`);
  await page.waitForFunction(() => window.nimbus && window.nimbus.done, null, { timeout: 120000 });
  const result = await page.evaluate(() => window.nimbus);
  // Chromium's note that a readPixels waits for the GPU is what the timing loop asks for, not
  // a problem of the page.
  const expected = (l) => l.startsWith('debug:') || l.includes('GPU stall due to ReadPixels');
  const problems = [...result.messages, ...logs.filter((l) => !expected(l))];
  if (result.error) problems.push(`error: ${result.error}`);
  await writeFile(`${outPng}.log.json`, JSON.stringify({ renderer: result.renderer, problems }, null, 2));
  if (result.png) await writeFile(outPng, Buffer.from(result.png.split(',')[1], 'base64'));
  console.log(`renderer: ${result.renderer}`);
  if (result.ms !== undefined) console.log(`median ms/frame: ${result.ms.toFixed(1)} (${result.times.map((t) => t.toFixed(0)).join(' ')})`);
  if (problems.length > 0 || !result.png) {
    console.error(problems.join('\n') || 'no image');
    status = 1;
  }
} finally {
  await browser.close();
  server.close();
}
process.exit(status);
