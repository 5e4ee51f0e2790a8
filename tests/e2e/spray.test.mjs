// The Spray tool's gun speeds in headless Chromium, on the sample's largest patch: the plan
// opens with the path coloured by the optimised speed (legend within the limits), the summary
// gives the cycle time, the checkbox off gives one uniform speed, "best of" reports the
// directions tried, and the speed limits are checked against the nominal speed in the form.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openAppWithSample, outputDir, waitForReady } from './helpers.mjs';

const text = (page, selector) => page.locator(selector).textContent();

let app;
before(async () => {
  app = await openAppWithSample();
  await app.page.click('#tab-spray');
  await app.page.click('#spray-defaults-button');
});
after(async () => {
  await app?.close();
});

/** Presses Plan spray and waits for the plan (or an alert), then for the page to be idle. */
async function plan(page) {
  const count = Number(await page.evaluate(() => document.body.dataset.sprayPlans ?? 0));
  await page.click('#spray-plan-button');
  await page.waitForFunction((n) => Number(document.body.dataset.sprayPlans ?? 0) > n
    || document.getElementById('alert').textContent !== '', count, { timeout: 300_000, polling: 200 });
  await waitForReady(page, 300_000);
  assert.equal(await text(page, '#alert'), '', 'the engine planned without an error');
  // Plans of many passes open with the path hidden (its legend too): show it.
  if (!(await page.isChecked('#spray-showPath'))) await page.check('#spray-showPath');
}

/** The speed legend's end values in mm/s. */
async function legendRange(page) {
  const lo = Number(await page.getAttribute('#spray-speed-legend .speed-min', 'data-value'));
  const hi = Number(await page.getAttribute('#spray-speed-legend .speed-max', 'data-value'));
  return { lo, hi };
}

test('a default plan colours the path by optimised speed within 200–800 mm/s and states the cycle time', async () => {
  const { page } = app;
  assert.equal(await page.isChecked('#spray-optimiseSpeed'), true, 'on by default');
  assert.equal(await page.inputValue('#spray-minSpeed'), '200');
  assert.equal(await page.inputValue('#spray-maxSpeed'), '800');
  assert.equal(await page.inputValue('#spray-direction'), 'principal');
  await plan(page);
  assert.equal(await page.inputValue('#spray-pathColors'), 'speed', 'optimised speeds open the path coloured by speed');
  assert.equal(await page.isVisible('#spray-speed-legend'), true);
  assert.match(await text(page, '#spray-speed-legend'), /Gun speed, mm\/s \(optimised\)/);
  const { lo, hi } = await legendRange(page);
  assert.ok(lo >= 200 * (1 - 1e-9) && hi <= 800 * (1 + 1e-9) && lo <= hi, `legend ${lo}–${hi} mm/s`);
  assert.ok(hi > lo, `the optimiser varies the speed (${lo}–${hi} mm/s)`);
  const summary = await text(page, '#spray-summary');
  assert.match(summary, /\d+ passes [\d.,]+ mm apart/);
  assert.match(summary, /Cycle time [\d.,]+ (s|min|h)/);
  assert.match(summary, /spray path [\d.,]+ m, whole path [\d.,]+ m/);
  assert.match(summary, /gun speed optimised along the passes, [\d.,]+–[\d.,]+ mm\/s commanded \(limits 200–800 mm\/s\)/);
  assert.match(summary, /along the principal direction/);
  // The sample's upper skin is large: its samples lie farther apart than R/2 (R = 91 mm at the
  // defaults), and the summary says what that means for the figures.
  const every = Number(summary.match(/evaluated every ([\d.,]+) mm/)[1].replace(/,/g, ''));
  assert.equal(/more than half the spray radius \(R = 91 mm\)/.test(summary), every > 45.5, summary);
  assert.match(await text(page, '#spray-verdict'), /^(Meets the limits|Limits not met)/);
  // The worst regions are listed (and ringed on the map) with their cause.
  const spots = await page.locator('#spray-hotspots li').allTextContents();
  assert.ok(spots.length >= 1, 'at least one worst region');
  for (const s of spots) assert.match(s, /^(Thick|Thin) by [\d.,]+ % (at the patch edge|at a fold|on a tightly curved part|between passes)$/);
  await page.hover('#spray-hotspots li >> nth=0');
  // Kind colouring brings back the kinds legend; speed again brings the scale back.
  await page.selectOption('#spray-pathColors', 'kind');
  assert.equal(await page.locator('#spray-speed-legend').count(), 0);
  assert.match(await text(page, '#overlay-spray'), /Pass \(gun on\)/);
  await page.selectOption('#spray-pathColors', 'speed');
  assert.equal(await page.isVisible('#spray-speed-legend'), true);
  await page.screenshot({ path: join(outputDir, 'e2e-spray-speeds.png') });
  await page.locator('#panel-spray').screenshot({ path: join(outputDir, 'e2e-spray-panel.png') });
  await page.locator('#results-spray').screenshot({ path: join(outputDir, 'e2e-spray-results.png') });
});

test('with the optimisation off the gun runs at one uniform speed', async () => {
  const { page } = app;
  await page.uncheck('#spray-optimiseSpeed');
  await plan(page);
  assert.equal(await page.inputValue('#spray-pathColors'), 'kind');
  await page.selectOption('#spray-pathColors', 'speed');
  assert.match(await text(page, '#spray-speed-legend'), /^Gun speed, mm\/s(?! \(optimised\))/);
  const { lo, hi } = await legendRange(page);
  assert.ok(Math.abs(hi - lo) <= 1e-9 * hi, `one speed (${lo}–${hi} mm/s)`);
  assert.ok(lo >= 200 * (1 - 1e-9) && hi <= 800 * (1 + 1e-9), `within the limits (${lo} mm/s)`);
  assert.match(await text(page, '#spray-summary'), /gun at [\d.,]+ mm\/s(?!–)/);
  await page.check('#spray-optimiseSpeed');
});

test('"best of" plans four directions and reports them in a table', async () => {
  const { page } = app;
  assert.equal(await page.isDisabled('#spray-rasterAngle'), true, 'the typed angle counts only when chosen');
  await page.selectOption('#spray-direction', 'best');
  await plan(page);
  assert.equal(await page.isVisible('#spray-directions'), true);
  const rows = await page.locator('#spray-directions tbody tr').allTextContents();
  assert.equal(rows.length, 4, rows.join(' | '));
  assert.equal(rows.filter((r) => r.includes('✓ used')).length, 1, 'one direction used');
  const turns = rows.map((r) => r.match(/^(principal \(0°\)|[+−]\d+°)/)?.[1]);
  assert.deepEqual([...turns].sort(), ['+45°', '+90°', 'principal (0°)', '−45°'].sort(), rows.join(' | '));
  assert.match(await text(page, '#spray-summary'), /the best of 4 directions tried/);
  // The direction used is the one the summary names.
  const used = turns[rows.findIndex((r) => r.includes('✓ used'))];
  const named = used.startsWith('principal') ? 'passes along the principal direction' : `passes turned by ${used}`;
  assert.ok((await text(page, '#spray-summary')).includes(named), named);
  await page.locator('#results-spray').screenshot({ path: join(outputDir, 'e2e-spray-best-of.png') });
  await page.selectOption('#spray-direction', 'typed');
  assert.equal(await page.isDisabled('#spray-rasterAngle'), false);
});

test('speed limits that exclude the nominal speed are named next to the fields and block planning', async () => {
  const { page } = app;
  await page.fill('#spray-minSpeed', '500');
  assert.match(await text(page, '#spray-speed-error'), /nominal gun speed v \(400 mm\/s\) must lie between the slowest and the fastest, 500–800 mm\/s/);
  assert.equal(await page.getAttribute('#spray-minSpeed', 'aria-invalid'), 'true');
  assert.equal(await page.isDisabled('#spray-plan-button'), true);
  await page.fill('#spray-maxSpeed', '300');
  assert.match(await text(page, '#spray-speed-error'), /slowest gun speed \(500 mm\/s\) must not exceed the fastest \(300 mm\/s\)/);
  await page.click('#spray-defaults-button');
  assert.equal(await text(page, '#spray-speed-error'), '');
  assert.equal(await page.isDisabled('#spray-plan-button'), false);
});

test('no request left the origin and nothing was logged as an error', () => {
  assert.deepEqual(app.foreignRequests, []);
  assert.deepEqual(app.consoleErrors, []);
});
