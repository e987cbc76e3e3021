// What every driver here shares: files served on 127.0.0.1 only (folders by URL prefix, plus
// generated buffers), and Debian's Chromium started headless with WebGL2 on SwiftShader and no
// background networking (the machine reaches nothing outside).
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { extname, join, normalize } from 'node:path';
import { chromium } from 'playwright-core';

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.png': 'image/png', '.frag': 'text/plain', '.vert': 'text/plain',
};

/**
 * Serves `roots` (URL prefix → folder) and `generated` (path → bytes) on 127.0.0.1 at a free
 * port; resolves to `{ server, origin }`.
 */
export async function serve(roots, generated = {}) {
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    if (path === '/favicon.ico') return res.writeHead(204).end();
    if (generated[path]) {
      return res.writeHead(200, { 'content-type': 'application/octet-stream' }).end(generated[path]);
    }
    const prefix = Object.keys(roots).find((p) => path.startsWith(p));
    const file = prefix && normalize(join(roots[prefix], path.slice(prefix.length)));
    if (!file || !file.startsWith(roots[prefix])) return res.writeHead(404).end();
    try {
      const body = await readFile(file);
      return res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' }).end(body);
    } catch {
      return res.writeHead(404).end();
    }
  });
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  return { server, origin: `http://127.0.0.1:${server.address().port}` };
}

/**
 * Debian's Chromium (or $CHROMIUM), headless, WebGL2 through SwiftShader; with `webgpu`, WebGPU
 * too, on SwiftShader's Vulkan.
 */
export function launch({ webgpu = false } = {}) {
  const gpu = webgpu
    ? ['--enable-unsafe-webgpu', '--enable-features=Vulkan,WebGPU', '--use-vulkan=swiftshader', '--use-webgpu-adapter=swiftshader']
    : [];
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    args: [
      '--no-sandbox', '--disable-gpu-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--ignore-gpu-blocklist', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run', '--disable-quic', ...gpu,
    ],
  });
}

/**
 * Serves `roots` and `generated` (see `serve`), opens one page in a fresh headless Chromium
 * (`pageOptions` as playwright's `newPage` takes them) recording its messages, and runs
 * `drive(page, origin, logs)`; the browser and the server are closed whatever happens. Resolves
 * to what `drive` returns (a driver's exit status).
 */
export async function withPage(roots, generated, pageOptions, drive, launchOptions = {}) {
  const { server, origin } = await serve(roots, generated);
  const browser = await launch(launchOptions);
  try {
    const page = await browser.newPage(pageOptions);
    const logs = [];
    record(page, logs);
    return await drive(page, origin, logs);
  } finally {
    await browser.close();
    server.close();
  }
}

/** Collects a page's console messages, errors and failed requests into `logs`. */
export function record(page, logs) {
  page.on('console', (m) => logs.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  page.on('response', (r) => { if (r.status() >= 400) logs.push(`http ${r.status()}: ${r.url()}`); });
}

/** Chromium's note that a readPixels waits for the GPU is what a timing loop asks for. */
export const expected = (line) => line.startsWith('debug:') || line.includes('GPU stall due to ReadPixels');

/**
 * Waits for a page's `window.nimbus` result, writes its frame to `outPng` and what it logged to
 * `outPng.log.json`, prints the renderer (and the timing, if any), and returns the process
 * status: 1 when the page failed or logged anything unexpected.
 */
export async function report(page, logs, outPng, timeout = Number(process.env.NIMBUS_PAGE_TIMEOUT_MS ?? 120000)) {
  await page.waitForFunction(() => window.nimbus && window.nimbus.done, null, { timeout, polling: 250 });
  const result = await page.evaluate(() => window.nimbus);
  const problems = [...result.messages, ...logs.filter((l) => !expected(l))];
  if (result.error) problems.push(`error: ${result.error}`);
  const log = { renderer: result.renderer, ms: result.ms, times: result.times, problems, values: result.values };
  await writeFile(`${outPng}.log.json`, JSON.stringify(log, null, 2));
  if (result.png) await writeFile(outPng, Buffer.from(result.png.split(',')[1], 'base64'));
  console.log(`renderer: ${result.renderer}`);
  if (result.ms !== undefined) {
    console.log(`median ms/frame: ${result.ms.toFixed(1)} (${result.times.map((t) => t.toFixed(0)).join(' ')})`);
  }
  if (problems.length > 0 || !result.png) {
    console.error(problems.join('\n') || 'no image');
    return 1;
  }
  return 0;
}
