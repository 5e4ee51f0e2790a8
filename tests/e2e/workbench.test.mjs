// The page as a workbench, in headless Chromium: files chosen while the sample loads, the
// file-unit suggestion, switching tools, and a spray plan from patch to robot program.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { unzipSync, strFromU8 } from 'fflate';
import {
  binaryStl, modelsDir, openApp, openAppWithSample, outputDir, paintedPixels, saveDownload, waitForModel, waitForReady,
} from './helpers.mjs';

const text = (page, selector) => page.locator(selector).textContent();

/** Resolves after `ms`; test pacing only, never a pass condition. */
const pause = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A closed box (12 triangles) with the given edge lengths, as a binary STL buffer. */
function boxStl([a, b, c], header = 'box') {
  const p = (i, j, k) => [i * a, j * b, k * c];
  const quads = [
    [p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)], [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)],
    [p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)], [p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)],
    [p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)], [p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)],
  ];
  const tris = [];
  for (const [q0, q1, q2, q3] of quads) tris.push(...q0, ...q1, ...q2, ...q0, ...q2, ...q3);
  return binaryStl(tris, header);
}

test('a file chosen while the engine and the sample are still loading wins over the sample', async () => {
  // Hold the wasm back so the file is chosen before the engine is up, and the sample too.
  let releaseSample;
  const sampleHeld = new Promise((resolve) => { releaseSample = resolve; });
  const app = await openApp({
    beforeGoto: async (page) => {
      await page.route('**/pkg/skinpath_bg.wasm', async (route) => {
        await pause(1500);
        await route.continue();
      });
      await page.route('**/samples/*.stl', async (route) => {
        await sampleHeld;
        await route.continue().catch(() => {}); // the page may have abandoned the request
      });
    },
  });
  try {
    const { page } = app;
    await page.setInputFiles('#file-input', join(modelsDir, 'airplane_10796_pymeshlab.stl'));
    releaseSample();
    await page.waitForFunction(() => document.body.dataset.state === 'ready' && document.body.dataset.model,
      null, { timeout: 60_000, polling: 100 });
    await pause(1500); // time for a late sample to land, if the page still wanted it
    await waitForReady(page);
    assert.equal(await page.evaluate(() => document.body.dataset.model), 'airplane_10796_pymeshlab.stl');
    assert.equal(await text(page, '#model-name'), 'airplane_10796_pymeshlab.stl');
    assert.equal(await text(page, '#stat-triangles'), '10,796');
    assert.doesNotMatch(await page.evaluate(() => location.hash), /sample=bwb/);
    assert.deepEqual(app.consoleErrors, []);
  } finally {
    await app.close();
  }
});

test('a file chosen while the sample downloads, then a later file, each replace what was in flight', async () => {
  let releaseSample;
  const sampleHeld = new Promise((resolve) => { releaseSample = resolve; });
  let sampleRequested;
  const sampleAsked = new Promise((resolve) => { sampleRequested = resolve; });
  const app = await openApp({
    beforeGoto: (page) => page.route('**/samples/*.stl', async (route) => {
      sampleRequested();
      await sampleHeld;
      await route.continue().catch(() => {});
    }),
  });
  try {
    const { page } = app;
    await sampleAsked; // the sample is on its way
    await page.setInputFiles('#file-input', join(modelsDir, 'wingbody_79868_flow360.stl'));
    // A second file while the first is still being read or parsed.
    await page.setInputFiles('#file-input', join(modelsDir, 'airplane_10796_pymeshlab.stl'));
    releaseSample();
    await waitForModel(page, 'airplane_10796_pymeshlab.stl');
    await pause(1500);
    await waitForReady(page);
    assert.equal(await page.evaluate(() => document.body.dataset.model), 'airplane_10796_pymeshlab.stl');
    assert.equal(await text(page, '#stat-triangles'), '10,796');
    assert.deepEqual(app.consoleErrors, []);
  } finally {
    await app.close();
  }
});

let app;
let page;

before(async () => {
  app = await openAppWithSample();
  page = app.page;
});

after(async () => {
  await app?.close();
});

test('an implausible size in the chosen unit brings a one-click unit suggestion', async () => {
  await page.selectOption('#unit-select', 'm');
  // 42,000 units long: 42 km in metres, a 42 m aircraft in millimetres.
  await page.setInputFiles('#file-input', { name: 'box_42000.stl', mimeType: 'model/stl', buffer: boxStl([42000, 3000, 800]) });
  await waitForModel(page, 'box_42000.stl');
  assert.equal(await page.isVisible('#unit-notice'), true);
  assert.match(await text(page, '#unit-notice-text'), /42 km long in metres.*millimetres \(42 m long\)/);
  assert.equal(await text(page, '#unit-suggest-button'), 'Use mm');
  await page.screenshot({ path: join(outputDir, 'e2e-unit-suggestion.png') });
  await page.click('#unit-suggest-button');
  assert.equal(await page.inputValue('#unit-select'), 'mm');
  assert.match(await text(page, '#stat-size'), / mm$/);
  assert.equal(await page.isVisible('#unit-notice'), false);
  assert.match(await page.evaluate(() => location.hash), /unit=mm/);

  // The other way: 0.042 units in millimetres is 42 µm; in metres a 42 m part.
  await page.setInputFiles('#file-input', { name: 'box_small.stl', mimeType: 'model/stl', buffer: boxStl([0.042, 0.003, 0.0008]) });
  await waitForModel(page, 'box_small.stl');
  assert.equal(await text(page, '#unit-suggest-button'), 'Use m');
  // A plausible size asks nothing.
  await page.selectOption('#unit-select', 'm');
  assert.equal(await page.isVisible('#unit-notice'), false);
});

test('tools switch by tab, keep their settings in the URL and across a reload', async () => {
  await page.click('#samples-menu summary');
  await page.click('#samples-list button[data-sample="bwb"]');
  await waitForModel(page, 'bwb_4464_pygeo_ascii.stl');
  assert.equal(await page.isVisible('#seg-form'), true);
  await page.click('#tab-spray');
  assert.equal(await page.getAttribute('#tab-spray', 'aria-selected'), 'true');
  assert.equal(await page.isVisible('#spray-form'), true);
  assert.equal(await page.isVisible('#seg-form'), false);
  assert.equal(await page.isVisible('#export-zip'), false, 'the segmentation exports go with their tab');
  assert.equal(await page.isVisible('#patch-table'), true, 'the patch list is shared');
  await page.fill('#spray-standoff', '300');
  await page.press('#spray-standoff', 'Tab');
  const hash = await page.evaluate(() => location.hash);
  assert.match(hash, /tool=spray/);
  assert.match(hash, /spray\.standoff=300/);
  await page.reload();
  await waitForModel(page, 'bwb_4464_pygeo_ascii.stl');
  assert.equal(await page.getAttribute('#tab-spray', 'aria-selected'), 'true');
  assert.equal(await page.inputValue('#spray-standoff'), '300');
  await page.click('#spray-defaults-button');
  assert.equal(await page.inputValue('#spray-standoff'), '250');
  await page.click('#tab-segment');
  assert.equal(await page.isVisible('#seg-form'), true);
  assert.equal(await page.isVisible('#spray-form'), false);
});

test('the sample aircraft sprays in one click: heat map, figures, chart and a RAPID program', async () => {
  await page.click('#tab-spray');
  assert.match(await text(page, '#spray-patch-label'), /patch \d+ \(the largest\)/);
  const before = await heatPixels(page, 'e2e-canvas-spray-before.png');
  await page.click('#spray-plan-button');
  await page.waitForFunction(() => Number(document.body.dataset.sprayPlans ?? 0) > 0
    || document.getElementById('alert').textContent !== '', null, { timeout: 120_000 });
  await waitForReady(page);
  assert.equal(await text(page, '#alert'), '', 'the engine planned without an error');
  await page.screenshot({ path: join(outputDir, 'e2e-spray.png') });
  // The patch now shows heat-map colours (viridis; unlit, so the pixels are the palette).
  const afterPlan = await heatPixels(page, 'e2e-canvas-spray.png');
  assert.ok(afterPlan - before > 2000, `the heat map is drawn (${before} → ${afterPlan} heat-coloured pixels)`);
  assert.match(await text(page, '#spray-summary'), /\d+ passes [\d.,]+ mm apart/);
  assert.match(await text(page, '#spray-quality'), /Mean thickness[\d.,]+ µm/);
  assert.ok((await page.locator('#spray-chart circle').count()) >= 1, 'one chart point per spacing tried');
  assert.match(await text(page, '#overlay-spray'), /Coating thickness, µm/);

  const rapid = await saveDownload(page, () => page.click('[data-format="rapid"]'));
  const files = rapid.name.endsWith('.zip')
    ? Object.entries(unzipSync(new Uint8Array(rapid.bytes))).map(([name, bytes]) => ({ name, text: strFromU8(bytes) }))
    : [{ name: rapid.name, text: rapid.bytes.toString('utf8') }];
  assert.ok(files.length >= 1);
  for (const f of files) {
    assert.match(f.name, /\.mod$/i);
    assert.match(f.text, /^\s*MODULE\s+\w+/m, `${f.name} opens a module`);
    assert.match(f.text, /^\s*ENDMODULE\s*$/m, `${f.name} closes it`);
  }
  const moves = files.map((f) => f.text.match(/^\s*MoveL\s/gm)?.length ?? 0).reduce((a, b) => a + b, 0);
  assert.ok(moves > 10, `the program moves the gun (${moves} MoveL lines)`);

  // An engine refusal lands in the alert, naming the parameter; the plan on screen stays.
  const summary = await text(page, '#spray-summary');
  await page.uncheck('#spray-search');
  await page.fill('#spray-spacing', '1000000');
  await page.click('#spray-plan-button');
  await page.waitForFunction(() => document.getElementById('alert').textContent !== '');
  await waitForReady(page);
  assert.match(await text(page, '#alert'), /spacing/);
  assert.equal(await text(page, '#spray-summary'), summary);
  await page.click('#alert-dismiss');
  await page.click('#spray-defaults-button');
});

test('no request left the origin and nothing was logged as an error', () => {
  assert.deepEqual(app.foreignRequests, []);
  assert.deepEqual(app.consoleErrors, []);
});

/** Canvas pixels within a small distance of the viridis palette (read back from a screenshot). */
async function heatPixels(p, file) {
  await paintedPixels(p, join(outputDir, file)); // the screenshot on disk, for people
  const png = await p.locator('#viewer canvas').screenshot();
  return p.evaluate(async (bytes) => {
    const bitmap = await createImageBitmap(new Blob([new Uint8Array(bytes)], { type: 'image/png' }));
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = canvas.getContext('2d');
    ctx.drawImage(bitmap, 0, 0);
    const { data } = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
    const stops = ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962', '#addc30', '#fde725']
      .map((h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16)));
    // The palette between stops: 8 steps each.
    const palette = [];
    for (let s = 0; s + 1 < stops.length; s++) {
      for (let k = 0; k < 8; k++) palette.push(stops[s].map((c, j) => c + ((stops[s + 1][j] - c) * k) / 8));
    }
    palette.push(stops.at(-1));
    let count = 0;
    for (let i = 0; i < data.length; i += 4) {
      for (const c of palette) {
        if (Math.abs(data[i] - c[0]) + Math.abs(data[i + 1] - c[1]) + Math.abs(data[i + 2] - c[2]) <= 12) {
          count++;
          break;
        }
      }
    }
    return count;
  }, [...png]);
}
