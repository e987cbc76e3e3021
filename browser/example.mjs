// Opens a three.js package's example.html in headless Chromium, with three.js served from this
// folder's node_modules in place of the CDN the page names, and writes two screenshots taken a
// moment apart (the sun moves between them) and the page's messages.
//
//   node example.mjs PACKAGE_DIR OUT_PREFIX
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { extname, join, normalize, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const [pkgDir, prefix] = process.argv.slice(2);
if (!pkgDir || !prefix) {
  console.error('usage: node example.mjs PACKAGE_DIR OUT_PREFIX');
  process.exit(2);
}
const root = resolve(pkgDir);
const three = join(here, 'node_modules', 'three');
const types = { '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json', '.png': 'image/png' };
const server = createServer(async (req, res) => {
  const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
  const file = normalize(join(root, path));
  if (!file.startsWith(root)) return res.writeHead(404).end();
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[extname(file)] ?? 'application/octet-stream' }).end(body);
  } catch {
    res.writeHead(path === '/favicon.ico' ? 204 : 404).end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
    '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic'],
});
let status = 0;
try {
  const page = await browser.newPage({ viewport: { width: 640, height: 360 } });
  // The page imports three.js from unpkg: answer those requests from node_modules.
  await page.route('https://unpkg.com/three@*/**', async (route) => {
    const rest = new URL(route.request().url()).pathname.split('/').slice(2).join('/');
    try {
      await route.fulfill({ body: await readFile(join(three, rest)), contentType: 'text/javascript' });
    } catch {
      await route.fulfill({ status: 404 });
    }
  });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') problems.push(`${m.type()}: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.on('response', (r) => { if (r.status() >= 400) problems.push(`http ${r.status()}: ${r.url()}`); });
  await page.goto(`http://127.0.0.1:${server.address().port}/example.html`);
  await page.waitForSelector('#pair:not(:empty)', { timeout: 120000 });
  await page.waitForTimeout(1500);
  await page.locator('canvas').screenshot({ path: `${prefix}-1.png` });
  await page.waitForTimeout(3000);
  await page.locator('canvas').screenshot({ path: `${prefix}-2.png` });
  const azimuth = await page.inputValue('#azimuth');
  await writeFile(`${prefix}.log.json`, JSON.stringify({ problems, azimuth }, null, 2));
  console.log(`azimuth after the run: ${azimuth}`);
  if (problems.length > 0) {
    console.error(problems.join('\n'));
    status = 1;
  }
} finally {
  await browser.close();
  server.close();
}
process.exit(status);
