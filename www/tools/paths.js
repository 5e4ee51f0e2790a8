// Paths tool (issue 8): geodesically equidistant passes from a source on the surface — a
// section plane through a clicked point, or a boundary loop of the mesh or of the selected
// patch — by the accurate method (window propagation merging windows within a tolerance;
// the default), the exact method (window propagation, the reference), the fast method
// (unfolded wavefronts, approximate) or the voxel method of the paper. Draws the distance as a colour map, the passes
// coloured by level (closed solid, open dashed) and the source, lists the passes, compares the
// methods on the same source against the exact one, and exports through the ToolPath
// exporters (CSV, JSON, ABB RAPID, KUKA KRL). Lengths are typed in mm whatever the file's
// unit; the worker (worker/paths.js) gets file units.
import { CancelledError } from '../app/engine.js';
import { download, fileStem } from '../app/download.js';
import { fieldText, integer, num, pointText } from '../app/format.js';
import { persistSettings } from '../app/settings.js';
import { cellHtml, cellOptions, mountCell, renderCell } from '../app/cell.js';
import { hexRgb, viridis, viridisInto } from '../app/colours.js';
import { pointMark } from '../viewer/viewer.js';

const P = 'paths.'; // settings key prefix

/** The paper's bead: 6.4 mm wide, overlap factor 0.738 (→ 4.72 mm between passes). */
const FIELDS = [
  // key, label, unit, default, lower bound (exclusive), upper bound (inclusive), group
  { key: 'spacing', label: 'Pass spacing', unit: 'mm', value: 10, min: 0, group: 'spacing', title: 'Geodesic distance between neighbouring passes' },
  { key: 'beadWidth', label: 'Bead width', unit: 'mm', value: 6.4, min: 0, group: 'bead' },
  { key: 'overlap', label: 'Overlap factor', unit: '', value: 0.738, min: 0, max: 1, group: 'bead', title: 'Spacing = bead width × overlap factor (the paper: 0.738)' },
  { key: 'voxelSize', label: 'Voxel size', unit: 'mm', value: 0, min: 0, group: 'method', blank: true, title: 'Edge of the voxels of the voxel method; empty: a quarter of the mean edge length' },
  { key: 'maxLevel', label: 'Most passes', unit: '', value: 200, min: 0, group: 'passes', integer: true, title: 'Passes beyond this level are left out' },
];
const CHOICES = {
  source: ['plane', 'boundary', 'points'],
  axis: ['x', 'y', 'z', 'view'],
  scope: ['mesh', 'patch'],
  spacingMode: ['spacing', 'bead'],
  method: ['accurate', 'exact', 'fast', 'voxel', 'compare'],
  order: ['zigzag', 'oneWay'],
  loop: ['all', '0', '1', '2', '3'],
};
const DEFAULTS = Object.freeze(Object.fromEntries([
  ...FIELDS.map((f) => [P + f.key, f.value]),
  ...Object.entries(CHOICES).map(([k, v]) => [P + k, v[0]]),
  [`${P}showMap`, true],
  [`${P}closedLoop`, false],
  [`${P}showPaths`, true],
]));
/** Passes cycle through these (Okabe & Ito, black first) so that neighbouring levels differ. */
const LEVEL_COLORS = ['#1d232a', '#E69F00', '#56B4E9', '#CC79A7', '#0072B2', '#D55E00'];
const SOURCE_COLOR = '#ff2a2a';
/** The cross where a method differs most from the reference (exact) distance. */
const DIFF_COLOR = '#ffffff';
const UNREACHED = [160, 164, 168];
/** Rows of the pass table at most (the exports carry all of them). */
const MAX_ROWS = 300;

const $ = (id) => document.getElementById(id);

function fieldRow(f) {
  const title = f.title ? ` title="${f.title}"` : '';
  return `<label class="field"${title}><span>${f.label}</span>` +
    `<input type="number" name="${f.key}" id="paths-${f.key}" step="any" inputmode="decimal" aria-describedby="paths-error"${f.blank ? ' placeholder="auto"' : ''}>` +
    `<span class="unit">${f.unit}</span></label>`;
}
const group = (g) => FIELDS.filter((f) => f.group === g).map(fieldRow).join('');
/** "accurate method", or what the accurate method ran when it answered by another (the
 *  exact distance on a small surface with corners or holes). */
const methodLabel = (run) => (run.ran && run.ran !== run.method
  ? `${run.method} method (the ${run.ran} distance: small surface with corners or holes)`
  : `${run.method} method`);
const radio = (name, value, label) => `<label><input type="radio" name="${name}" value="${value}"> ${label}</label>`;

const PANEL = `
  <h2 id="paths-heading">Equidistant paths</h2>
  <form id="paths-form" novalidate>
    <fieldset>
      <legend>Source</legend>
      ${radio('source', 'plane', 'a section plane through a point')}
      <div class="indent">
        <label class="check">Plane normal <select id="paths-axis" name="axis">
          <option value="x">X</option><option value="y">Y</option><option value="z">Z</option><option value="view">view direction</option></select></label>
        <p class="hint" id="paths-point">Point: the model's centre. Click the surface to choose one. The piece of the section nearest the point is the source.</p>
      </div>
      ${radio('source', 'boundary', 'the boundary')}
      <div class="indent">
        <label class="check">Loop <select id="paths-loop" name="loop">
          <option value="all">every loop</option><option value="0">the longest</option><option value="1">the 2nd longest</option>
          <option value="2">the 3rd longest</option><option value="3">the 4th longest</option></select></label>
      </div>
      ${radio('source', 'points', 'clicked points, joined along the surface')}
      <div class="indent">
        <p class="hint" id="paths-points">No points yet: click the surface.</p>
        <label class="check"><input type="checkbox" id="paths-closedLoop" name="closedLoop"> Close the loop</label>
        <button type="button" id="paths-undo-point">Remove the last point</button>
        <button type="button" id="paths-clear-points">Clear</button>
      </div>
    </fieldset>
    <fieldset>
      <legend>On</legend>
      ${radio('scope', 'mesh', 'the whole mesh')}
      ${radio('scope', 'patch', '<span id="paths-patch-label">the selected patch</span>')}
    </fieldset>
    <fieldset>
      <legend>Spacing</legend>
      ${radio('spacingMode', 'spacing', 'typed')}
      ${radio('spacingMode', 'bead', 'bead width × overlap')}
      ${group('spacing')}${group('bead')}
      <p class="hint" id="paths-spacing-hint"></p>
      ${group('passes')}
      <label class="check">Order <select id="paths-order" name="order">
        <option value="zigzag">zig-zag</option><option value="oneWay">one direction</option></select></label>
    </fieldset>
    <fieldset>
      <legend>Method</legend>
      ${radio('method', 'accurate', 'accurate (virtual sources, or exact on a small surface with corners or holes; the default)')}
      ${radio('method', 'exact', 'exact (window propagation; slow on large curved meshes)')}
      ${radio('method', 'fast', 'fast (unfolded wavefronts; approximate on curved meshes)')}
      ${radio('method', 'voxel', 'voxels (the paper)')}
      ${radio('method', 'compare', 'all four, compared with exact')}
      ${group('method')}
    </fieldset>
    <p id="paths-error" class="field-error" aria-live="polite"></p>
    <div class="form-actions">
      <button type="submit" id="paths-run" class="primary">Compute paths</button>
    </div>
  </form>`;

const RESULTS = `
  <section aria-labelledby="paths-results-heading">
    <h2 id="paths-results-heading">Paths</h2>
    <p id="paths-summary" class="summary">No paths yet: choose a source and press <strong>Compute paths</strong>.</p>
    <div id="paths-figures" hidden>
      <p id="paths-diff" class="summary" hidden></p>
      <fieldset class="display-options"><legend>Show</legend>
        <label class="check"><input type="checkbox" id="paths-showMap" name="showMap"> Distance</label>
        <label class="check"><input type="checkbox" id="paths-showPaths" name="showPaths"> Paths</label>
      </fieldset>
      <div class="table-wrap">
        <table class="quality-table" id="paths-table">
          <thead><tr><th scope="col">Level</th><th scope="col">Distance, mm</th><th scope="col">Length, mm</th><th scope="col">Closed</th></tr></thead>
          <tbody></tbody>
        </table>
      </div>
    </div>
  </section>
  <section aria-labelledby="paths-export-heading">
    <h2 id="paths-export-heading">Export the program</h2>
    <div class="export-buttons">
      <button type="button" data-format="rapid" disabled title="ABB RAPID module(s), positions in mm; several files come in one ZIP">ABB RAPID</button>
      <button type="button" data-format="krl" disabled title="KUKA KRL .src file(s), positions in mm; several files come in one ZIP">KUKA KRL</button>
      <button type="button" data-format="csv" disabled title="One row per path point: position, tool axis, kind, pass">Path · CSV</button>
      <button type="button" data-format="json" disabled title="The path points and parameters">Path · JSON</button>
    </div>
    ${cellHtml('paths')}
  </section>`;

class PathsTool {
  id = 'paths';
  title = 'Paths';
  settings = {
    order: 4,
    defaults: DEFAULTS,
    allowed: Object.fromEntries(Object.entries(CHOICES).map(([k, v]) => [P + k, v])),
    hashKeys: () => Object.keys(DEFAULTS),
  };

  #shell;
  #form;
  #results;
  #overlay;
  #point = null; // clicked plane point, file units (null: the model's centre)
  #points = []; // clicked polyline points, file units
  #result = null; // { out, request, model, unit } on screen
  #runs = null; // { key, mesh?, voxel? } vertex distances per method for one source
  #listening = false;

  mount(shell, { panel, results, overlay }) {
    this.#shell = shell;
    panel.innerHTML = PANEL;
    panel.setAttribute('aria-labelledby', 'paths-heading');
    results.innerHTML = RESULTS;
    mountCell(results, () => shell.state.settings);
    this.#results = results;
    this.#overlay = overlay;
    this.#form = panel.querySelector('#paths-form');
    this.#wire();
    this.#renderForm();
    this.#renderPoints();
  }

  get #s() {
    return this.#shell.state.settings;
  }

  // ---------------------------------------------------------------- form

  #renderForm() {
    const s = this.#s;
    for (const f of FIELDS) $(`paths-${f.key}`).value = f.blank && !s[P + f.key] ? '' : fieldText(s[P + f.key], 8);
    for (const name of ['source', 'scope', 'spacingMode', 'method']) {
      for (const r of this.#form.elements[name]) r.checked = r.value === s[P + name];
    }
    $('paths-axis').value = s[`${P}axis`];
    $('paths-order').value = s[`${P}order`];
    $('paths-loop').value = s[`${P}loop`];
    $('paths-showMap').checked = s[`${P}showMap`];
    $('paths-showPaths').checked = s[`${P}showPaths`];
    $('paths-closedLoop').checked = s[`${P}closedLoop`];
    this.#validate();
  }

  /** Reads the form: { values } (mm), or { error } with the bad field marked. */
  #read() {
    const values = {};
    let error = null;
    for (const name of ['source', 'scope', 'spacingMode', 'method']) values[name] = this.#form.elements[name].value || CHOICES[name][0];
    values.axis = $('paths-axis').value;
    values.order = $('paths-order').value;
    values.loop = $('paths-loop').value;
    values.showMap = $('paths-showMap').checked;
    values.showPaths = $('paths-showPaths').checked;
    values.closedLoop = $('paths-closedLoop').checked;
    for (const f of FIELDS) {
      const el = $(`paths-${f.key}`);
      const text = el.value.trim();
      const v = text === '' ? (f.blank ? 0 : NaN) : Number(text);
      const used = (f.group !== 'spacing' || values.spacingMode === 'spacing') && (f.group !== 'bead' || values.spacingMode === 'bead') &&
        (f.group !== 'method' || values.method === 'voxel' || values.method === 'compare');
      let problem = null;
      if (!Number.isFinite(v)) problem = `Enter a number for the ${f.label.toLowerCase()}.`;
      else if (f.blank && v === 0) problem = null;
      else if (v <= f.min || (f.max !== undefined && v > f.max)) {
        problem = `The ${f.label.toLowerCase()} must be above ${f.min}${f.max !== undefined ? ` and at most ${f.max}` : ''}${f.unit ? ` ${f.unit}` : ''}.`;
      } else if (f.integer && !Number.isInteger(v)) problem = `The ${f.label.toLowerCase()} must be a whole number.`;
      el.setAttribute('aria-invalid', String(Boolean(problem && used)));
      if (problem && used) error ??= problem;
      if (!problem) values[f.key] = v;
    }
    values.spacingMm = values.spacingMode === 'bead' ? values.beadWidth * values.overlap : values.spacing;
    return error ? { error, values } : { values };
  }

  #validate() {
    const r = this.#read();
    const v = r.values;
    const noPatch = v.scope === 'patch' && this.#shell.state.selected === null;
    const noPoints = v.source === 'points' && this.#points.length === 0;
    $('paths-error').textContent = r.error ?? (noPatch ? 'Select a patch (click it in the view or the list), or use the whole mesh.'
      : noPoints ? 'Click at least one point on the surface.' : '');
    $('paths-run').disabled = Boolean(r.error) || noPatch || noPoints || !this.#shell.state.model;
    $('paths-spacing-hint').textContent = Number.isFinite(v.spacingMm) && v.spacingMode === 'bead'
      ? `Passes ${num(v.spacingMm, 4)} mm apart.` : '';
    const sel = this.#shell.state.selected;
    $('paths-patch-label').textContent = sel === null ? 'the selected patch (none)' : `patch ${sel}`;
    return r;
  }

  #save() {
    const { values } = this.#read();
    for (const [k, v] of Object.entries(values)) {
      if (`${P}${k}` in DEFAULTS && typeof v === typeof DEFAULTS[P + k]) this.#s[P + k] = v;
    }
    persistSettings(this.#s);
  }

  #renderPoint() {
    const el = $('paths-point');
    if (!el) return;
    const u = this.#shell.unitOf.length();
    el.textContent = this.#point
      ? `Point: ${pointText(this.#point)} ${u}. Click the surface to move it. The piece of the section nearest the point is the source.`
      : 'Point: the model\'s centre. Click the surface to choose one. The piece of the section nearest the point is the source.';
  }

  #renderPoints() {
    const el = $('paths-points');
    if (!el) return;
    const n = this.#points.length;
    el.textContent = n ? `${n} point${n === 1 ? '' : 's'} clicked. Click the surface to add more.` : 'No points yet: click the surface.';
    $('paths-undo-point').disabled = n === 0;
    $('paths-clear-points').disabled = n === 0;
    this.#drawMarks();
  }

  /** Small crosses at the plane point and the clicked points, the points joined by straight lines. */
  #drawMarks() {
    const viewer = this.#shell.viewer;
    if (!viewer) return;
    const v = this.#read().values;
    const size = Math.max((v.spacingMm || 10) / this.#shell.mmPerUnit / 3, 1e-9);
    const pos = [];
    const cross = (p) => pointMark(pos, p, size);
    if (v.source === 'plane' && this.#point) cross(this.#point);
    if (v.source === 'points') {
      this.#points.forEach(cross);
      for (let i = 1; i < this.#points.length; i++) pos.push(...this.#points[i - 1], ...this.#points[i]);
    }
    if (pos.length === 0) viewer.removeLayer('paths.marks');
    else viewer.setLayer('paths.marks', { kind: 'lines', positions: Float32Array.from(pos), color: SOURCE_COLOR });
    viewer.setLayerVisible('paths.marks', this.#shell.activeTool === this);
  }

  // ---------------------------------------------------------------- shell hooks

  onModelLoaded() {
    this.#point = null;
    this.#points = [];
    this.#runs = null;
    this.#clear();
    this.#renderPoint();
    this.#renderPoints();
    this.#validate();
  }

  onSegmentation() {
    this.#validate();
  }

  onSelectionChanged() {
    this.#validate();
  }

  onUnitsChanged({ unitChanged }) {
    if (unitChanged && this.#result) this.#clear('The file unit changed: compute again.');
    this.#renderPoint();
  }

  onSettingsChanged() {
    renderCell(this.#s);
    this.#renderForm();
  }

  onActivate() {
    const viewer = this.#shell.viewer;
    if (viewer && !this.#listening) {
      this.#listening = true;
      viewer.addEventListener('pick', (event) => {
        if (this.#shell.activeTool !== this || !event.detail.point) return;
        if (this.#read().values.source === 'points') {
          this.#points.push(event.detail.point);
          this.#renderPoints();
          this.#validate();
        } else {
          this.#point = event.detail.point;
          this.#renderPoint();
          this.#drawMarks();
        }
      });
    }
    this.#showLayers(true);
    this.#drawMarks();
    this.#validate();
    // The engine takes the memory of the first distance while the source is set up (nothing
    // is lost when it cannot: the distance takes it then); the model's figures show it.
    const shell = this.#shell;
    if (shell.engine?.hasMesh) {
      shell.engine.request('paths.prepare').then(({ memoryBytes }) => {
        shell.state.memoryBytes = memoryBytes;
        shell.refreshUnits();
      }, () => {});
    }
  }

  onDeactivate() {
    this.#showLayers(false);
    this.#shell.viewer?.setLayerVisible('paths.marks', false);
  }

  // ---------------------------------------------------------------- computing

  #request() {
    const r = this.#validate();
    if (r.error || $('paths-run').disabled) return null;
    const v = r.values;
    const shell = this.#shell;
    const mm = shell.mmPerUnit;
    const patchId = v.scope === 'patch' ? shell.state.selected : null;
    let source;
    if (v.source === 'plane') {
      const normal = v.axis === 'view' ? shell.viewer.viewDirectionInModel() : { x: [1, 0, 0], y: [0, 1, 0], z: [0, 0, 1] }[v.axis];
      source = { kind: 'plane', point: this.#point, normal };
    } else if (v.source === 'points') {
      source = { kind: 'points', points: this.#points.flat(), closed: v.closedLoop && this.#points.length > 2 };
    } else {
      source = { kind: 'boundary', ...(v.loop !== 'all' ? { loop: Number(v.loop) } : {}) };
    }
    const methods = v.method === 'compare' ? ['exact', 'accurate', 'fast', 'voxel'] : [v.method];
    return {
      values: v,
      patchId,
      source,
      methods,
      voxelSize: v.voxelSize ? v.voxelSize / mm : undefined,
      spacing: v.spacingMm / mm,
      pathOptions: { maxLevel: v.maxLevel, order: v.order },
    };
  }

  compute() {
    const shell = this.#shell;
    const request = this.#request();
    if (!request) return;
    this.#save();
    const { values, ...message } = request;
    shell.enqueue('Computing the geodesic paths', async (progress, checkpoint) => {
      shell.hideAlert();
      let out;
      try {
        await shell.restoreEngine(progress, checkpoint);
        out = await shell.engine.request('paths.compute', message, { onProgress: progress });
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        throw new Error(`The paths could not be computed: ${error.message.replace(/\.?$/, '.')}${this.#result ? ' The result on screen is unchanged.' : ''}`);
      }
      progress('Drawing', null);
      if (out.memoryBytes) shell.showMemory(out.memoryBytes);
      // The source as the engine saw it (the plane's point filled in), for the comparison.
      const key = JSON.stringify([shell.state.model.name, { ...message.source, point: out.point }, message.patchId]);
      if (this.#runs?.key !== key) this.#runs = { key };
      for (const run of out.runs) this.#runs[run.method] = run.vertexDistance;
      this.#result = { out, request, model: shell.state.model.name };
      this.#draw();
      this.#renderResults();
      document.body.dataset.pathsRuns = String(Number(document.body.dataset.pathsRuns ?? 0) + 1);
      const first = out.runs[0];
      shell.setStatus(`${integer.format(first.table.length)} passes ${num(values.spacingMm, 4)} mm apart, ` +
        `computed in ${num(out.runs.reduce((a, r) => a + r.ms, 0) / 1000, 2)} s.`);
    });
  }

  /**
   * Why the first passes are missing, when they are: the distance is known at the vertices
   * and varies linearly in each face between them, so no pass lies nearer the source than
   * its nearest vertices (a plane between two rings of a coarse model's vertices, a spacing
   * finer than the mesh).
   */
  #missingLevels(run, request) {
    const first = run.table.length ? run.table[0].level : null;
    if (first === 1 || (first === null && !(run.maxDistance >= request.spacing))) return '';
    const mm = this.#shell.mmPerUnit;
    let nearest = Infinity;
    for (const d of run.vertexDistance) if (d < nearest) nearest = d;
    const reach = (first === null ? request.pathOptions.maxLevel : first - 1) * request.spacing;
    const why = 'the distance is known at the vertices of the mesh and varies linearly between them' +
      (reach < nearest ? `, and the nearest vertices are ${num(nearest * mm, 4)} mm from the source` : '');
    return first === null
      ? ` No pass: the ${integer.format(request.pathOptions.maxLevel)} levels asked for (Most passes) end ${num(reach * mm, 4)} mm ` +
        `from the source, nearer than the mesh resolves: ${why}. Widen the spacing, raise Most passes, or use a finer mesh.`
      : ` Levels 1 to ${first - 1} (up to ${num(reach * mm, 4)} mm) are not cut, nearer the source than the mesh resolves: ${why}.`;
  }

  #clear(message) {
    this.#result = null;
    for (const layer of ['map', 'closed', 'open', 'source', 'diffmark']) this.#shell.viewer?.removeLayer(`paths.${layer}`);
    if (!this.#results) return;
    $('paths-figures').hidden = true;
    $('paths-summary').textContent = message ?? 'No paths yet: choose a source and press Compute paths.';
    for (const b of this.#results.querySelectorAll('[data-format]')) b.disabled = true;
    this.#overlay.replaceChildren();
    this.#overlay.hidden = true;
  }

  // ---------------------------------------------------------------- drawing

  #draw() {
    const viewer = this.#shell.viewer;
    const { out, request } = this.#result;
    const run = out.runs[0];
    // Colour map: viridis over 0 … max distance; unreached vertices grey; faces with an
    // unreached corner left out (outside the patch).
    const d = run.vertexDistance;
    const max = run.maxDistance > 0 ? run.maxDistance : 1;
    const colors = new Uint8Array(d.length * 3);
    for (let i = 0; i < d.length; i++) {
      if (Number.isFinite(d[i])) viridisInto(d[i] / max, colors, 3 * i);
      else colors.set(UNREACHED, 3 * i);
    }
    const I = out.indices;
    // Typed, not a growing array of numbers: at millions of triangles the latter costs
    // seconds and gigabytes.
    const kept = new Uint32Array(I.length);
    let k = 0;
    for (let t = 0; t < I.length; t += 3) {
      if (Number.isFinite(d[I[t]]) && Number.isFinite(d[I[t + 1]]) && Number.isFinite(d[I[t + 2]])) {
        kept[k++] = I[t];
        kept[k++] = I[t + 1];
        kept[k++] = I[t + 2];
      }
    }
    viewer.setLayer('paths.map', { kind: 'surface', positions: out.positions, indices: kept.subarray(0, k), colors });
    const lines = (closed) => {
      const pos = [];
      const col = [];
      for (const p of run.table) {
        if (p.closed !== closed) continue;
        const c = hexRgb(LEVEL_COLORS[(p.level - 1) % LEVEL_COLORS.length]);
        const n = p.count;
        const segs = closed ? n : n - 1;
        for (let i = 0; i < segs; i++) {
          const a = p.start + i;
          const b = p.start + ((i + 1) % n);
          for (const k of [a, b]) {
            pos.push(run.points[3 * k], run.points[3 * k + 1], run.points[3 * k + 2]);
            col.push(...c);
          }
        }
      }
      return { positions: Float32Array.from(pos), colors: Uint8Array.from(col) };
    };
    viewer.setLayer('paths.closed', { kind: 'lines', ...lines(true) });
    viewer.setLayer('paths.open', { kind: 'lines', ...lines(false), dashed: true, dashSize: request.spacing / 4 });
    const src = [];
    for (const p of run.sourceTable) {
      const n = p.count;
      for (let i = 0; i < (p.closed ? n : n - 1); i++) {
        for (const k of [p.start + i, p.start + ((i + 1) % n)]) src.push(run.source[3 * k], run.source[3 * k + 1], run.source[3 * k + 2]);
      }
    }
    viewer.setLayer('paths.source', { kind: 'lines', positions: Float32Array.from(src), color: SOURCE_COLOR });
    this.#showLayers(this.#shell.activeTool === this);
  }

  #showLayers(visible) {
    const viewer = this.#shell.viewer;
    if (!viewer) return;
    const v = this.#read().values;
    viewer.setLayerVisible('paths.map', visible && v.showMap);
    for (const id of ['closed', 'open', 'source']) viewer.setLayerVisible(`paths.${id}`, visible && v.showPaths);
    viewer.setLayerVisible('paths.diffmark', visible);
  }

  // ---------------------------------------------------------------- figures

  #renderResults() {
    const shell = this.#shell;
    const mm = shell.mmPerUnit;
    const { out, request } = this.#result;
    const run = out.runs[0];
    const closed = run.table.filter((p) => p.closed).length;
    const total = run.table.reduce((a, p) => a + p.length, 0);
    const what = request.source.kind === 'plane'
      ? `Section plane (normal ${request.values.axis === 'view' ? 'along the view' : request.values.axis.toUpperCase()})`
      : request.source.kind === 'points' ? `${request.source.points.length / 3} clicked points`
        : request.source.loop === undefined ? 'Boundary loops' : `Boundary loop ${request.source.loop + 1} (by length)`;
    $('paths-summary').textContent = `${what} on ${request.patchId === null ? 'the whole mesh' : `patch ${request.patchId}`}, ` +
      `${methodLabel(run)}: ${integer.format(run.table.length)} passes (${closed} closed, ${run.table.length - closed} open) ` +
      `${num(request.spacing * mm, 4)} mm apart, ${num(total * mm / 1000, 4)} m of path; farthest point ${num(run.maxDistance * mm, 4)} mm.` +
      (run.table.length && run.table[run.table.length - 1].level >= request.pathOptions.maxLevel ? ` Stopped at level ${request.pathOptions.maxLevel} (Most passes).` : '') +
      this.#missingLevels(run, request);
    const rows = run.table.slice(0, MAX_ROWS).map((p) => {
      const tr = document.createElement('tr');
      tr.dataset.level = String(p.level);
      tr.dataset.closed = String(p.closed);
      for (const text of [String(p.level), num(p.distance * mm, 4), num(p.length * mm, 4), p.closed ? 'closed' : 'open']) {
        tr.append(Object.assign(document.createElement('td'), { textContent: text }));
      }
      return tr;
    });
    $('paths-table').tBodies[0].replaceChildren(...rows);
    this.#renderDiff();
    $('paths-figures').hidden = false;
    for (const b of this.#results.querySelectorAll('[data-format]')) b.disabled = run.table.length === 0;
    this.#renderLegend();
  }

  /** Max and mean difference of each method from the reference (exact, else accurate) over the
   * vertices both reached, and a cross where the largest difference is. */
  #renderDiff() {
    const el = $('paths-diff');
    const runs = this.#runs;
    this.#shell.viewer?.removeLayer('paths.diffmark');
    const reference = runs?.exact ? 'exact' : 'accurate';
    const others = ['accurate', 'fast', 'voxel'].filter((m) => m !== reference && runs?.[m] && runs[m].length === runs[reference]?.length);
    if (!others.length) {
      el.hidden = true;
      return;
    }
    const mm = this.#shell.mmPerUnit;
    const P = this.#result.out.positions;
    const unit = this.#shell.unitOf.length();
    const NAMES = { exact: 'exact', accurate: 'accurate', fast: 'fast', voxel: 'voxel' };
    let worst = { max: 0, at: -1 };
    const lines = others.map((method) => {
      const a = runs[method];
      const b = runs[reference];
      let max = 0;
      let at = -1;
      let sum = 0;
      let n = 0;
      for (let i = 0; i < a.length; i++) {
        if (!Number.isFinite(a[i]) || !Number.isFinite(b[i])) continue;
        const e = Math.abs(a[i] - b[i]);
        sum += e;
        n++;
        if (e > max) {
          max = e;
          at = i;
        }
      }
      if (max > worst.max) worst = { max, at };
      el.dataset[`${method}Max`] = String(max * mm);
      const where = at >= 0 ? ` at (${[0, 1, 2].map((k) => num(P[3 * at + k], 4)).join(', ')}) ${unit}` : '';
      return `${NAMES[method]} method vs ${NAMES[reference]}: largest difference ${num(max * mm, 4)} mm${where}, ` +
        `mean ${num(n ? (sum / n) * mm : 0, 4)} mm over ${integer.format(n)} vertices` +
        (method === 'voxel' ? ' (the voxel distance read at the nearest voxel)' : '') + '.';
    });
    el.hidden = false;
    el.dataset.max = String(worst.max * mm);
    if (worst.at >= 0) {
      // A ring of three crosses where a method differs most, sized by the difference.
      const r = Math.max(worst.max, this.#result.request.spacing / 2);
      const c = [P[3 * worst.at], P[3 * worst.at + 1], P[3 * worst.at + 2]];
      const pos = [];
      pointMark(pos, c, r);
      this.#shell.viewer.setLayer('paths.diffmark', { kind: 'lines', positions: Float32Array.from(pos), color: DIFF_COLOR });
      this.#shell.viewer.setLayerVisible('paths.diffmark', this.#shell.activeTool === this);
    }
    el.textContent = `On this source: ${lines.join(' ')} White cross in the view: the largest difference.`;
  }

  #renderLegend() {
    const overlay = this.#overlay;
    const v = this.#read().values;
    const el = (tag, className, text) => Object.assign(document.createElement(tag), { className: className ?? '', textContent: text ?? '' });
    const nodes = [];
    if (this.#result && v.showMap) {
      const max = this.#result.out.runs[0].maxDistance * this.#shell.mmPerUnit;
      nodes.push(el('p', 'legend-title', `Geodesic distance from the source, mm (${methodLabel(this.#result.out.runs[0])})`));
      const bar = el('div', 'legend-bar');
      const stops = [0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1];
      bar.style.backgroundImage = `linear-gradient(to right, ${stops.map((t) => `rgb(${viridis(t).join(' ')}) ${100 * t}%`).join(', ')})`;
      const ticks = el('div', 'legend-ticks');
      ticks.append(el('span', '', '0'), el('span', '', num(max / 2, 3)), el('span', '', num(max, 3)));
      nodes.push(bar, ticks);
    }
    if (this.#result && v.showPaths) {
      const list = el('ul', 'legend-list kinds');
      const item = (color, dashed, text) => {
        const li = el('li');
        const s = el('span', `legend-line${dashed ? ' dashed' : ''}`);
        s.style.borderColor = color;
        li.append(s, text);
        list.append(li);
      };
      item(SOURCE_COLOR, false, 'Source');
      item(LEVEL_COLORS[0], false, 'Closed pass (colour cycles with the level)');
      item(LEVEL_COLORS[1], true, 'Open pass');
      nodes.push(list);
    }
    overlay.replaceChildren(...nodes);
    overlay.hidden = nodes.length === 0;
  }

  // ---------------------------------------------------------------- exports

  #export(format) {
    const shell = this.#shell;
    const result = this.#result;
    if (!result) return;
    const stem = fileStem(result.model);
    // KRL allows 24 characters and the exporters append a part number: keep 16.
    const name = `gp_${stem.replace(/[^A-Za-z0-9_]/g, '_')}`.slice(0, 16).replace(/_+$/, '');
    const options = { mmPerUnit: shell.mmPerUnit, name, ...cellOptions(this.#s) };
    const { values, ...message } = result.request;
    const recompute = (progress) => shell.engine.request('paths.compute', message, { onProgress: progress });
    shell.enqueue(`Writing the ${format.toUpperCase()} program`, async (progress, checkpoint) => {
      if (!shell.engine.hasMesh) {
        await shell.restoreEngine(progress, checkpoint);
        await recompute(progress);
      }
      let out;
      try {
        out = await shell.engine.request('paths.exportPaths', { format, options, stem }, { onProgress: progress });
      } catch (error) {
        if (error.message !== 'NO_PATHS') throw new Error(`The ${format.toUpperCase()} export failed: ${error.message}`);
        await recompute(progress);
        out = await shell.engine.request('paths.exportPaths', { format, options, stem }, { onProgress: progress });
      }
      const type = out.fileName.endsWith('.zip') ? 'application/zip' : out.fileName.endsWith('.json') ? 'application/json' : 'text/plain';
      download(out.bytes, out.fileName, type);
      shell.setStatus(`Saved ${out.fileName}${out.fileCount > 1 ? ` with ${out.fileCount} files` : ''}.`);
    });
  }

  #wire() {
    this.#form.addEventListener('submit', (event) => {
      event.preventDefault();
      this.compute();
    });
    this.#form.addEventListener('input', () => {
      const r = this.#validate();
      if (!r.error) this.#save();
    });
    this.#form.addEventListener('change', () => {
      this.#validate();
      this.#drawMarks();
    });
    $('paths-undo-point').addEventListener('click', () => {
      this.#points.pop();
      this.#renderPoints();
      this.#validate();
    });
    $('paths-clear-points').addEventListener('click', () => {
      this.#points = [];
      this.#renderPoints();
      this.#validate();
    });
    this.#results.addEventListener('change', () => {
      this.#save();
      if (!this.#result) return;
      this.#showLayers(true);
      this.#renderLegend();
    });
    for (const b of this.#results.querySelectorAll('[data-format]')) b.addEventListener('click', () => this.#export(b.dataset.format));
  }
}

export const pathsTool = new PathsTool();
