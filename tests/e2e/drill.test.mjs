// The Drill tool in headless Chromium: the paper's example in one click (its panel becomes
// the model, the errors uncorrected > bilinear > Coons appear beside the paper's figures),
// a hole list with a bad row, the robot-program and hole CSV exports, and references and
// holes set by clicks on the model.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openAppWithSample, outputDir, saveDownload, waitForModel, waitForReady } from './helpers.mjs';

let app;
before(async () => {
  app = await openAppWithSample();
});
after(async () => {
  await app?.close();
});

/** The figure in a cell of the comparison table (row key, column 1 = max, 2 = min). */
const cell = (page, row, column) => page.locator(`#drill-compare tr[data-row="${row}"] td:nth-child(${column + 1})`).textContent()
  .then(Number);

test('the paper\'s example runs from the page and shows uncorrected > bilinear > Coons beside the paper', async () => {
  const { page } = app;
  await page.click('#tab-drill');
  await page.click('#drill-example-button');
  await waitForModel(page, 'paper_60deg_panel.stl');
  await page.waitForSelector('#drill-compare tr[data-row="coons"]', { timeout: 30_000 });
  await waitForReady(page);
  const max = {};
  const min = {};
  for (const row of ['uncorrected', 'bilinear', 'coons']) {
    max[row] = await cell(page, row, 1);
    min[row] = await cell(page, row, 2);
  }
  assert.ok(max.uncorrected > max.bilinear && max.bilinear > max.coons, JSON.stringify(max));
  assert.ok(min.uncorrected > min.bilinear && min.bilinear > min.coons, JSON.stringify(min));
  assert.ok(max.uncorrected > 1, 'the panel moves by millimetres');
  assert.ok(max.coons < 0.1 * max.bilinear, JSON.stringify(max));
  const paper = await page.locator('#drill-compare tbody').textContent();
  for (const figure of ['5.586 / 3.302', '2.442 / 0.175', '0.628 / 0.005']) assert.ok(paper.includes(figure), figure);
  assert.equal(await page.locator('#drill-table tbody tr').count(), 16);
  assert.equal(await page.locator('#drill-compare').evaluate((t) => t.closest('[hidden]')), null);
  assert.match(await page.locator('#overlay-drill').textContent(), /Corrections drawn × 20/);
  await page.screenshot({ path: join(outputDir, 'drill-example.png') });
  assert.deepEqual(app.consoleErrors, []);
});

test('a bad hole row is reported by its line number and the good rows are kept', async () => {
  const { page } = app;
  const text = await page.inputValue('#drill-holes');
  const lines = text.trim().split('\n');
  lines.splice(3, 0, 'H99,12.5,oops,7'); // line 4
  await page.fill('#drill-holes', `${lines.join('\n')}\n`);
  await page.click('#drill-run');
  await page.waitForFunction(() => /Line 4/.test(document.getElementById('drill-holes-report').textContent), null, { timeout: 30_000 });
  await waitForReady(page);
  const report = await page.textContent('#drill-holes-report');
  assert.match(report, /^16 holes read \(first line taken as a header\)\. Line 4: y = "oops" is not a finite number\./);
  assert.equal(await page.locator('#drill-table tbody tr').count(), 16);
  assert.match(await page.textContent('#status'), /1 bad row skipped/);
});

test('the export section says what the cell must set up, and its names reach the program', async () => {
  const { page } = app;
  const notes = await page.locator('#drill-cell .cell-notes').textContent();
  for (const needed of ['doProcess', '$OUT[1]', 'tSkinpath', 'TOOL_DATA[1]', 'wSkinpath', 'BASE_DATA[1]', 'I/O configuration', 'flange', "part's frame", '50 mm']) {
    assert.ok(notes.includes(needed), `${needed} in: ${notes}`);
  }
  await page.click('#drill-cell summary');
  await page.fill('#drill-cell-rapidSignal', 'doDrill');
  await page.press('#drill-cell-rapidSignal', 'Enter');
  await page.fill('#drill-cell-approachClearanceMm', '30');
  await page.press('#drill-cell-approachClearanceMm', 'Tab');
  assert.match(await page.locator('#drill-cell .cell-notes').textContent(), /doDrill.*30 mm/s);
  await page.locator('#drill-cell').screenshot({ path: join(outputDir, 'drill-cell.png') });
  // The same cell in the other tools' export sections.
  assert.equal(await page.inputValue('#spray-cell-rapidSignal'), 'doDrill');
  const rapid = await saveDownload(page, () => page.click('#results-drill button[data-format="rapid"]'));
  const program = rapid.bytes.toString('utf8');
  assert.match(program, /SetDO doDrill,1;/);
  assert.match(program, /30 mm back along/);
  assert.match(program, /ConfL\\Off;/);
  assert.ok(program.indexOf('MoveJ ') < program.indexOf('MoveL '), 'a joint move first');
  // Back to the defaults for the tests after this one.
  await page.fill('#drill-cell-rapidSignal', 'doProcess');
  await page.press('#drill-cell-rapidSignal', 'Tab');
  await page.fill('#drill-cell-approachClearanceMm', '50');
  await page.press('#drill-cell-approachClearanceMm', 'Tab');
  assert.deepEqual(app.consoleErrors, []);
});

test('the corrected holes export as a RAPID program and as a hole CSV', async () => {
  const { page } = app;
  const rapid = await saveDownload(page, () => page.click('#results-drill button[data-format="rapid"]'));
  assert.match(rapid.name, /\.mod$/);
  const program = rapid.bytes.toString('utf8');
  assert.match(program, /MODULE \w+/);
  // Approach, drill and retract for each of the 16 holes.
  assert.ok((program.match(/MoveL /g) ?? []).length >= 48, 'three moves a hole');
  const csv = await saveDownload(page, () => page.click('#results-drill button[data-format="holes"]'));
  const rows = csv.bytes.toString('utf8').trim().split('\n');
  assert.equal(rows[0], 'id,x,y,z,nx,ny,nz');
  assert.equal(rows.length, 17);
  const [, ...h01] = rows[1].split(',').map(Number);
  assert.ok(Math.abs(Math.hypot(h01[3], h01[4], h01[5]) - 1) < 1e-5, 'unit normals');
  assert.deepEqual(app.consoleErrors, []);
});

test('clicks on the model set the four references with the model\'s normals, then add holes, which are corrected', async () => {
  const { page } = app;
  // The example's panel, seen from the top (the first test): click around its middle.
  await page.fill('#drill-holes', '');
  for (let i = 0; i < 4; i++) {
    for (const g of ['nom', 'act', 'n']) for (const c of ['x', 'y', 'z']) await page.fill(`#drill-ref-${i}-${g}${c}`, '');
  }
  await page.selectOption('#drill-pick', 'ref-0');
  assert.equal(await page.locator('#viewer canvas').evaluate((c) => c.style.cursor), 'crosshair');
  const box = await page.locator('#viewer canvas').boundingBox();
  const at = (dx, dy) => [box.x + box.width / 2 + dx, box.y + box.height / 2 + dy];
  const corners = [at(-120, -70), at(120, -70), at(120, 70), at(-120, 70)];
  for (const [i, [x, y]] of corners.entries()) {
    await page.mouse.click(x, y);
    await page.waitForFunction((k) => document.getElementById(`drill-ref-${k}-nz`).value !== '', i, { timeout: 30_000 });
  }
  await waitForReady(page);
  // After D the clicks add holes.
  assert.equal(await page.inputValue('#drill-pick'), 'holes');
  const value = (id) => page.inputValue(id).then(Number);
  const refs = [];
  for (let i = 0; i < 4; i++) {
    const p = [];
    const n = [];
    for (const c of ['x', 'y', 'z']) {
      p.push(await value(`#drill-ref-${i}-nom${c}`));
      n.push(await value(`#drill-ref-${i}-n${c}`));
    }
    assert.ok(p.every(Number.isFinite), `reference ${i}: ${p}`);
    assert.ok(Math.abs(Math.hypot(...n) - 1) < 1e-5, `reference ${i}: unit normal ${n}`);
    refs.push(p);
  }
  // Four distinct points, spread over the panel (it is about 1 m wide in mm).
  for (let i = 0; i < 4; i++) {
    const d = Math.hypot(...refs[i].map((x, k) => x - refs[(i + 1) % 4][k]));
    assert.ok(d > 20, `references ${i} and ${(i + 1) % 4} are ${d} mm apart`);
  }
  for (const [x, y] of [at(-30, 0), at(30, 10)]) await page.mouse.click(x, y);
  await page.waitForFunction(() => document.getElementById('drill-holes').value.includes('H02'), null, { timeout: 30_000 });
  const rows = (await page.inputValue('#drill-holes')).trim().split('\n');
  assert.equal(rows[0], 'id,x,y,z');
  assert.deepEqual(rows.slice(1).map((r) => r.split(',')[0]), ['H01', 'H02']);
  assert.match(await page.textContent('#status'), /Hole H02 added at/);
  await page.waitForTimeout(200); // the marks of the form's references and holes
  await page.screenshot({ path: join(outputDir, 'drill-picking.png') });
  // Measured = nominal moved by 0.5 mm along x everywhere: each hole moves by about that.
  for (let i = 0; i < 4; i++) {
    for (const [k, c] of ['x', 'y', 'z'].entries()) await page.fill(`#drill-ref-${i}-act${c}`, String(refs[i][k] + (k === 0 ? 0.5 : 0)));
  }
  await page.click('#drill-run');
  await page.waitForFunction(() => document.querySelectorAll('#drill-table tbody tr').length === 2, null, { timeout: 30_000 });
  await waitForReady(page);
  assert.match(await page.textContent('#drill-summary'), /^2 holes corrected by the Coons patch on paper_60deg_panel\.stl\.$/);
  const moved = await page.locator('#drill-table tbody tr td:nth-child(5)').allTextContents();
  for (const m of moved.map(Number)) assert.ok(Math.abs(m - 0.5) < 0.05, `a hole moved ${m} mm, the references 0.5 mm`);
  await page.screenshot({ path: join(outputDir, 'drill-picked.png') });
  await page.selectOption('#drill-pick', 'off');
  assert.equal(await page.locator('#viewer canvas').evaluate((c) => c.style.cursor), '');
  assert.deepEqual(app.consoleErrors, []);
});
