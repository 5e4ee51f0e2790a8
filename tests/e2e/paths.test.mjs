// The Paths tool in headless Chromium on the paper's cylinder (R 50 mm, length 120 mm, open
// ends): a section plane z = const as source gives closed rings 10 mm apart up and down the
// cylinder; the table, the colour map and the RAPID export follow; a bad spacing is refused
// in the form and a source that misses the surface is reported with the result kept.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { binaryStl, openAppWithSample, outputDir, paintedPixels, saveDownload, waitForModel, waitForReady } from './helpers.mjs';

const R = 50;
const L = 120;

/** An open cylinder about z, `around` × `along` quads split in two triangles each. */
function cylinderStl(around, along) {
  const tris = [];
  const p = (i, j) => {
    const u = (2 * Math.PI * (i % around)) / around;
    return [R * Math.cos(u), R * Math.sin(u), (L * j) / along];
  };
  for (let i = 0; i < around; i++) {
    for (let j = 0; j < along; j++) {
      tris.push(...p(i, j), ...p(i + 1, j), ...p(i + 1, j + 1), ...p(i, j), ...p(i + 1, j + 1), ...p(i, j + 1));
    }
  }
  return binaryStl(tris, 'cylinder for the paths test');
}

let app;
/** The engine's memory shown with the model before the tool was opened. */
let memoryBefore;
before(async () => {
  app = await openAppWithSample();
  const { page } = app;
  await page.setInputFiles('#file-input', { name: 'cylinder.stl', mimeType: 'model/stl', buffer: cylinderStl(96, 24) });
  await waitForModel(page, 'cylinder.stl');
  await page.selectOption('#unit-select', 'mm');
  await waitForReady(page);
  memoryBefore = await page.textContent('#stat-memory');
  await page.click('#tab-paths');
});
after(async () => {
  await app?.close();
});

/** Canvas pixels near viridis' dark end #440154 (no patch colour comes near it). */
async function purplePixels(page) {
  const png = await page.locator('#viewer canvas').screenshot();
  return page.evaluate(async (bytes) => {
    const bitmap = await createImageBitmap(new Blob([new Uint8Array(bytes)], { type: 'image/png' }));
    const c = new OffscreenCanvas(bitmap.width, bitmap.height);
    const g = c.getContext('2d');
    g.drawImage(bitmap, 0, 0);
    const { data } = g.getImageData(0, 0, bitmap.width, bitmap.height);
    let count = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - 0x44) + Math.abs(data[i + 1] - 0x01) + Math.abs(data[i + 2] - 0x54) < 60) count++;
    }
    return count;
  }, [...png]);
}

const rows = (page) => page.locator('#paths-table tbody tr');

/**
 * Opens `buffer` as `name` (in mm) and sets the Paths tool to a section plane normal to z
 * through the model's centre, on the whole mesh, passes `spacing` mm apart by `method`.
 */
async function planeAcross(page, name, buffer, spacing, method) {
  await page.setInputFiles('#file-input', { name, mimeType: 'model/stl', buffer });
  await waitForModel(page, name);
  await page.selectOption('#unit-select', 'mm');
  await waitForReady(page);
  await page.click('#tab-paths');
  await page.check('#paths-form input[name="source"][value="plane"]');
  await page.check('#paths-form input[name="scope"][value="mesh"]');
  await page.selectOption('#paths-axis', 'z');
  await page.check('#paths-form input[name="spacingMode"][value="spacing"]');
  await page.fill('#paths-spacing', String(spacing));
  await page.check(`#paths-form input[name="method"][value="${method}"]`);
}

/** Presses Compute paths and waits for the result: the summary. */
async function computePaths(page) {
  const runs = await page.evaluate(() => Number(document.body.dataset.pathsRuns ?? 0));
  await page.click('#paths-run');
  await page.waitForFunction((n) => Number(document.body.dataset.pathsRuns) === n + 1, runs, { timeout: 60_000 });
  await waitForReady(page);
  return page.textContent('#paths-summary');
}

/** Bytes of a figure such as "45.2 MiB" (www/app/format.js bytesText). */
function bytesOf(text) {
  const m = /([\d.]+)\s*(KiB|MiB|GiB)/.exec(text.replace(/,/g, ''));
  assert.ok(m, `a memory figure: ${text}`);
  return Number(m[1]) * 1024 ** { KiB: 1, MiB: 2, GiB: 3 }[m[2]];
}

test('opening the tool has the engine reserve the memory of its first distance (at least 32 MiB), shown with the model', async () => {
  const { page } = app;
  await page.waitForFunction((t) => document.getElementById('stat-memory').textContent !== t, memoryBefore);
  const [was, now] = [bytesOf(memoryBefore), bytesOf(await page.textContent('#stat-memory'))];
  assert.ok(now > was, `${memoryBefore} → ${await page.textContent('#stat-memory')}`);
});

test('a section plane z = 60 gives closed rings 10 mm apart, listed, drawn and coloured', async () => {
  const { page } = app;
  await page.check('#paths-form input[name="source"][value="plane"]');
  await page.check('#paths-form input[name="scope"][value="mesh"]');
  await page.selectOption('#paths-axis', 'z');
  await page.check('#paths-form input[name="spacingMode"][value="spacing"]');
  await page.fill('#paths-spacing', '10');
  await page.check('#paths-form input[name="method"][value="compare"]');
  await page.fill('#paths-voxelSize', '2');
  const before = await paintedPixels(page, join(outputDir, 'paths-before.png'));
  const purpleBefore = await purplePixels(page);
  await page.click('#paths-run');
  await page.waitForFunction(() => document.body.dataset.pathsRuns === '1', null, { timeout: 60_000 });
  await waitForReady(page);
  // Plane through the box centre z = 60: rings at 60 ± 10k, k = 1..6 on each side (level 6
  // is the rim itself) → each level twice.
  const n = await rows(page).count();
  assert.equal(n, 12, await page.textContent('#paths-table'));
  const levels = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.dataset.level)).sort((a, b) => a - b));
  assert.deepEqual(levels, [1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6]);
  for (let i = 0; i < n; i++) {
    const cells = await rows(page).nth(i).locator('td').allTextContents();
    const [level, distance, length, closed] = cells;
    assert.equal(closed, 'closed');
    assert.ok(Math.abs(Number(distance) - 10 * Number(level)) < 1e-6, cells.join(' '));
    // A ring of radius 50 on a 96-gon: its length is within 0.1 % of 2π·50.
    assert.ok(Math.abs(Number(length) - 2 * Math.PI * R) < 0.5, cells.join(' '));
  }
  // All four methods ran: their differences from the exact distance are shown, small against
  // the 2 mm voxels, and far smaller for the accurate and fast methods on this developable
  // cylinder.
  const diff = page.locator('#paths-diff');
  assert.equal(await diff.isVisible(), true);
  assert.match(await diff.textContent(), /accurate method vs exact: .*fast method vs exact: .*voxel method vs exact: /);
  const voxelMax = Number(await diff.getAttribute('data-voxel-max'));
  const fastMax = Number(await diff.getAttribute('data-fast-max'));
  const accurateMax = Number(await diff.getAttribute('data-accurate-max'));
  assert.ok(voxelMax > 0 && voxelMax < 5, `voxel vs exact ${voxelMax}`);
  assert.ok(fastMax < 0.05, `fast vs exact ${fastMax}`);
  assert.ok(accurateMax < 0.01, `accurate vs exact ${accurateMax}`);
  assert.equal(Number(await diff.getAttribute('data-max')), voxelMax);
  assert.match(await page.textContent('#overlay-paths'), /Geodesic distance from the source, mm/);
  // The colour map changes the picture: coloured pixels that are not the grey model.
  const after = await paintedPixels(page, join(outputDir, 'paths-plane.png'));
  assert.ok(after.painted >= before.painted * 0.8, JSON.stringify({ before, after }));
  const darkPurple = await purplePixels(page);
  assert.ok(darkPurple > purpleBefore + 1000, `viridis' dark end near the source: ${purpleBefore} → ${darkPurple} pixels`);
  await page.screenshot({ path: join(outputDir, 'paths-page.png') });
  assert.deepEqual(app.consoleErrors, []);
});

test('the passes export as a RAPID program with MoveL lines', async () => {
  const { page } = app;
  const rapid = await saveDownload(page, () => page.click('#results-paths button[data-format="rapid"]'));
  const text = rapid.name.endsWith('.zip') ? '' : rapid.bytes.toString('utf8');
  assert.match(rapid.name, /\.mod$/);
  assert.match(text, /MODULE \w+/);
  assert.ok((text.match(/MoveL /g) ?? []).length >= 10 * 20, 'many moves along twelve rings');
  const csv = await saveDownload(page, () => page.click('#results-paths button[data-format="csv"]'));
  assert.match(csv.name, /\.csv$/);
  assert.ok(csv.bytes.toString('utf8').trim().split('\n').length > 100);
});

test('spacing 0 is refused in the form; an engine error is reported and the result kept', async () => {
  const { page } = app;
  await page.fill('#paths-spacing', '0');
  assert.match(await page.textContent('#paths-error'), /pass spacing must be above 0/);
  assert.equal(await page.isDisabled('#paths-run'), true);
  await page.fill('#paths-spacing', '10');
  assert.equal(await page.isDisabled('#paths-run'), false);
  // Voxels of 1 µm over a 100 × 100 × 120 mm box: far too many, refused by the engine.
  await page.check('#paths-form input[name="method"][value="voxel"]');
  await page.fill('#paths-voxelSize', '0.001');
  await page.click('#paths-run');
  await page.waitForFunction(() => document.getElementById('alert').textContent.length > 0, null, { timeout: 60_000 });
  await waitForReady(page);
  const alert = await page.textContent('#alert');
  assert.match(alert, /The paths could not be computed: .*voxel.*The result on screen is unchanged\./s);
  assert.equal(await rows(page).count(), 12, 'the previous table stays');
  assert.equal(await page.isDisabled('#results-paths button[data-format="rapid"]'), false);
  assert.equal(await page.evaluate(() => document.body.dataset.pathsRuns), '1');
});

test('the boundary loops of the cylinder give rings from both rims, bead width × overlap spacing', async () => {
  const { page } = app;
  await page.check('#paths-form input[name="method"][value="fast"]');
  await page.check('#paths-form input[name="source"][value="boundary"]');
  await page.check('#paths-form input[name="spacingMode"][value="bead"]');
  await page.fill('#paths-beadWidth', '6.4');
  await page.fill('#paths-overlap', '0.738');
  assert.match(await page.textContent('#paths-spacing-hint'), /4\.723 mm apart/);
  await page.click('#paths-run');
  await page.waitForFunction(() => document.body.dataset.pathsRuns === '2', null, { timeout: 60_000 });
  await waitForReady(page);
  // Distance to the nearer rim reaches 60 mm at mid-length: levels 1..12 (12 · 4.7232 = 56.7),
  // two rings each.
  const levels = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.dataset.level)).sort((a, b) => a - b));
  assert.deepEqual(levels, Array.from({ length: 24 }, (_, i) => 1 + Math.floor(i / 2)));
  const distances = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.children[1].textContent)));
  for (const [i, d] of distances.entries()) assert.ok(d > 0 && d < 60, `row ${i}: ${d}`);
  assert.equal(await page.locator('#paths-diff').isVisible(), false, 'a new source: no comparison yet');
  // The settings persist (URL hash, like the other tools).
  const hash = new URLSearchParams((await page.evaluate(() => location.hash)).slice(1));
  assert.equal(hash.get('paths.spacingMode'), 'bead');
  assert.equal(hash.get('paths.source'), 'boundary');
  assert.equal(hash.get('paths.overlap'), '0.738');
  assert.deepEqual(app.consoleErrors, []);
});

test('clicked points on the surface become the source', async () => {
  const { page } = app;
  await page.check('#paths-form input[name="source"][value="points"]');
  assert.equal(await page.isDisabled('#paths-run'), true, 'no points yet');
  await page.check('#paths-form input[name="spacingMode"][value="spacing"]');
  await page.fill('#paths-spacing', '10');
  const box = await page.locator('#viewer canvas').boundingBox();
  for (const dx of [-60, 0, 60]) {
    await page.mouse.click(box.x + box.width / 2 + dx, box.y + box.height / 2 - 150);
  }
  // The worker answers picks: wait for the three answers, which arrive in click order.
  await page.waitForFunction(() => /^3 points clicked/.test(document.getElementById('paths-points').textContent));
  await page.click('#paths-undo-point');
  assert.match(await page.textContent('#paths-points'), /^2 points clicked/);
  await page.click('#paths-run');
  await page.waitForFunction(() => document.body.dataset.pathsRuns === '3', null, { timeout: 60_000 });
  await waitForReady(page);
  assert.match(await page.textContent('#paths-summary'), /^2 clicked points on the whole mesh/);
  const n = await rows(page).count();
  assert.ok(n >= 3, `${n} passes`);
  const distances = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.children[1].textContent)));
  for (const d of distances) assert.ok(Math.abs(d / 10 - Math.round(d / 10)) < 1e-6, `distance ${d} is a multiple of the spacing`);
  await page.screenshot({ path: join(outputDir, 'paths-points.png') });
  assert.deepEqual(app.consoleErrors, []);
});

test('a plane normal to the view (top view: Y) through the centre: open passes from one generator', async () => {
  const { page } = app;
  await page.click('button[data-view="top"]');
  await page.check('#paths-form input[name="source"][value="plane"]');
  await page.selectOption('#paths-axis', 'view');
  await page.click('#paths-run');
  await page.waitForFunction(() => document.body.dataset.pathsRuns === '4', null, { timeout: 60_000 });
  await waitForReady(page);
  const summary = await page.textContent('#paths-summary');
  assert.match(summary, /^Section plane \(normal along the view\)/);
  // The section y = 0 is the generators x = ±50; the source is the piece nearest the point
  // (one generator), the farthest points are the opposite generator (π·50 = 157.1 mm away):
  // levels 1..15, one open pass on each side of the source, each ending at the rims.
  const cells = await rows(page).evaluateAll((trs) => trs.map((tr) => [Number(tr.dataset.level), tr.dataset.closed]));
  assert.deepEqual(cells.map((c) => c[0]).sort((a, b) => a - b), Array.from({ length: 30 }, (_, i) => 1 + Math.floor(i / 2)));
  assert.ok(cells.every((c) => c[1] === 'false'), JSON.stringify(cells));
  const far = Number(summary.match(/farthest point ([\d.]+) mm/)[1]);
  assert.ok(Math.abs(far - Math.PI * R) < 0.5, `farthest ${far}`);
  assert.deepEqual(app.consoleErrors, []);
});

test('one boundary loop of the cylinder: rings from one rim only', async () => {
  const { page } = app;
  await page.check('#paths-form input[name="source"][value="boundary"]');
  await page.selectOption('#paths-loop', '0');
  await page.click('#paths-run');
  await page.waitForFunction(() => document.body.dataset.pathsRuns === '5', null, { timeout: 60_000 });
  await waitForReady(page);
  assert.match(await page.textContent('#paths-summary'), /^Boundary loop 1 \(by length\)/);
  // From one rim the farthest point is the other rim, 120 mm away: rings at 10k, k = 1..12.
  const cells = await rows(page).evaluateAll((trs) => trs.map((tr) => [Number(tr.dataset.level), tr.dataset.closed]));
  assert.deepEqual(cells, Array.from({ length: 12 }, (_, i) => [i + 1, 'true']));
  await page.selectOption('#paths-loop', 'all');
  assert.deepEqual(app.consoleErrors, []);
});

test('on a small model with corners the accurate method gives the exact distance and says so', async () => {
  const { page } = app;
  // A closed cube of side 40 mm, each face 4 × 4 squares, cut by the plane z = 20 through
  // its centre: the farthest points, the centres of the top and bottom faces, are 20 + 20 mm
  // away.
  const s = 40, n = 4;
  const faces = [ // origin, u, v of each face, outwards
    [[0, 0, 0], [0, s, 0], [s, 0, 0]], [[0, 0, s], [s, 0, 0], [0, s, 0]],
    [[0, 0, 0], [s, 0, 0], [0, 0, s]], [[0, s, 0], [0, 0, s], [s, 0, 0]],
    [[0, 0, 0], [0, 0, s], [0, s, 0]], [[s, 0, 0], [0, s, 0], [0, 0, s]],
  ];
  const tris = [];
  for (const [o, u, v] of faces) {
    const p = (i, j) => [0, 1, 2].map((k) => o[k] + (u[k] * i + v[k] * j) / n);
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) tris.push(...p(i, j), ...p(i + 1, j), ...p(i + 1, j + 1), ...p(i, j), ...p(i + 1, j + 1), ...p(i, j + 1));
    }
  }
  await planeAcross(page, 'cube.stl', binaryStl(tris, 'cube for the paths test'), 7, 'accurate');
  const summary = await computePaths(page);
  assert.match(summary, /accurate method \(the exact distance: small surface with corners or holes\)/);
  const far = Number(summary.match(/farthest point ([\d.]+) mm/)[1]);
  assert.ok(Math.abs(far - 40) < 1e-3, `farthest ${far}: ${summary}`);
  // Levels 7, 14 (on the sides), 21, 28, 35 mm (squares on the top and bottom faces), twice.
  const levels = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.dataset.level)).sort((a, b) => a - b));
  assert.deepEqual(levels, [1, 1, 2, 2, 3, 3, 4, 4, 5, 5]);
  assert.match(await page.textContent('#overlay-paths'), /\(accurate method \(the exact distance/);
  assert.deepEqual(app.consoleErrors, []);
});

test('passes nearer the source than the mesh resolves are said to be missing, and why', async () => {
  const { page } = app;
  // Rings of vertices every 4.8 mm: the plane z = 60 through the centre passes 2.4 mm from
  // the nearest, and the distance is known at the vertices only.
  await planeAcross(page, 'cylinder25.stl', cylinderStl(96, 25), 1, 'fast');
  const compute = async (most) => {
    await page.fill('#paths-maxLevel', String(most));
    return computePaths(page);
  };
  const none = await compute(2);
  assert.match(none, /: 0 passes .* No pass: the 2 levels asked for \(Most passes\) end 2 mm from the source, nearer than the mesh resolves: .*the nearest vertices are 2\.4 mm from the source\. Widen the spacing/);
  const some = await compute(10);
  assert.match(some, /Levels 1 to 2 \(up to 2 mm\) are not cut, nearer the source than the mesh resolves/);
  const levels = await rows(page).evaluateAll((trs) => trs.map((tr) => Number(tr.dataset.level)));
  assert.equal(Math.min(...levels), 3);
  assert.deepEqual(app.consoleErrors, []);
});
