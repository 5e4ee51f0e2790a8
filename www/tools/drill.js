// Drill tool (seed 004): four reference holes (nominal and measured positions, normals typed,
// taken from the model or computed from four laser readings), a list of holes to drill
// (`id,x,y,z`: typed, read from a CSV or clicked on the model), their positions corrected by
// the Coons error surface (and the bilinear baseline beside it), drawn on the panel,
// tabulated, and exported as a hole CSV or a robot program (ABB RAPID, KUKA KRL, tool-path
// CSV/JSON). The built-in example is the paper's 60° cylindrical sector. Lengths are in the
// file's unit throughout (robot programs in mm); the worker side is worker/drill.js.
import { CancelledError } from '../app/engine.js';
import { download, fileStem } from '../app/download.js';
import { num, pointText } from '../app/format.js';
import { persistSettings } from '../app/settings.js';
import { cellHtml, cellOptions, mountCell, renderCell } from '../app/cell.js';
import { hexRgb } from '../app/colours.js';
import { pointMark } from '../viewer/viewer.js';

const P = 'drill.'; // settings key prefix
const DEFAULTS = Object.freeze({
  [`${P}method`]: 'coons',
  [`${P}scale`]: 20,
  [`${P}approach`]: 20,
  [`${P}retract`]: 20,
  [`${P}extrapolate`]: false,
  [`${P}headWidth`]: 87,
  [`${P}headHeight`]: 92,
  [`${P}standoff`]: 90,
});
const NAMES = ['A', 'B', 'C', 'D'];
const XYZ = ['x', 'y', 'z'];
/** The paper's figures (Bi et al. 2015, §4.2), max / min mm. */
const PAPER = { uncorrected: [5.586, 3.302], bilinear: [2.442, 0.175], coons: [0.628, 0.005] };
const EXAMPLE_FILE = 'paper_60deg_panel.stl';
/** Colours (Okabe & Ito). */
const COLORS = { reference: '#CC79A7', nominal: '#6b7480', corrected: '#009E73', vector: '#D55E00' };
/** Marker half size as a fraction of the model's diagonal. */
const MARKER = 0.01;

const $ = (id) => document.getElementById(id);
const input = (id, cls, label) => `<input type="number" step="any" inputmode="decimal" class="${cls}" id="${id}" aria-label="${label}">`;

const GROUPS = [['nom', 'nominal'], ['act', 'measured'], ['n', 'normal']];

const refRows = NAMES.map((n, i) => `<tbody>${GROUPS.map(([g, label], k) => `<tr${k === 0 ? ' class="first"' : ''}>` +
  `<th scope="row">${k === 0 ? `<strong>${n}</strong> ` : ''}${label}</th>` +
  XYZ.map((c) => `<td>${input(`drill-ref-${i}-${g}${c}`, 'xyz', `${n} ${label} ${c}`)}</td>`).join('') + '</tr>').join('')}</tbody>`).join('');
const readingRows = NAMES.map((n, i) => `<tr><th scope="row">${n}</th>` +
  [0, 1, 2, 3].map((k) => `<td>${input(`drill-read-${i}-${k}`, 'reading', `${n} reading ${k + 1}`)}</td>`).join('') + '</tr>').join('');
const field = (key, label, unit, title = '') => `<label class="field"${title ? ` title="${title}"` : ''}><span>${label}</span>` +
  `<input type="number" step="any" inputmode="decimal" id="drill-${key}" name="${key}"><span class="unit" data-unit="${unit}"></span></label>`;

const PANEL = `
  <h2 id="drill-heading">Hole correction</h2>
  <p class="hint">Four measured reference holes correct the nominal holes for the panel's real shape
    (Coons error surface, Bi et al. 2015). Lengths in the file unit (<span data-unit="length"></span>).</p>
  <div class="form-actions"><button type="button" id="drill-example-button">Paper's example (60° panel)</button></div>
  <label class="field choice"><span>Clicks on the model</span><select id="drill-pick" aria-describedby="drill-pick-hint">
    <option value="off">select patches only</option>
    ${NAMES.map((n, i) => `<option value="ref-${i}">set reference ${n}, then the next</option>`).join('')}
    <option value="holes">add holes to drill</option></select></label>
  <p class="hint" id="drill-pick-hint">A reference takes the clicked point as its nominal position and the model's normal
    there; type its measured position. After D, clicks add holes to the list.</p>
  <fieldset><legend>Reference holes A, B, C, D (in order around the region, A→B across the flight direction)</legend>
    <table class="drill-refs" id="drill-refs">
      <thead><tr><th></th><th scope="col">x</th><th scope="col">y</th><th scope="col">z</th></tr></thead>
      ${refRows}</table>
    <div class="form-actions">
      <button type="button" id="drill-mesh-normals" title="The model's normal at each measured position (the model should be the real panel)">Normals from the model</button>
    </div>
    <details id="drill-lasers"><summary>Normals from four laser readings</summary>
      <p class="hint">The sensor head: four parallel beams at the corners of a rectangle, aimed along the current normal,
        from the standoff above the measured hole; readings are the distances along the beams (A's four, then B's…).</p>
      ${field('headWidth', 'Head width', 'length')}${field('headHeight', 'Head height', 'length')}${field('standoff', 'Standoff', 'length', 'Distance from the head to the hole along the normal')}
      <table class="drill-readings"><thead><tr><th></th><th scope="col">1</th><th scope="col">2</th><th scope="col">3</th><th scope="col">4</th></tr></thead><tbody>${readingRows}</tbody></table>
      <div class="form-actions">
        <button type="button" id="drill-simulate" title="Cast the four beams onto the model">Simulate on the model</button>
        <button type="button" id="drill-laser-normals">Normals from readings</button>
      </div>
    </details>
  </fieldset>
  <fieldset><legend>Holes to drill (id,x,y,z — header optional)</legend>
    <textarea id="drill-holes" rows="6" spellcheck="false" placeholder="id,x,y,z&#10;H01,120.5,980.2,80"></textarea>
    <label class="file-button">Open a CSV… <input type="file" id="drill-holes-file" accept=".csv,.txt,text/csv,text/plain"></label>
    <p id="drill-holes-report" class="hint" aria-live="polite"></p>
  </fieldset>
  <fieldset><legend>Correction</legend>
    <label><input type="radio" name="drill-method" value="coons"> Coons patch (the paper's method)</label>
    <label><input type="radio" name="drill-method" value="bilinear"> Bilinear (baseline)</label>
    <label class="check"><input type="checkbox" id="drill-extrapolate"> Also correct holes outside A–D (extrapolated, flagged)</label>
    ${field('approach', 'Approach distance', 'length')}${field('retract', 'Retract distance', 'length')}
  </fieldset>
  <p id="drill-error" class="field-error" aria-live="polite"></p>
  <div class="form-actions"><button type="button" id="drill-run" class="primary">Correct holes</button></div>`;

const RESULTS = `
  <section aria-labelledby="drill-results-heading">
    <h2 id="drill-results-heading">Corrected holes</h2>
    <p id="drill-summary" class="summary">No correction yet: fill the references and holes, or press <strong>Paper's example</strong>.</p>
    <div id="drill-figures" hidden>
      <table class="quality-table" id="drill-compare"><thead></thead><tbody></tbody></table>
      <p id="drill-compare-note" class="hint"></p>
      <label class="field"><span>Error vectors drawn ×</span><input type="number" step="any" min="0" id="drill-scale" name="scale"><span class="unit"></span></label>
      <div class="table-scroll hole-table"><table class="quality-table" id="drill-table"><thead></thead><tbody></tbody></table></div>
    </div>
  </section>
  <section aria-labelledby="drill-export-heading">
    <h2 id="drill-export-heading">Export</h2>
    <div class="export-buttons">
      <button type="button" data-format="holes" disabled title="id,x,y,z,nx,ny,nz per hole, file units, normal out of the part">Holes · CSV</button>
      <button type="button" data-format="rapid" disabled title="ABB RAPID: approach, drill, retract per hole, mm">ABB RAPID</button>
      <button type="button" data-format="krl" disabled title="KUKA KRL: approach, drill, retract per hole, mm">KUKA KRL</button>
      <button type="button" data-format="csv" disabled title="Tool path: one row per pose">Tool path · CSV</button>
      <button type="button" data-format="json" disabled title="Tool path as JSON">Tool path · JSON</button>
    </div>
    ${cellHtml('drill')}
  </section>`;

const sub = (a, b, i) => [a[3 * i] - b[3 * i], a[3 * i + 1] - b[3 * i + 1], a[3 * i + 2] - b[3 * i + 2]];
const norm = (v) => Math.hypot(v[0], v[1], v[2]);

/** Max and min distance between matching points of two flat xyz arrays. */
function maxMin(a, b) {
  let max = 0;
  let min = Infinity;
  for (let i = 0; i < a.length / 3; i++) {
    const d = norm(sub(a, b, i));
    max = Math.max(max, d);
    min = Math.min(min, d);
  }
  return [max, min];
}

/** Two unit vectors spanning the plane perpendicular to the unit n. */
function frame(n) {
  const helper = Math.abs(n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (v) => v.map((x) => x / norm(v));
  const e1 = unit(cross(n, helper));
  return [e1, cross(n, e1)];
}

class DrillTool {
  id = 'drill';
  title = 'Drill';
  settings = {
    order: 3,
    defaults: DEFAULTS,
    allowed: { [`${P}method`]: ['coons', 'bilinear'] },
    hashKeys: () => [`${P}method`],
  };

  #shell;
  #overlay;
  #result = null; // { params, ids, holes, coons, bilinear, truth, model }
  #example = null; // DrillPaperExample while its panel is on screen
  #pendingExample = null;
  #frameExample = false; // look at the example's panel from outside once its holes are drawn
  #listening = false; // the viewer's picks reach #onPick
  #pendingDraw = 0; // the latest drawing of the form's references and holes (older answers are dropped)

  mount(shell, { panel, results, overlay }) {
    this.#shell = shell;
    panel.innerHTML = PANEL;
    panel.setAttribute('aria-labelledby', 'drill-heading');
    results.innerHTML = RESULTS;
    mountCell(results, () => shell.state.settings);
    this.#overlay = overlay;
    this.#wire(panel, results);
    this.#renderForm();
  }

  get #s() {
    return this.#shell.state.settings;
  }

  #renderForm() {
    const s = this.#s;
    for (const k of ['approach', 'retract', 'headWidth', 'headHeight', 'standoff', 'scale']) $(`drill-${k}`).value = s[P + k];
    $('drill-extrapolate').checked = s[`${P}extrapolate`];
    for (const r of document.getElementsByName('drill-method')) r.checked = r.value === s[`${P}method`];
    this.#validate();
  }

  #save() {
    const s = this.#s;
    for (const k of ['approach', 'retract', 'headWidth', 'headHeight', 'standoff', 'scale']) {
      const v = Number($(`drill-${k}`).value);
      if ($(`drill-${k}`).value.trim() !== '' && Number.isFinite(v) && v >= 0) s[P + k] = v;
    }
    s[`${P}extrapolate`] = $('drill-extrapolate').checked;
    s[`${P}method`] = this.#method();
    persistSettings(s);
  }

  #method() {
    return [...document.getElementsByName('drill-method')].find((r) => r.checked)?.value ?? 'coons';
  }

  #validate() {
    const busyless = Boolean(this.#shell.state.model);
    $('drill-run').disabled = !busyless;
    $('drill-mesh-normals').disabled = !busyless;
    $('drill-simulate').disabled = !busyless;
  }

  // ---------------------------------------------------------------- reading the form

  #vec(id) {
    const v = XYZ.map((c) => $(`${id}${c}`).value.trim());
    if (v.every((x) => x === '')) return null;
    const n = v.map(Number);
    return v.some((x) => x === '') || !n.every(Number.isFinite) ? undefined : n;
  }

  #setVec(id, v, digits = 6) {
    XYZ.forEach((c, k) => { $(`${id}${c}`).value = v ? String(Number(v[k].toFixed(digits))) : ''; });
  }

  /** The four references, or throws an Error naming the first bad cell. */
  #references() {
    return NAMES.map((name, i) => {
      const get = (g, what, required) => {
        const v = this.#vec(`drill-ref-${i}-${g}`);
        if (v === undefined) throw new Error(`Reference ${name}: enter three numbers for the ${what}.`);
        if (v === null && required) throw new Error(`Reference ${name}: the ${what} is missing.`);
        return v;
      };
      const ref = { nominal: get('nom', 'nominal position', true), actual: get('act', 'measured position', true) };
      const normal = get('n', 'normal', true);
      if (norm(normal) === 0) throw new Error(`Reference ${name}: the normal must not be zero.`);
      ref.normal = normal;
      const nn = this.#example?.references[i].nominalNormal;
      if (nn && this.#sameAsExample(i, ref)) ref.nominalNormal = nn;
      return ref;
    });
  }

  /** True while reference `i` still holds the example's nominal position (its CAD normal applies). */
  #sameAsExample(i, ref) {
    const e = this.#example?.references[i];
    return e && e.nominal.every((x, k) => Math.abs(x - ref.nominal[k]) < 1e-6);
  }

  // ---------------------------------------------------------------- engine

  /** Runs `fn(progress)` as a job, with the model given back to a fresh worker first. */
  #job(label, fn) {
    const shell = this.#shell;
    return shell.enqueue(label, async (progress, checkpoint) => {
      shell.hideAlert();
      if (shell.state.model && !shell.engine.hasMesh) await shell.restoreEngine(progress, checkpoint);
      await fn(progress);
    });
  }

  #parseHoles(progress) {
    return this.#shell.engine.request('drill.parseHoles', { text: $('drill-holes').value }, { onProgress: progress });
  }

  #renderHoleReport(list) {
    const lines = [`${list.ids.length} hole${list.ids.length === 1 ? '' : 's'} read${list.header ? ' (first line taken as a header)' : ''}.`];
    for (const e of list.errors.slice(0, 8)) lines.push(`Line ${e.line}: ${e.message}.`);
    if (list.errors.length > 8) lines.push(`…and ${list.errors.length - 8} more bad rows.`);
    const el = $('drill-holes-report');
    el.textContent = lines.join(' ');
    el.classList.toggle('field-error', list.errors.length > 0);
  }

  run() {
    this.#save();
    $('drill-error').textContent = '';
    let references;
    try {
      references = this.#references();
    } catch (error) {
      $('drill-error').textContent = error.message;
      return Promise.resolve();
    }
    const shell = this.#shell;
    return this.#job('Correcting the holes', async (progress) => {
      const list = await this.#parseHoles(progress);
      this.#renderHoleReport(list);
      if (!list.ids.length) {
        $('drill-error').textContent = 'No hole to correct: enter rows id,x,y,z.';
        return;
      }
      const params = { references, holes: Array.from(list.positions), extrapolate: $('drill-extrapolate').checked };
      let out;
      try {
        out = await shell.engine.request('drill.correct', { params }, { onProgress: progress });
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        $('drill-error').textContent = error.message;
        throw new Error(`The correction failed: ${error.message}`);
      }
      const truth = this.#example && shell.state.model?.name === EXAMPLE_FILE && list.ids.join() === this.#example.ids.join()
        ? this.#example.truth : null;
      this.#result = { params, ids: list.ids, holes: list.positions, ...out, truth, model: shell.state.model.name };
      this.#renderResults();
      this.#draw();
      if (this.#frameExample) {
        this.#frameExample = false;
        shell.viewer.setView('top');
      }
      shell.setStatus(`Corrected ${list.ids.length} holes${list.errors.length ? ` (${list.errors.length} bad row${list.errors.length === 1 ? '' : 's'} skipped)` : ''}.`);
    });
  }

  async loadExample() {
    const shell = this.#shell;
    let ex = null;
    await shell.enqueue('Building the paper\'s example', async (progress) => {
      ex = await shell.engine.request('drill.example', {}, { onProgress: progress });
    });
    if (!ex) return;
    this.#example = ex;
    NAMES.forEach((_, i) => {
      const r = ex.references[i];
      this.#setVec(`drill-ref-${i}-nom`, r.nominal);
      this.#setVec(`drill-ref-${i}-act`, r.actual);
      this.#setVec(`drill-ref-${i}-n`, r.normal, 6);
    });
    const rows = ex.ids.map((id, i) => `${id},${[0, 1, 2].map((k) => Number(ex.holes[3 * i + k].toFixed(6))).join(',')}`);
    $('drill-holes').value = `id,x,y,z\n${rows.join('\n')}\n`;
    $('drill-holes-report').textContent = '';
    if (shell.state.settings.unit !== 'mm') shell.setUnit('mm');
    this.#pendingExample = true;
    await shell.openFile(new File([ex.stl], EXAMPLE_FILE));
    // onModelLoaded runs the correction.
  }

  // ---------------------------------------------------------------- results

  #correction() {
    return this.#result?.[this.#s[`${P}method`]] ?? null;
  }

  #renderResults() {
    const r = this.#result;
    const u = this.#shell.unitOf.length();
    const has = Boolean(r);
    $('drill-figures').hidden = !has;
    for (const b of document.querySelectorAll('#drill-export-heading + .export-buttons button')) b.disabled = !has;
    if (!has) {
      $('drill-summary').textContent = 'No correction yet: fill the references and holes, or press Paper\'s example.';
      this.#renderLegend();
      return;
    }
    const method = this.#s[`${P}method`];
    const c = r[method];
    const outside = c.outside.reduce((a, b) => a + b, 0);
    $('drill-summary').textContent = `${r.ids.length} holes corrected by the ${method === 'coons' ? 'Coons patch' : 'bilinear interpolation'} on ${r.model}` +
      (outside ? `; ${outside} outside A–D (extrapolated).` : '.');
    const thead = $('drill-compare').tHead;
    const tbody = $('drill-compare').tBodies[0];
    const rows = [];
    if (r.truth) {
      thead.innerHTML = `<tr><th scope="col">Error to the true holes (${u})</th><th scope="col">max</th><th scope="col">min</th><th scope="col">Paper max / min (mm)</th></tr>`;
      const figures = { uncorrected: maxMin(r.holes, r.truth), bilinear: maxMin(r.bilinear.corrected, r.truth), coons: maxMin(r.coons.corrected, r.truth) };
      for (const [key, label] of [['uncorrected', 'Uncorrected'], ['bilinear', 'Bilinear'], ['coons', 'Coons (ours)']]) {
        rows.push(`<tr data-row="${key}"><th scope="row">${label}</th><td>${num(figures[key][0], 3)}</td><td>${num(figures[key][1], 3)}</td>` +
          `<td>${PAPER[key][0]} / ${PAPER[key][1]}</td></tr>`);
      }
      $('drill-compare-note').textContent = 'The true holes are known here: they are the nominal holes carried onto the deformed panel. ' +
        'The paper\'s panel coordinates are not published, so our deformation (3 mm larger radius, stretch, twist, small rigid move) differs; ' +
        'the ranking uncorrected > bilinear > Coons is what carries over.';
    } else {
      thead.innerHTML = `<tr><th scope="col">Correction (${u})</th><th scope="col">max</th><th scope="col">mean</th></tr>`;
      const stats = (a, b) => {
        let max = 0;
        let sum = 0;
        const n = a.length / 3;
        for (let i = 0; i < n; i++) {
          const d = norm(sub(a, b, i));
          max = Math.max(max, d);
          sum += d;
        }
        return [max, sum / n];
      };
      for (const [label, s] of [['Coons: |corrected − nominal|', stats(r.coons.corrected, r.holes)],
        ['Bilinear: |corrected − nominal|', stats(r.bilinear.corrected, r.holes)],
        ['Coons − bilinear', stats(r.coons.corrected, r.bilinear.corrected)]]) {
        rows.push(`<tr><th scope="row">${label}</th><td>${num(s[0], 3)}</td><td>${num(s[1], 3)}</td></tr>`);
      }
      $('drill-compare-note').textContent = 'Without the true holes the table shows how far each method moves the holes, and how far the two methods differ.';
    }
    tbody.innerHTML = rows.join('');
    const table = $('drill-table');
    table.tHead.innerHTML = `<tr><th scope="col">Hole</th><th scope="col">Δx</th><th scope="col">Δy</th><th scope="col">Δz</th><th scope="col">|Δ| (${u})</th>` +
      (r.truth ? '<th scope="col">Error after</th>' : '') + '<th scope="col"></th></tr>';
    table.tBodies[0].innerHTML = r.ids.map((id, i) => {
      const d = sub(c.corrected, r.holes, i);
      const after = r.truth ? `<td>${num(norm(sub(c.corrected, r.truth, i)), 3)}</td>` : '';
      return `<tr><th scope="row">${id}</th>${d.map((x) => `<td>${num(x, 3)}</td>`).join('')}<td>${num(norm(d), 3)}</td>${after}` +
        `<td>${c.outside[i] ? '<span title="outside the reference quadrilateral: extrapolated">outside</span>' : ''}</td></tr>`;
    }).join('');
    this.#renderLegend();
  }

  #renderLegend() {
    const r = this.#result;
    if (!r) {
      this.#overlay.replaceChildren();
      this.#overlay.hidden = true;
      return;
    }
    const scale = this.#s[`${P}scale`];
    const items = [
      [COLORS.reference, 'Reference holes A–D (nominal → measured, same scale)'],
      [COLORS.nominal, 'Nominal holes'],
      [COLORS.corrected, `Corrected holes (${this.#s[`${P}method`] === 'coons' ? 'Coons' : 'bilinear'}), at the tips`],
      [COLORS.vector, `Corrections drawn × ${num(scale, 3)}`],
    ];
    const list = document.createElement('ul');
    list.className = 'legend-list';
    for (const [color, label] of items) {
      const li = document.createElement('li');
      const sw = document.createElement('span');
      sw.className = 'legend-swatch';
      sw.style.backgroundColor = color;
      li.append(sw, label);
      list.append(li);
    }
    const title = document.createElement('p');
    title.className = 'legend-title';
    title.textContent = 'Drilling';
    this.#overlay.replaceChildren(title, list);
    this.#overlay.hidden = false;
  }

  #draw() {
    const viewer = this.#shell.viewer;
    const r = this.#result;
    if (!r) {
      for (const id of ['refs', 'nominal', 'corrected', 'vectors']) viewer.removeLayer(`drill.${id}`);
      return;
    }
    const report = this.#shell.state.model.report;
    const diag = Math.hypot(...[0, 1, 2].map((k) => report.bboxMax[k] - report.bboxMin[k]));
    const h = diag * MARKER;
    const cross = (out, p, normal) => {
      const [e1, e2] = frame(normal);
      for (const e of [e1, e2]) out.push(p[0] - h * e[0], p[1] - h * e[1], p[2] - h * e[2], p[0] + h * e[0], p[1] + h * e[1], p[2] + h * e[2]);
    };
    const c = this.#correction();
    const scale = this.#s[`${P}scale`];
    const nominal = [];
    const corrected = [];
    const vectors = [];
    for (let i = 0; i < r.ids.length; i++) {
      const n = [c.normals[3 * i], c.normals[3 * i + 1], c.normals[3 * i + 2]];
      const p = [r.holes[3 * i], r.holes[3 * i + 1], r.holes[3 * i + 2]];
      const q = [c.corrected[3 * i], c.corrected[3 * i + 1], c.corrected[3 * i + 2]];
      cross(nominal, p, n);
      cross(corrected, p.map((x, k) => x + scale * (q[k] - x)), n);
      vectors.push(...p, ...p.map((x, k) => x + scale * (q[k] - x)));
    }
    const refs = [];
    for (const ref of r.params.references) {
      const n = ref.normal.map((x) => x / norm(ref.normal));
      cross(refs, ref.nominal, n);
      const tip = ref.nominal.map((x, k) => x + scale * (ref.actual[k] - x));
      refs.push(...ref.nominal, ...tip);
      cross(refs, tip, n);
    }
    viewer.setLayer('drill.refs', { kind: 'lines', positions: Float32Array.from(refs), color: COLORS.reference });
    viewer.setLayer('drill.nominal', { kind: 'lines', positions: Float32Array.from(nominal), color: COLORS.nominal });
    viewer.setLayer('drill.corrected', { kind: 'lines', positions: Float32Array.from(corrected), color: COLORS.corrected });
    viewer.setLayer('drill.vectors', { kind: 'lines', positions: Float32Array.from(vectors), color: COLORS.vector });
    this.#showLayers(this.#shell.activeTool === this);
  }

  #showLayers(visible) {
    for (const id of ['refs', 'nominal', 'corrected', 'vectors']) this.#shell.viewer.setLayerVisible(`drill.${id}`, visible && Boolean(this.#result));
    this.#shell.viewer.setLayerVisible('drill.form', visible && !this.#result);
    this.#overlay.hidden = !visible || !this.#result;
    this.#syncCursor(visible);
  }

  #clear() {
    this.#result = null;
    this.#draw();
    this.#renderResults();
    this.#drawForm();
  }

  // ---------------------------------------------------------------- clicks on the model

  #pickMode() {
    return $('drill-pick').value;
  }

  #setPickMode(mode) {
    $('drill-pick').value = mode;
    this.#syncCursor();
  }

  /** A crosshair over the model while clicks there set references or add holes. */
  #syncCursor(active = this.#shell.activeTool === this) {
    const canvas = this.#shell.viewer?.canvas;
    if (canvas) canvas.style.cursor = active && this.#pickMode() !== 'off' ? 'crosshair' : '';
  }

  /** A click on the model at `point` (model coordinates), as the pick mode says. */
  #onPick(point) {
    const mode = this.#pickMode();
    if (this.#shell.activeTool !== this || mode === 'off' || !point) return;
    if (this.#result) this.#clear(); // the result on screen would no longer match the form
    const at = `${pointText(point)} ${this.#shell.unitOf.length()}`;
    if (mode === 'holes') {
      const id = this.#addHole(point);
      this.#shell.setStatus(`Hole ${id} added at ${at}.`);
      this.#drawForm();
      return;
    }
    const i = Number(mode.slice('ref-'.length));
    this.#setVec(`drill-ref-${i}-nom`, point);
    this.#setVec(`drill-ref-${i}-n`, null);
    this.#setPickMode(i < NAMES.length - 1 ? `ref-${i + 1}` : 'holes');
    this.#drawForm();
    this.#job(`Reading the model's normal at reference ${NAMES[i]}`, async (progress) => {
      const found = await this.#shell.engine.request('drill.meshNormals', { points: point }, { onProgress: progress });
      // A later click on the same reference wins.
      if (this.#vec(`drill-ref-${i}-nom`)?.every((x, k) => x === Number(point[k].toFixed(6)))) {
        this.#setVec(`drill-ref-${i}-n`, Array.from(found.normals.slice(0, 3)), 6);
      }
      this.#shell.setStatus(`Reference ${NAMES[i]} set at ${at} with the model's normal there: enter its measured position.`);
      this.#drawForm();
    });
  }

  /** Appends a row for `point` to the hole list, under the first free id H01, H02…: the id. */
  #addHole(point) {
    const area = $('drill-holes');
    const text = area.value.replace(/\s+$/, '');
    const taken = new Set(text.split('\n').map((line) => line.split(/[,;\t]/)[0].trim()));
    let k = 1;
    while (taken.has(`H${String(k).padStart(2, '0')}`)) k++; // at most one past the rows
    const id = `H${String(k).padStart(2, '0')}`;
    area.value = `${text === '' ? 'id,x,y,z' : text}\n${id},${point.map((x) => Number(x.toFixed(6))).join(',')}\n`;
    return id;
  }

  /**
   * Before a correction: the form's reference nominal positions and holes, marked on the
   * model (the holes as the engine reads the list), so that clicked and typed positions show
   * where they are.
   */
  async #drawForm() {
    const shell = this.#shell;
    const viewer = shell.viewer;
    const token = ++this.#pendingDraw;
    const report = shell.state.model?.report;
    if (!viewer || !report || this.#result) {
      viewer?.removeLayer('drill.form');
      return;
    }
    let list = null;
    if ($('drill-holes').value.trim() !== '' && shell.engine) {
      try {
        list = await shell.engine.request('drill.parseHoles', { text: $('drill-holes').value });
      } catch {
        // drawn without the holes (the engine is restarting); a run reports the list
      }
    }
    if (token !== this.#pendingDraw || this.#result) return;
    if (list) this.#renderHoleReport(list);
    else if ($('drill-holes').value.trim() === '') $('drill-holes-report').textContent = '';
    const holes = list?.positions ?? [];
    const h = Math.hypot(...[0, 1, 2].map((k) => report.bboxMax[k] - report.bboxMin[k])) * MARKER;
    const positions = [];
    const colors = [];
    const mark = (p, rgb) => {
      pointMark(positions, p, h);
      for (let k = 0; k < 6; k++) colors.push(...rgb);
    };
    NAMES.forEach((_, i) => {
      const p = this.#vec(`drill-ref-${i}-nom`);
      if (p) mark(p, hexRgb(COLORS.reference));
    });
    for (let i = 0; i + 2 < holes.length; i += 3) mark([holes[i], holes[i + 1], holes[i + 2]], hexRgb(COLORS.nominal));
    if (positions.length === 0) {
      viewer.removeLayer('drill.form');
      return;
    }
    viewer.setLayer('drill.form', { kind: 'lines', positions: Float32Array.from(positions), colors: Uint8Array.from(colors) });
    viewer.setLayerVisible('drill.form', shell.activeTool === this);
  }

  // ---------------------------------------------------------------- normals

  #meshNormals() {
    let points;
    try {
      points = NAMES.map((name, i) => {
        const v = this.#vec(`drill-ref-${i}-act`) ?? this.#vec(`drill-ref-${i}-nom`);
        if (!v) throw new Error(`Reference ${name}: enter its measured (or nominal) position first.`);
        return v;
      }).flat();
    } catch (error) {
      $('drill-error').textContent = error.message;
      return;
    }
    $('drill-error').textContent = '';
    this.#job('Reading normals from the model', async (progress) => {
      const found = await this.#shell.engine.request('drill.meshNormals', { points }, { onProgress: progress });
      NAMES.forEach((_, i) => this.#setVec(`drill-ref-${i}-n`, Array.from(found.normals.slice(3 * i, 3 * i + 3)), 6));
      const far = Math.max(...found.distances);
      this.#shell.setStatus(`Normals taken from the model (positions up to ${num(far, 3)} ${this.#shell.unitOf.length()} from its surface).`);
    });
  }

  /** Beam origins and directions of the head over each reference (aimed along its normal). */
  #heads() {
    this.#save();
    const s = this.#s;
    return NAMES.map((name, i) => {
      const p = this.#vec(`drill-ref-${i}-act`) ?? this.#vec(`drill-ref-${i}-nom`);
      const n0 = this.#vec(`drill-ref-${i}-n`);
      if (!p || !n0 || norm(n0) === 0) throw new Error(`Reference ${name}: a position and an approximate normal (typed or from the model) are needed to aim the head.`);
      const n = n0.map((x) => x / norm(n0));
      const [e1, e2] = frame(n);
      const corners = [[1, 1], [-1, 1], [-1, -1], [1, -1]];
      const origins = corners.flatMap(([a, b]) => [0, 1, 2].map((k) => p[k] + s[`${P}standoff`] * n[k] +
        (a * s[`${P}headWidth`] * e1[k]) / 2 + (b * s[`${P}headHeight`] * e2[k]) / 2));
      const directions = corners.flatMap(() => n.map((x) => -x));
      return { origins, directions };
    });
  }

  #simulate() {
    let heads;
    try {
      heads = this.#heads();
    } catch (error) {
      $('drill-error').textContent = error.message;
      return;
    }
    $('drill-error').textContent = '';
    this.#job('Simulating the laser readings', async (progress) => {
      const r = await this.#shell.engine.request('drill.laserReadings', {
        origins: heads.flatMap((h) => h.origins), directions: heads.flatMap((h) => h.directions),
      }, { onProgress: progress });
      r.forEach((d, j) => { $(`drill-read-${Math.floor(j / 4)}-${j % 4}`).value = Number.isFinite(d) ? String(Number(d.toFixed(6))) : ''; });
      const missed = r.filter((d) => !Number.isFinite(d)).length;
      this.#shell.setStatus(missed ? `${missed} beams missed the model (left blank).` : 'Readings simulated on the model.');
    });
  }

  #laserNormals() {
    let heads;
    try {
      heads = this.#heads().map((h, i) => {
        const readings = [0, 1, 2, 3].map((k) => Number($(`drill-read-${i}-${k}`).value.trim() || NaN));
        if (!readings.every(Number.isFinite)) throw new Error(`Reference ${NAMES[i]}: enter its four readings.`);
        return { ...h, readings };
      });
    } catch (error) {
      $('drill-error').textContent = error.message;
      return;
    }
    $('drill-error').textContent = '';
    this.#job('Normals from the laser readings', async (progress) => {
      const out = await this.#shell.engine.request('drill.laserNormals', { heads }, { onProgress: progress });
      const bad = [];
      out.forEach((o, i) => {
        if (o.error) bad.push(`Reference ${NAMES[i]}: ${o.error}`);
        else this.#setVec(`drill-ref-${i}-n`, o.normal, 6);
      });
      $('drill-error').textContent = bad.join(' ');
      if (!bad.length) this.#shell.setStatus('Normals computed from the four laser readings of each reference.');
    });
  }

  // ---------------------------------------------------------------- exports

  #export(format) {
    const r = this.#result;
    if (!r) return;
    const shell = this.#shell;
    const stem = fileStem(r.model);
    const c = this.#correction();
    if (format === 'holes') {
      const f = (x) => String(Number(x.toFixed(6)));
      const rows = r.ids.map((id, i) => [id, ...[0, 1, 2].map((k) => f(c.corrected[3 * i + k])), ...[0, 1, 2].map((k) => f(c.normals[3 * i + k]))].join(','));
      download(`id,x,y,z,nx,ny,nz\n${rows.join('\n')}\n`, `${stem}_holes_corrected.csv`, 'text/csv');
      shell.setStatus(`Saved ${stem}_holes_corrected.csv (${r.ids.length} holes, ${shell.unitOf.length()}).`);
      return;
    }
    const name = `dr_${stem.replace(/[^A-Za-z0-9_]/g, '_')}`.slice(0, 16).replace(/_+$/, '');
    const params = { ...r.params, method: this.#s[`${P}method`] };
    const pose = { approach: this.#s[`${P}approach`], retract: this.#s[`${P}retract`] };
    this.#job(`Writing the ${format.toUpperCase()} program`, async (progress) => {
      let out;
      try {
        out = await shell.engine.request('drill.program', { params, pose, format, options: { mmPerUnit: shell.mmPerUnit, name, ...cellOptions(this.#s) }, stem },
          { onProgress: progress });
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        throw new Error(`The ${format.toUpperCase()} export failed: ${error.message}`);
      }
      const type = out.fileName.endsWith('.zip') ? 'application/zip' : out.fileName.endsWith('.json') ? 'application/json' : 'text/plain';
      download(out.bytes, out.fileName, type);
      shell.setStatus(`Saved ${out.fileName}${out.fileCount > 1 ? ` with ${out.fileCount} files` : ''}.`);
    });
  }

  #wire(panel, results) {
    $('drill-example-button').addEventListener('click', () => this.loadExample());
    $('drill-run').addEventListener('click', () => this.run());
    $('drill-mesh-normals').addEventListener('click', () => this.#meshNormals());
    $('drill-simulate').addEventListener('click', () => this.#simulate());
    $('drill-laser-normals').addEventListener('click', () => this.#laserNormals());
    $('drill-holes-file').addEventListener('change', async (event) => {
      const file = event.target.files?.[0];
      if (!file) return;
      $('drill-holes').value = await file.text();
      event.target.value = '';
      this.#job('Reading the hole list', async (progress) => {
        this.#renderHoleReport(await this.#parseHoles(progress));
        if (this.#result) this.#clear(); // the list on screen is no longer the one corrected
        else this.#drawForm();
      });
    });
    $('drill-pick').addEventListener('change', () => this.#syncCursor());
    panel.addEventListener('change', (event) => {
      if (event.target.id === 'drill-pick') return;
      this.#save();
      if (!this.#result) this.#drawForm();
      if (event.target.name === 'drill-method' && this.#result) {
        this.#renderResults();
        this.#draw();
      }
    });
    results.addEventListener('change', (event) => {
      if (event.target.id !== 'drill-scale') return;
      this.#save();
      if (this.#result) {
        this.#draw();
        this.#renderLegend();
      }
    });
    for (const b of results.querySelectorAll('.export-buttons button')) b.addEventListener('click', () => this.#export(b.dataset.format));
  }

  // ---------------------------------------------------------------- shell hooks

  onModelLoaded(model) {
    this.#clear();
    this.#validate();
    if (this.#pendingExample && model.name === EXAMPLE_FILE) {
      this.#pendingExample = null;
      this.#frameExample = true;
      // After the load job: the shell runs jobs one at a time.
      queueMicrotask(() => this.run());
    } else if (model.name !== EXAMPLE_FILE) {
      this.#example = null;
    }
  }

  onUnitsChanged({ unitChanged }) {
    if (unitChanged && this.#result) this.#clear();
    else if (this.#result) this.#renderResults();
  }

  onSettingsChanged() {
    renderCell(this.#s);
    this.#renderForm();
  }

  onActivate() {
    const viewer = this.#shell.viewer;
    if (viewer && !this.#listening) {
      this.#listening = true;
      viewer.addEventListener('pick', (event) => this.#onPick(event.detail.point));
    }
    this.#showLayers(true);
    this.#drawForm();
    this.#validate();
  }

  onDeactivate() {
    this.#showLayers(false);
  }
}

export const drillTool = new DrillTool();
