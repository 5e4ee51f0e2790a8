// The page as its users meet it, in headless Chromium: the built site in dist/ (run
// `npm run build` first), real aircraft meshes from ../shared/models, screenshots in test-output/.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import {
  binaryStl, importMapHash, modelsDir, openAppWithSample, outputDir, paintedPixels, repoRoot, waitForModel, waitForReady,
} from './helpers.mjs';

let app;
let page;

before(async () => {
  // First visit: the default sample opens and is segmented without any action.
  app = await openAppWithSample();
  page = app.page;
});

after(async () => {
  await app?.close();
});

const rowCount = () => page.locator('#patch-rows tr[data-patch-id]').count();
const text = (selector) => page.locator(selector).textContent();

test('the page opens with the sample aircraft segmented and drawn', async () => {
  assert.ok((await rowCount()) > 0, 'patch rows are listed');
  assert.equal(await text('#stat-triangles'), '4,464');
  assert.match(await text('#threshold-value'), /α = 0\.35 rad/);
  assert.match(await text('#stat-memory'), /MiB|KiB|GiB/);
  const { painted, total } = await paintedPixels(page, join(outputDir, 'e2e-canvas-sample.png'));
  assert.ok(painted > total * 0.03, `the canvas shows the model (${painted} of ${total} pixels painted)`);
  await page.screenshot({ path: join(outputDir, 'e2e-sample.png') });
});

test('a lost WebGL context comes back with the model drawn again', async () => {
  // The page lets go of the model's arrays once they are on the GPU, so a restored context
  // asks the worker for them again.
  const before = Number(await page.evaluate(() => document.body.dataset.segmentations));
  await page.evaluate(() => new Promise((resolve) => {
    const canvas = document.querySelector('#viewer canvas');
    const lose = canvas.getContext('webgl2').getExtension('WEBGL_lose_context');
    canvas.addEventListener('webglcontextlost', () => setTimeout(() => lose.restoreContext(), 100), { once: true });
    canvas.addEventListener('webglcontextrestored', () => resolve(), { once: true });
    lose.loseContext();
  }));
  await page.waitForTimeout(200); // the redraw job starts
  await waitForReady(page);
  const { painted, total } = await paintedPixels(page, join(outputDir, 'e2e-canvas-restored.png'));
  assert.ok(painted > total * 0.03, `the canvas shows the model again (${painted} of ${total} pixels painted)`);
  assert.ok((await rowCount()) > 0, 'the patches are kept');
  assert.equal(Number(await page.evaluate(() => document.body.dataset.segmentations)), before, 'not re-segmented');
});

test('the content security policy allows exactly the import map', () => {
  // The page forbids inline scripts except the import map, by hash: keep them in step.
  const html = readFileSync(join(repoRoot, 'www', 'index.html'), 'utf8');
  const hash = importMapHash(html);
  assert.ok(hash, 'index.html has an import map');
  assert.ok(html.includes(`'sha256-${hash}'`),
    `the CSP in www/index.html must list the import map's hash 'sha256-${hash}'`);
});

test('an aircraft opens through the file input', async () => {
  await page.setInputFiles('#file-input', join(modelsDir, 'airplane_10796_pymeshlab.stl'));
  await waitForModel(page, 'airplane_10796_pymeshlab.stl');
  assert.equal(await text('#stat-triangles'), '10,796');
  assert.equal(await text('#model-name'), 'airplane_10796_pymeshlab.stl');
  assert.ok((await rowCount()) > 0);
  const { painted, total } = await paintedPixels(page, join(outputDir, 'e2e-canvas-airplane.png'));
  assert.ok(painted > total * 0.02, `the canvas shows the airplane (${painted} of ${total} pixels)`);
  await page.screenshot({ path: join(outputDir, 'e2e-airplane.png') });
});

test('an ASCII file opens through the file input too (the worker gathers its text)', async () => {
  // A user's file is streamed into the engine; an ASCII one is gathered whole and read.
  const bytes = readFileSync(join(modelsDir, 'bwb_4464_pygeo_ascii.stl'));
  await page.setInputFiles('#file-input', { name: 'bwb_as_a_user_file.stl', mimeType: 'model/stl', buffer: bytes });
  await waitForModel(page, 'bwb_as_a_user_file.stl');
  assert.equal(await text('#stat-triangles'), '4,464');
  assert.ok((await rowCount()) > 0);
  assert.match(await text('#status'), /^Opened bwb_as_a_user_file\.stl in /);
});

test('an aircraft opens by drag and drop on the viewport', async () => {
  const bytes = readFileSync(join(modelsDir, 'wingbody_79868_flow360.stl')).toString('base64');
  await page.evaluate((base64) => {
    const binary = atob(base64);
    const data = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) data[i] = binary.charCodeAt(i);
    const transfer = new DataTransfer();
    transfer.items.add(new File([data], 'wingbody_79868_flow360.stl', { type: 'model/stl' }));
    const target = document.getElementById('viewport');
    for (const type of ['dragenter', 'dragover', 'drop']) {
      target.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }
  }, bytes);
  await waitForModel(page, 'wingbody_79868_flow360.stl');
  assert.equal(await text('#stat-triangles'), '79,868');
  assert.ok((await rowCount()) > 0);
  assert.equal(await page.locator('#drop-overlay').isHidden(), true, 'the drop hint is gone');
  const { painted, total } = await paintedPixels(page, join(outputDir, 'e2e-canvas-wingbody.png'));
  assert.ok(painted > total * 0.02, `the canvas shows the wing-body (${painted} of ${total} pixels)`);
  await page.screenshot({ path: join(outputDir, 'e2e-wingbody.png') });
});

test('the derived threshold follows the parameters as they are typed', async () => {
  await page.check('input[name="criterion"][value="grind"]');
  const first = await text('#threshold-value');
  assert.match(first, /^κ = /);
  await page.fill('input[name="contactWidth"]', '10');
  const second = await text('#threshold-value');
  assert.match(second, /^κ = /);
  assert.notEqual(second, first, 'a new contact width gives a new curvature threshold');
  // Tool lengths are in mm whatever the file's unit: d 0.5 mm, δ 0.8, Lc 10 mm give
  // κ = 2·0.5·(1 − 0.64)/10² = 0.0036 1/mm = 3.6 1/m.
  const unit = await page.locator('#unit-select').inputValue();
  await page.fill('input[name="indentationDepth"]', '0.5');
  await page.fill('input[name="minPressureRatio"]', '0.8');
  await page.selectOption('#unit-select', 'm');
  await page.waitForFunction(() => document.getElementById('threshold-value').textContent === 'κ = 3.6 1/m');
  await page.selectOption('#unit-select', 'mm');
  await page.waitForFunction(() => document.getElementById('threshold-value').textContent === 'κ = 0.0036 1/mm');
  await page.selectOption('#unit-select', unit);

  // Out of range: flagged inline, no threshold, Segment disabled.
  await page.fill('input[name="minPressureRatio"]', '1.5');
  assert.equal(await text('#threshold-value'), '–');
  assert.equal(await page.getAttribute('input[name="minPressureRatio"]', 'aria-invalid'), 'true');
  assert.ok((await text('#params-error')).length > 10, 'the problem is named');
  assert.equal(await page.isDisabled('#segment-button'), true);
  await page.screenshot({ path: join(outputDir, 'e2e-invalid-parameter.png') });
  await page.fill('input[name="minPressureRatio"]', '0.8');
  assert.equal(await page.getAttribute('input[name="minPressureRatio"]', 'aria-invalid'), 'false');
  assert.equal(await text('#params-error'), '');

  // Spraying, in degrees: α = acos((Qd − ΔQd) / Qmin) = acos(90 / 96) = 20.36°.
  await page.selectOption('#angle-unit-select', 'deg');
  await page.check('input[name="criterion"][value="spray"]');
  await page.fill('input[name="meanThickness"]', '100');
  await page.fill('input[name="allowedDeviation"]', '10');
  await page.fill('input[name="minThickness"]', '96');
  assert.match(await text('#threshold-value'), /20\.36°/);

  // Back to the paper's angle criterion; committing the form re-segments.
  const before = Number(await page.evaluate(() => document.body.dataset.segmentations));
  await page.check('input[name="criterion"][value="angle"]');
  await page.fill('input[name="angleThreshold"]', '20');
  await page.press('input[name="angleThreshold"]', 'Enter');
  await page.waitForFunction((n) => Number(document.body.dataset.segmentations) > n, before);
  await waitForReady(page);
  assert.match(await text('#threshold-value'), /α = 0\.3491 rad \(20°\)/);
  assert.ok((await rowCount()) > 0);
  assert.match(await page.evaluate(() => location.hash), /criterion=angle&angleThreshold=0\.349/);
});

test('clicking the model selects its patch row, and a row highlights its patch', async () => {
  const canvas = await page.locator('#viewer canvas').boundingBox();
  // Hover around the middle of the view, where the fitted model is, until a patch answers.
  let point = null;
  for (const [dx, dy] of [[0, 0], [40, 0], [-40, 0], [0, 40], [0, -40], [80, 20], [-80, -20], [120, 0], [-120, 0]]) {
    const x = canvas.x + canvas.width / 2 + dx;
    const y = canvas.y + canvas.height / 2 + dy;
    await page.mouse.move(x, y);
    const shown = await page.waitForFunction(() => /^Patch/.test(document.getElementById('hover-tip').textContent)
      && !document.getElementById('hover-tip').hidden, null, { timeout: 3000 }).then(() => true, () => false);
    if (shown) {
      point = { x, y };
      break;
    }
  }
  assert.ok(point, 'hovering the model shows a patch tooltip');
  const id = (await text('#hover-tip')).match(/Patch (\d+)/)[1];
  await page.mouse.click(point.x, point.y);
  await page.waitForSelector(`#patch-rows tr[data-patch-id="${id}"][aria-selected="true"]`);
  // The other way round: a row selects, keyboard moves on, the export follows the selection.
  await page.click('#patch-rows tr[data-patch-id="0"] td:nth-child(2)');
  assert.equal(await page.getAttribute('#patch-rows tr[data-patch-id="0"]', 'aria-selected'), 'true');
  assert.equal(await page.isEnabled('#export-selected'), true);
  if ((await rowCount()) > 1) {
    await page.keyboard.press('ArrowDown');
    assert.equal(await page.locator('#patch-rows tr[aria-selected="true"]').count(), 1);
    assert.notEqual(await page.getAttribute('#patch-rows tr[aria-selected="true"]', 'data-patch-id'), '0');
  }
  // Isolate and show again.
  await page.keyboard.press('i');
  const hidden = await page.locator('#patch-rows tr.is-hidden').count();
  assert.equal(hidden, (await rowCount()) - 1, 'isolating hides every other patch');
  await page.screenshot({ path: join(outputDir, 'e2e-isolated.png') });
  await page.click('#show-all-button');
  assert.equal(await page.locator('#patch-rows tr.is-hidden').count(), 0);
});

test('the patches export as STL, ZIP, CSV and JSON', async () => {
  const save = async (button) => {
    const [download] = await Promise.all([page.waitForEvent('download'), page.click(button)]);
    return { name: download.suggestedFilename(), bytes: readFileSync(await download.path()) };
  };
  const rows = await rowCount();
  const selectedId = Number(await page.getAttribute('#patch-rows tr[aria-selected="true"]', 'data-patch-id'));
  const triangles = Number((await page.locator('#patch-rows tr[aria-selected="true"] td').nth(1).textContent()).replace(/,/g, ''));

  const stl = await save('#export-selected');
  assert.equal(stl.name, `wingbody_79868_flow360_patch${selectedId}.stl`);
  assert.equal(stl.bytes.readUInt32LE(80), triangles);
  assert.equal(stl.bytes.length, 84 + 50 * triangles);

  const zip = await save('#export-zip');
  assert.equal(zip.name, 'wingbody_79868_flow360_patches.zip');
  assert.equal(zip.bytes.readUInt32LE(0), 0x04034b50, 'a zip archive');
  assert.equal(zip.bytes.toString('latin1').split('wingbody_79868_flow360_patch').length - 1, 2 * rows,
    'one STL per patch (each name appears in a local header and the directory)');

  const csv = (await save('#export-csv')).bytes.toString('utf8').trim().split(/\r?\n/);
  const header = csv.findIndex((line) => line.startsWith('patch_id,'));
  assert.ok(csv.slice(0, header).some((line) => line.includes('angleThreshold')), 'parameters in the CSV preamble');
  assert.equal(csv.length - header - 1, rows);

  const json = JSON.parse((await save('#export-json')).bytes.toString('utf8'));
  assert.equal(json.patches.length, rows);
  assert.equal(json.model.triangles, 79868);
  assert.equal(json.parameters.thetaMax, 1);
  assert.equal(typeof json.parameters.angleThreshold, 'number');
  for (const p of json.patches) {
    assert.equal(p.normal.length, 3);
    assert.ok(p.area > 0 && p.maxDeviation >= 0);
  }
});

test('a malformed file is refused with a message and the model stays', async () => {
  const rowsBefore = await rowCount();
  const truncated = binaryStl(new Array(9 * 37).fill(0).map((_, i) => i % 7), 'truncated');
  truncated.writeUInt32LE(1200, 80); // the header promises far more triangles than follow
  await page.setInputFiles('#file-input', { name: 'truncated.stl', mimeType: 'model/stl', buffer: truncated });
  await page.waitForFunction(() => document.getElementById('alert').textContent.length > 0);
  await waitForReady(page);
  const alert = await text('[role="alert"]');
  assert.match(alert, /truncated\.stl/);
  assert.match(alert, /1200/, `the alert says what is wrong: ${alert}`);
  assert.doesNotMatch(alert, /unreachable|RuntimeError|\bat \S+:\d+|wasm-function/i);
  assert.equal(await text('#model-name'), 'wingbody_79868_flow360.stl');
  assert.equal(await rowCount(), rowsBefore, 'the patches of the model on screen stay');
  await page.screenshot({ path: join(outputDir, 'e2e-malformed.png') });

  // The engine keeps working afterwards: an empty file gets its own message.
  await page.setInputFiles('#file-input', { name: 'empty.stl', mimeType: 'model/stl', buffer: Buffer.alloc(0) });
  await page.waitForFunction(() => document.getElementById('alert').textContent.includes('empty.stl'));
  await waitForReady(page);
  assert.equal(await text('#model-name'), 'wingbody_79868_flow360.stl');
  await page.click('#alert-dismiss');
});

test('settings survive a reload and travel in the URL', async () => {
  await page.selectOption('#unit-select', 'm');
  await page.fill('input[name="minAreaPercent"]', '5');
  await page.press('input[name="minAreaPercent"]', 'Tab');
  const hash = await page.evaluate(() => location.hash);
  assert.match(hash, /minAreaRatio=0\.05/);
  assert.match(hash, /unit=m/);
  await page.reload();
  await waitForModel(page, 'bwb_4464_pygeo_ascii.stl'); // user files are not kept; the last sample reopens
  assert.equal(await page.inputValue('input[name="minAreaPercent"]'), '5');
  assert.equal(await page.inputValue('#unit-select'), 'm');
  assert.match(await text('#stat-area'), / m²$/);
});

test('the samples menu switches models', async () => {
  await page.click('#samples-menu summary');
  await page.click('#samples-list button[data-sample="orion"]');
  await waitForModel(page, 'orion_51736_nasa.stl');
  assert.equal(await text('#stat-triangles'), '51,736');
  assert.ok((await rowCount()) > 0);
  assert.match(await page.evaluate(() => location.hash), /sample=orion/);
  await page.screenshot({ path: join(outputDir, 'e2e-orion.png') });
  // Standard views by keyboard; the view still shows the model.
  await page.locator('body').press('1');
  const { painted } = await paintedPixels(page, join(outputDir, 'e2e-canvas-orion-top.png'));
  assert.ok(painted > 1000);
});

test('no request left the origin and nothing was logged as an error', () => {
  assert.deepEqual(app.foreignRequests, []);
  assert.deepEqual(app.consoleErrors, []);
});
