// `npm run bench -- page`: opening a large file in the page as a user does, in headless
// Chromium (SwiftShader WebGL: software drawing, far slower than a GPU's), from the file chosen
// to its patches on screen. The bench's aircraft-like files (1M and 4M triangles; see
// aircraftStl in bench.mjs) are written to test-output/ and chosen through the page's file
// input once the page has opened its sample and been idle for two seconds (its warm-up).
// Printed per file: the time from the input's change event to the page ready again, split at
// the progress stages the page shows (read + parse + welding, adjacency, winding, segmentation,
// the display buffers, drawing), and two yardsticks: three.js's STLLoader.parse of the same
// File's bytes in the same page (median of three, after the open: warm, the bytes in memory),
// and a three.js viewer's open of the file as the page's is timed: from the change event of a
// file input in a fresh page to `STLLoader.parse` of `file.arrayBuffer()` done (cold, like the
// page's open; median over three fresh pages). Skipped with a word when Chromium is not
// installed (`npm run setup -- --browser` installs it).
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const CHROMIUM = '/usr/bin/chromium';
const SIZES = (process.env.PAGE_CASES ?? '1000000,4000000').split(',').map(Number);
// The page's progress stages, grouped as printed.
const STAGE_GROUPS = [
  ['read+parse', ['Opening', 'Reading the STL']],
  ['adjacency', ['Finding neighbouring triangles']],
  ['winding', ['Making the winding consistent', 'Computing normals and areas']],
  ['segment', ['Growing regions', 'Splitting regions into near-planar patches', 'Measuring the patches']],
  ['display', ['Preparing the display']],
  ['drawing', ['Drawing']],
];

/** `aircraftStl(triangles)`: bench.mjs's generator (this module is imported from there). */
export async function main({ aircraftStl }) {
  console.log('\nopening a file in the page (headless Chromium, SwiftShader WebGL): the bench\'s aircraft-like files, from the file chosen to its patches drawn; ' +
    'stages as the page shows them; yardsticks: three.js STLLoader.parse of the same bytes in the same page (warm), ' +
    'and a three.js viewer opening the same file in a fresh page (file read + parse, cold)');
  if (!existsSync(CHROMIUM)) {
    console.log(`skipped: Chromium is not installed at ${CHROMIUM} (npm run setup -- --browser)`);
    return;
  }
  const { openApp, outputDir } = await import('../tests/e2e/helpers.mjs');
  mkdirSync(outputDir, { recursive: true });
  const stlLoader = readFileSync(join(root, 'node_modules', 'three', 'examples', 'jsm', 'loaders', 'STLLoader.js'), 'utf8');
  console.log('    triangles   ready ms  ' + STAGE_GROUPS.map(([name]) => name.padStart(10)).join('  ') + '  STLLoader ms  (ready − drawing)/STLLoader  viewer open ms  (ready − drawing)/viewer open');
  for (const size of SIZES) {
    const path = join(outputDir, `bench_aircraft_${size}.stl`);
    if (!existsSync(path)) writeFileSync(path, aircraftStl(size));
    const app = await openApp({
      beforeGoto: (page, url) => page.route(`${url}bench/STLLoader.js`, (route) =>
        route.fulfill({ body: stlLoader, contentType: 'text/javascript' })),
    });
    try {
      const { page } = app;
      await page.waitForFunction(() => document.body.dataset.state === 'ready' && document.body.dataset.model, null, { timeout: 120_000 });
      await page.waitForTimeout(2000);
      // Stage changes as the page shows them, from the input's change event on.
      await page.evaluate(() => {
        window.__stages = [];
        const note = () => {
          const stage = document.getElementById('progress-stage')?.textContent ?? '';
          const state = document.body.dataset.state;
          const last = window.__stages.at(-1);
          if (!last || last.stage !== stage || last.state !== state) window.__stages.push({ t: performance.now(), stage, state });
        };
        document.getElementById('file-input').addEventListener('change', (event) => {
          window.__start = performance.now();
          window.__file = event.target.files[0]; // the page clears the input once it has it
          new MutationObserver(note).observe(document.body, { subtree: true, childList: true, characterData: true, attributes: true });
        }, { once: true });
      });
      await page.setInputFiles('#file-input', path);
      const name = path.split(/[\\/]/).pop();
      await page.waitForFunction((n) => document.body.dataset.state === 'ready' && document.body.dataset.model === n, name, { timeout: 600_000, polling: 50 });
      const { start, stages, end } = await page.evaluate(() => ({ start: window.__start, stages: window.__stages, end: performance.now() }));
      const ready = (stages.findLast((s) => s.state === 'ready')?.t ?? end) - start;
      const spans = Object.fromEntries(STAGE_GROUPS.map(([group]) => [group, 0]));
      for (let i = 0; i < stages.length; i++) {
        if (stages[i].state !== 'busy') continue;
        const next = stages[i + 1]?.t ?? end;
        const from = Math.max(stages[i].t, start);
        const group = STAGE_GROUPS.find(([, names]) => names.some((n) => stages[i].stage.startsWith(n)))?.[0] ?? 'read+parse';
        spans[group] += Math.max(0, next - from);
      }
      const loader = await page.evaluate(async () => {
        const { STLLoader } = await import('/bench/STLLoader.js');
        const bytes = await window.__file.arrayBuffer();
        const times = [];
        for (let r = 0; r < 3; r++) {
          const t = performance.now();
          new STLLoader().parse(bytes);
          times.push(performance.now() - t);
        }
        return times.sort((a, b) => a - b)[1];
      });
      const viewer = await viewerOpen(app, path, stlLoader);
      console.log(`${String(size).padStart(13)}  ${ready.toFixed(0).padStart(9)}  ` +
        STAGE_GROUPS.map(([group]) => spans[group].toFixed(0).padStart(10)).join('  ') +
        `  ${loader.toFixed(0).padStart(12)}  ${((ready - spans.drawing) / loader).toFixed(2).padStart(25)}` +
        `  ${viewer.toFixed(0).padStart(14)}  ${((ready - spans.drawing) / viewer).toFixed(2).padStart(27)}`);
    } finally {
      await app.close();
    }
  }
}


/** Fresh pages in which a file input opens the file as a three.js viewer would. */
const VIEWER_RUNS = 3;

/**
 * The yardstick for the page's open: a three.js viewer's, timed as the page's is, from the
 * file input's change event to `STLLoader.parse(await file.arrayBuffer())` done, in a fresh
 * page of the same browser (cold: the file is read and the heap grows, as in the page's
 * open). Median over VIEWER_RUNS fresh pages, in ms.
 */
async function viewerOpen(app, path, stlLoader) {
  const page0 = `${app.url}bench/viewer.html`;
  const html = `<!doctype html><meta charset="utf-8"><script type="importmap">
{ "imports": { "three": "../vendor/three/build/three.module.js" } }</script>
<input type="file" id="file"><script type="module">
import { STLLoader } from './STLLoader.js';
document.getElementById('file').addEventListener('change', async (event) => {
  const t = performance.now();
  const geometry = new STLLoader().parse(await event.target.files[0].arrayBuffer());
  window.__opened = { ms: performance.now() - t, vertices: geometry.attributes.position.count };
});
window.__ready = true;
</script>`;
  const times = [];
  for (let r = 0; r < VIEWER_RUNS; r++) {
    const page = await app.browser.newPage();
    try {
      await page.route(page0, (route) => route.fulfill({ body: html, contentType: 'text/html' }));
      await page.route(`${app.url}bench/STLLoader.js`, (route) =>
        route.fulfill({ body: stlLoader, contentType: 'text/javascript' }));
      await page.goto(page0);
      await page.waitForFunction(() => window.__ready, null, { timeout: 60_000 });
      await page.setInputFiles('#file', path);
      const opened = await page.waitForFunction(() => window.__opened, null, { timeout: 600_000, polling: 50 });
      times.push((await opened.jsonValue()).ms);
    } finally {
      await page.close();
    }
  }
  return times.sort((a, b) => a - b)[Math.floor(VIEWER_RUNS / 2)];
}
