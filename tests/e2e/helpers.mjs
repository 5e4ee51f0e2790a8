// Shared by the browser tests: launching Chromium, serving dist/, and making test STL files.
import { chromium } from 'playwright-core';
import { createHash } from 'node:crypto';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../../scripts/serve.mjs';

export const repoRoot = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const modelsDir = join(repoRoot, '..', 'shared', 'models');
export const outputDir = join(repoRoot, 'test-output');
mkdirSync(outputDir, { recursive: true });

// Without the background-networking flags Chromium tries to reach the network.
const CHROMIUM_ARGS = [
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--no-first-run', '--disable-quic',
];

/**
 * Serves dist/ and opens a page on it. Records every request that leaves the origin and
 * every console error or uncaught exception, for the tests to assert on at the end.
 */
export async function openApp({ viewport = { width: 1400, height: 860 }, hash = '', beforeGoto } = {}) {
  const { server, url } = await serve(join(repoRoot, 'dist'), 0);
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
  const context = await browser.newContext({ viewport, acceptDownloads: true });
  const page = await context.newPage();
  const foreignRequests = [];
  const consoleErrors = [];
  page.on('request', (request) => {
    const u = request.url();
    // data: and blob: URLs never leave the machine (favicon, downloads).
    if (!u.startsWith(url) && !u.startsWith('data:') && !u.startsWith('blob:')) foreignRequests.push(u);
  });
  page.on('console', (message) => {
    if (message.type() === 'error') consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(`uncaught: ${error.message}`));
  await beforeGoto?.(page, url); // e.g. routes that hold back a response
  await page.goto(url + hash);
  const close = async () => {
    await browser.close();
    await new Promise((done) => server.close(done));
  };
  return { page, url, browser, foreignRequests, consoleErrors, close };
}

/** Opens the page on a first visit and waits until the default sample is segmented. */
export async function openAppWithSample(options) {
  const app = await openApp(options);
  await waitForModel(app.page, 'bwb_4464_pygeo_ascii.stl');
  return app;
}

/** Waits until the page is idle with `name` on screen (body data attributes set by main.js). */
export async function waitForModel(page, name, timeout = 60_000) {
  await page.waitForFunction(
    (n) => document.body.dataset.state === 'ready' && document.body.dataset.model === n,
    name, { timeout, polling: 100 });
}

export async function waitForReady(page, timeout = 60_000) {
  await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout, polling: 100 });
}

/** Counts canvas pixels that differ from the viewport background (read back from a screenshot). */
export async function paintedPixels(page, screenshotPath) {
  const png = await page.locator('#viewer canvas').screenshot({ path: screenshotPath });
  return page.evaluate(async (bytes) => {
    const bitmap = await createImageBitmap(new Blob([new Uint8Array(bytes)], { type: 'image/png' }));
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = canvas.getContext('2d');
    ctx.drawImage(bitmap, 0, 0);
    const { data } = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
    const [r0, g0, b0] = [0xe9, 0xed, 0xf1]; // viewer.js BACKGROUND
    let painted = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - r0) + Math.abs(data[i + 1] - g0) + Math.abs(data[i + 2] - b0) > 24) painted++;
    }
    return { painted, total: data.length / 4 };
  }, [...png]);
}

/** A binary STL header + count + triangles, from flat float triples (9 per triangle). */
export function binaryStl(triangles, header = 'test') {
  const count = triangles.length / 9;
  const buffer = Buffer.alloc(84 + 50 * count);
  buffer.write(header.slice(0, 80), 0, 'latin1');
  buffer.writeUInt32LE(count, 80);
  for (let t = 0; t < count; t++) {
    for (let k = 0; k < 9; k++) buffer.writeFloatLE(triangles[9 * t + k], 84 + 50 * t + 12 + 4 * k);
  }
  return buffer;
}

/**
 * A closed torus as binary STL, 2·around·tube triangles (around = 1000, tube = 500 gives
 * one million), written to test-output/ and reused while the same size is asked for.
 */
export function torusStl(around, tube, fileName) {
  const path = join(outputDir, fileName);
  const count = 2 * around * tube;
  const buffer = Buffer.alloc(84 + 50 * count);
  buffer.write('torus for the skinpath browser tests', 0, 'latin1');
  buffer.writeUInt32LE(count, 80);
  const R = 10;
  const r = 3;
  const point = (i, j) => {
    const u = (2 * Math.PI * (i % around)) / around;
    const v = (2 * Math.PI * (j % tube)) / tube;
    return [(R + r * Math.cos(v)) * Math.cos(u), (R + r * Math.cos(v)) * Math.sin(u), r * Math.sin(v)];
  };
  let offset = 84;
  const put = (a, b, c) => {
    offset += 12; // normal left zero: readers recompute it from the winding
    for (const p of [a, b, c]) for (const x of p) { buffer.writeFloatLE(x, offset); offset += 4; }
    offset += 2;
  };
  for (let i = 0; i < around; i++) {
    for (let j = 0; j < tube; j++) {
      const a = point(i, j);
      const b = point(i + 1, j);
      const c = point(i + 1, j + 1);
      const d = point(i, j + 1);
      put(a, b, c);
      put(a, c, d);
    }
  }
  writeFileSync(path, buffer);
  return path;
}

/** sha256 (base64) of the import map in index.html, which the page's CSP must list. */
export function importMapHash(html) {
  const script = html.match(/<script type="importmap">([\s\S]*?)<\/script>/);
  return script ? createHash('sha256').update(script[1]).digest('base64') : null;
}

/** Waits for the next download started by `action`; resolves to { name, bytes }. */
export async function saveDownload(page, action, timeout = 60_000) {
  const [download] = await Promise.all([page.waitForEvent('download', { timeout }), action()]);
  return { name: download.suggestedFilename(), bytes: readFileSync(await download.path()) };
}

export function readText(path) {
  return readFileSync(path, 'utf8');
}
