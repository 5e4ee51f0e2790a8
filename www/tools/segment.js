// Segmentation tool (seed 000): the growing criterion and its parameters, the live
// threshold, Segment, and the patch exports (STL per patch, ZIP, table as CSV/JSON).
// Worker side: worker/segment.js. The patches it makes are the shell's shared patch list.
import { CancelledError } from '../app/engine.js';
import { download, fileStem } from '../app/download.js';
import { fieldText, num } from '../app/format.js';
import { MM_PER_UNIT, persistSettings } from '../app/settings.js';

// The paper's defaults (α 0.35 rad, θmax 1 rad, ε 10 %); spray (µm) and grind (mm) values are examples.
const DEFAULTS = Object.freeze({
  criterion: 'angle',
  angleThreshold: 0.35,
  curvatureThreshold: 0.05,
  meanThickness: 100,
  allowedDeviation: 10,
  minThickness: 96,
  indentationDepth: 0.5,
  minPressureRatio: 0.8,
  contactWidth: 20,
  thetaMax: 1,
  minAreaRatio: 0.1,
  seedRule: 'flattest',
});
const CRITERION_FIELDS = {
  spray: ['meanThickness', 'allowedDeviation', 'minThickness'],
  grind: ['indentationDepth', 'minPressureRatio', 'contactWidth'],
  angle: ['angleThreshold'],
  curvature: ['curvatureThreshold'],
};
const COMMON_FIELDS = ['thetaMax', 'minAreaRatio'];
const SEED_RULES = ['flattest', 'largestArea', 'lowestIndex'];
const ANGLE_FIELDS = new Set(['angleThreshold', 'thetaMax']);
const FIELD_LABELS = {
  meanThickness: 'mean thickness', allowedDeviation: 'allowed deviation', minThickness: 'minimum thickness',
  indentationDepth: 'indentation depth', minPressureRatio: 'minimum pressure ratio', contactWidth: 'contact width',
  angleThreshold: 'angle threshold', curvatureThreshold: 'curvature threshold',
  thetaMax: 'maximum angle to the patch normal θmax', minAreaRatio: 'minimum patch area',
};

/**
 * The object the core takes: exactly one criterion, plus thetaMax and minAreaRatio. The
 * grinding lengths go from mm into the file's unit, so κ comes back in 1 / file unit.
 */
export function coreParams(s) {
  const params = {};
  if (s.criterion === 'angle') params.angleThreshold = s.angleThreshold;
  else if (s.criterion === 'curvature') params.curvatureThreshold = s.curvatureThreshold;
  else if (s.criterion === 'spray') {
    params.spray = { meanThickness: s.meanThickness, allowedDeviation: s.allowedDeviation, minThickness: s.minThickness };
  } else {
    const mm = MM_PER_UNIT[s.unit] ?? 1;
    params.grind = {
      indentationDepth: s.indentationDepth / mm, minPressureRatio: s.minPressureRatio, contactWidth: s.contactWidth / mm,
    };
  }
  params.thetaMax = s.thetaMax;
  params.minAreaRatio = s.minAreaRatio;
  params.seedRule = s.seedRule;
  return params;
}

/** The core names parameters as in its API (minPressureRatio); the page says them in words. */
function inWords(message) {
  const text = message.replace(/\b(\w+)\b/g, (word) => FIELD_LABELS[word] ?? word);
  return text.charAt(0).toUpperCase() + text.slice(1);
}

const PANEL = `
  <h2 id="seg-heading">Segmentation</h2>
  <form id="seg-form" novalidate>
    <fieldset class="criterion">
      <legend>Growing criterion</legend>
      <label><input type="radio" name="criterion" value="spray"> Spraying</label>
      <label><input type="radio" name="criterion" value="grind"> Grinding</label>
      <label><input type="radio" name="criterion" value="angle"> Angle</label>
      <label><input type="radio" name="criterion" value="curvature"> Curvature</label>
    </fieldset>

    <div class="criterion-fields" data-criterion="spray">
      <p class="hint">Coating thickness falls with the cosine of the tilt, so the thicknesses bound the angle between neighbouring triangles: α = arccos((Q<sub>d</sub> − ΔQ<sub>d</sub>) / Q<sub>min</sub>). Any one thickness unit; only ratios count.</p>
      <label class="field"><span>Mean thickness Q<sub>d</sub></span>
        <input type="number" name="meanThickness" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit">µm</span></label>
      <label class="field"><span>Allowed deviation ΔQ<sub>d</sub></span>
        <input type="number" name="allowedDeviation" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit">µm</span></label>
      <label class="field"><span>Minimum thickness Q<sub>min</sub></span>
        <input type="number" name="minThickness" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit">µm</span></label>
    </div>

    <div class="criterion-fields" data-criterion="grind">
      <p class="hint">Hertz contact: keeping the edge pressure at least δ·P<sub>0</sub> bounds the curvature: κ = 2 d (1 − δ²) / L<sub>c</sub>². Tool lengths in mm, converted to the file's unit.</p>
      <label class="field"><span>Indentation depth d</span>
        <input type="number" name="indentationDepth" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit">mm</span></label>
      <label class="field"><span>Minimum pressure ratio δ (0–1)</span>
        <input type="number" name="minPressureRatio" step="any" min="0" max="1" required inputmode="decimal" aria-describedby="params-error"><span class="unit"></span></label>
      <label class="field"><span>Contact width L<sub>c</sub></span>
        <input type="number" name="contactWidth" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit">mm</span></label>
    </div>

    <div class="criterion-fields" data-criterion="angle">
      <p class="hint">A neighbour joins a region when the angle between the two triangles' normals is below α.</p>
      <label class="field"><span>Angle threshold α</span>
        <input type="number" name="angleThreshold" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit" data-unit="angle">rad</span></label>
    </div>

    <div class="criterion-fields" data-criterion="curvature">
      <p class="hint">A neighbour joins a region when the angle between normals divided by the distance between centroids is below κ.</p>
      <label class="field"><span>Curvature threshold κ</span>
        <input type="number" name="curvatureThreshold" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit" data-unit="curvature">1/mm</span></label>
    </div>

    <p class="derived">Growing threshold: <output id="threshold-value" for="seg-form" aria-live="polite">–</output></p>

    <label class="field"><span title="Largest angle allowed between a triangle's normal and its patch's mean normal">Max. angle to patch normal θ<sub>max</sub></span>
      <input type="number" name="thetaMax" step="any" min="0" required inputmode="decimal" aria-describedby="params-error"><span class="unit" data-unit="angle">rad</span></label>
    <label class="field"><span>Minimum patch area ε (share of the total)</span>
      <input type="number" name="minAreaPercent" step="any" min="0" max="99.99" required inputmode="decimal" aria-describedby="params-error"><span class="unit">%</span></label>

    <label class="field choice"><span>Patch seeds</span>
      <select name="seedRule" title="Where each near-planar patch starts growing inside a region">
        <option value="flattest">flattest first</option>
        <option value="largestArea">largest first</option>
        <option value="lowestIndex">file order (paper)</option>
      </select></label>

    <p id="params-error" class="field-error" aria-live="polite"></p>
    <div class="form-actions">
      <button type="submit" id="segment-button" class="primary">Segment</button>
      <button type="button" id="defaults-button">Paper defaults</button>
    </div>
  </form>`;

const RESULTS = `
  <section aria-labelledby="export-heading">
    <h2 id="export-heading">Export patches</h2>
    <div class="export-buttons">
      <button type="button" id="export-selected" disabled title="Binary STL of the selected patch">Selected patch · STL</button>
      <button type="button" id="export-zip" disabled title="One binary STL per patch, in one ZIP archive">All patches · ZIP</button>
      <button type="button" id="export-files" disabled title="One binary STL download per patch">All patches · STL files</button>
      <button type="button" id="export-csv" disabled title="Ids, areas, normals, deviations and the parameters used">Patch table · CSV</button>
      <button type="button" id="export-json" disabled title="Ids, areas, normals, deviations and the parameters used">Patch table · JSON</button>
    </div>
  </section>`;

class SegmentTool {
  id = 'segment';
  title = 'Segment';
  settings = {
    order: 0,
    defaults: DEFAULTS,
    allowed: { criterion: Object.keys(CRITERION_FIELDS), seedRule: SEED_RULES },
    hashKeys: (s) => ['criterion', ...CRITERION_FIELDS[s.criterion], ...COMMON_FIELDS, 'seedRule'],
  };

  #shell;
  #form;
  #segmentedParams = null; // core params of the segmentation on screen
  #segmentationQueued = false;
  #autoTimer = 0;

  mount(shell, { panel, results }) {
    this.#shell = shell;
    panel.innerHTML = PANEL;
    panel.setAttribute('aria-labelledby', 'seg-heading');
    results.innerHTML = RESULTS;
    this.#form = panel.querySelector('#seg-form');
    this.#wire();
    this.#renderForm();
  }

  get #s() {
    return this.#shell.state.settings;
  }

  #input(name) {
    return name === 'minAreaRatio' ? this.#form.elements.minAreaPercent : this.#form.elements[name];
  }

  // ---------------------------------------------------------------- the form

  #renderForm() {
    const s = this.#s;
    const form = this.#form;
    for (const radio of form.elements.criterion) radio.checked = radio.value === s.criterion;
    for (const block of form.querySelectorAll('.criterion-fields')) block.hidden = block.dataset.criterion !== s.criterion;
    for (const name of [...Object.values(CRITERION_FIELDS).flat(), ...COMMON_FIELDS]) {
      let value = s[name];
      let digits = 10;
      if (ANGLE_FIELDS.has(name) && s.angleUnit === 'deg') {
        value = (value * 180) / Math.PI;
        digits = 6;
      }
      if (name === 'minAreaRatio') value *= 100;
      const el = this.#input(name);
      el.value = fieldText(value, digits);
      // Unedited fields keep the exact stored value (degrees shown rounded are not re-read).
      el.dataset.shown = el.value;
      el.dataset.exact = String(s[name]);
    }
    form.elements.seedRule.value = s.seedRule;
    this.#input('thetaMax').max = s.angleUnit === 'deg' ? '180' : String(Math.PI);
    this.#validate();
  }

  /**
   * Reads the form into candidate settings and checks them: per field (a number, in range),
   * then the core's own check through deriveThreshold. Marks bad fields inline.
   * Returns { settings, params, threshold } or { error }.
   */
  #read() {
    const form = this.#form;
    const s = {
      ...this.#s,
      criterion: form.elements.criterion.value || this.#s.criterion,
      seedRule: form.elements.seedRule.value || this.#s.seedRule,
    };
    const names = [...CRITERION_FIELDS[s.criterion], ...COMMON_FIELDS];
    const problems = new Map();
    for (const name of names) {
      const el = this.#input(name);
      if (el.value === el.dataset.shown && el.dataset.exact !== undefined) {
        s[name] = Number(el.dataset.exact);
        continue;
      }
      let value = el.value.trim() === '' ? NaN : Number(el.value);
      if (!Number.isFinite(value)) {
        problems.set(name, `Enter a number for the ${FIELD_LABELS[name]}.`);
        continue;
      }
      if (ANGLE_FIELDS.has(name) && s.angleUnit === 'deg') value = (value * Math.PI) / 180;
      if (name === 'minAreaRatio') value /= 100;
      s[name] = value;
    }
    // Ranges the API documents for the common parameters (the core checks them again).
    if (!problems.has('thetaMax') && !(s.thetaMax > 0 && s.thetaMax <= Math.PI)) {
      problems.set('thetaMax', `The ${FIELD_LABELS.thetaMax} must be above 0 and at most ${s.angleUnit === 'deg' ? '180°' : 'π rad'}.`);
    }
    if (!problems.has('minAreaRatio') && !(s.minAreaRatio >= 0 && s.minAreaRatio < 1)) {
      problems.set('minAreaRatio', 'The minimum patch area must be at least 0 % and below 100 %.');
    }
    let threshold = null;
    const params = coreParams(s);
    if (problems.size === 0 && this.#shell.engine?.started) {
      try {
        threshold = this.#shell.engine.deriveThreshold(params);
      } catch (error) {
        // The core names the problem; flag the criterion's fields (or the one it names).
        const named = names.filter((n) => error.message.includes(n) || error.message.toLowerCase().includes(FIELD_LABELS[n]));
        for (const n of named.length ? named : CRITERION_FIELDS[s.criterion]) problems.set(n, null);
        problems.set('_core', error.message);
      }
    }
    for (const name of [...Object.values(CRITERION_FIELDS).flat(), ...COMMON_FIELDS]) {
      this.#input(name).setAttribute('aria-invalid', String(problems.has(name)));
    }
    if (problems.size) {
      const message = problems.get('_core') ?? [...problems.values()].find(Boolean);
      return { error: inWords(message) };
    }
    return { settings: s, params, threshold };
  }

  #thresholdText({ kind, value }) {
    if (kind === 'angle') return `α = ${num(value)} rad (${num((value * 180) / Math.PI)}°)`;
    return `κ = ${num(value)} ${this.#shell.unitOf.curvature()}`;
  }

  #validate() {
    const result = this.#read();
    const panel = this.#form;
    panel.querySelector('#threshold-value').textContent = result.error || !result.threshold ? '–' : this.#thresholdText(result.threshold);
    panel.querySelector('#params-error').textContent = result.error ?? '';
    panel.querySelector('#segment-button').disabled = Boolean(result.error);
    return result;
  }

  #onInput() {
    const result = this.#validate();
    for (const block of this.#form.querySelectorAll('.criterion-fields')) {
      block.hidden = block.dataset.criterion !== this.#form.elements.criterion.value;
    }
    if (result.error) return;
    Object.assign(this.#s, result.settings);
    persistSettings(this.#s);
  }

  /** Committed edits (Enter, leaving a field, a new criterion) re-segment by themselves. */
  #onChange() {
    const result = this.#validate();
    if (result.error || !this.#shell.state.model) return;
    if (JSON.stringify(result.params) === JSON.stringify(this.#segmentedParams)) return;
    clearTimeout(this.#autoTimer);
    this.#autoTimer = setTimeout(() => this.requestSegmentation(), 150);
  }

  // ---------------------------------------------------------------- shell hooks

  /** The worker segments right after parsing, with the form's params (none if invalid). */
  openParams() {
    const validated = this.#validate();
    this.#pendingOpenParams = validated.error ? null : validated.params;
    return this.#pendingOpenParams;
  }

  #pendingOpenParams = null;

  onModelLoaded(model, result) {
    const seg = result.tools.segment;
    this.#segmentedParams = seg?.segmentation ? this.#pendingOpenParams : null;
    if (seg?.segmentError) this.#form.querySelector('#params-error').textContent = inWords(seg.segmentError);
  }

  onSegmentation() {
    this.#updateExportButtons();
  }

  onSelectionChanged() {
    this.#updateExportButtons();
  }

  onBeforeUnitsChange() {
    // Keep what is typed valid: the angle fields are converted in place on re-render.
    const current = this.#read();
    if (!current.error) Object.assign(this.#s, current.settings);
  }

  onUnitsChanged({ unitChanged }) {
    this.#renderForm();
    // Grinding tool lengths are in mm: in another file unit they give another κ.
    if (unitChanged && this.#s.criterion === 'grind') this.requestSegmentation();
  }

  onSettingsChanged() {
    this.#renderForm();
    this.requestSegmentation();
  }

  onEngineReady() {
    this.#validate();
  }

  onEngineLost() {
    this.#segmentationQueued = false;
  }

  // ---------------------------------------------------------------- segmenting

  /**
   * Queues one re-segmentation with the settings current when it starts; without `force` it
   * is skipped when they are those of the segmentation on screen.
   */
  requestSegmentation({ force = false } = {}) {
    const shell = this.#shell;
    if (!shell.state.model || this.#segmentationQueued) return;
    this.#segmentationQueued = true;
    shell.enqueue('Segmenting', async (progress, checkpoint) => {
      this.#segmentationQueued = false;
      const validated = this.#validate();
      if (validated.error || !shell.state.model) return;
      const same = JSON.stringify(validated.params) === JSON.stringify(this.#segmentedParams);
      if (same && !force && shell.engine.hasMesh) return;
      shell.hideAlert();
      let result;
      try {
        await shell.restoreEngine(progress, checkpoint); // after Cancel the worker is new and empty
        result = await shell.engine.request('segment.run', { params: validated.params }, { onProgress: progress });
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        throw new Error(`The segmentation failed: ${inWords(error.message).replace(/\.?$/, '.')} The patches on screen are unchanged.`);
      }
      progress('Drawing', null);
      this.#segmentedParams = validated.params;
      shell.setSegmentation(result.segmentation, { display: result.display, keepView: true, memoryBytes: result.memoryBytes });
      shell.setStatus(`${result.segmentation.patchCount} patches in ${num(result.timings.segmentMs / 1000, 2)} s ` +
        `(${this.#thresholdText({ kind: result.segmentation.thresholdKind, value: result.segmentation.threshold })}).`);
    });
  }

  // ---------------------------------------------------------------- exports

  #updateExportButtons() {
    const { segmentation, selected } = this.#shell.state;
    const hasPatches = Boolean(segmentation?.patchCount);
    const $ = (id) => document.getElementById(id);
    $('export-selected').disabled = !hasPatches || selected === null;
    $('export-zip').disabled = !hasPatches;
    $('export-files').disabled = !hasPatches;
    $('export-csv').disabled = !segmentation;
    $('export-json').disabled = !segmentation;
  }

  #table() {
    const { model, segmentation, settings } = this.#shell.state;
    return patchTable({ model, segmentation, params: this.#segmentedParams, units: { length: settings.unit } });
  }

  #exportSelected() {
    const shell = this.#shell;
    const id = shell.state.selected;
    const stem = fileStem(shell.state.model.name);
    shell.enqueue(`Writing patch ${id}`, async (progress, checkpoint) => {
      await shell.restoreEngine(progress, checkpoint);
      const bytes = await shell.engine.request('segment.patchStl', { patchId: id });
      download(bytes, `${stem}_patch${id}.stl`, 'model/stl');
      shell.setStatus(`Saved ${stem}_patch${id}.stl.`);
    });
  }

  #exportZip() {
    const shell = this.#shell;
    const stem = fileStem(shell.state.model.name);
    const names = shell.state.segmentation.patches.map((p) => ({ patchId: p.id, fileName: `${stem}_patch${p.id}.stl` }));
    shell.enqueue('Writing the archive', async (progress, checkpoint) => {
      await shell.restoreEngine(progress, checkpoint);
      const bytes = await shell.engine.request('segment.zip', { names }, { onProgress: progress });
      download(bytes, `${stem}_patches.zip`, 'application/zip');
      shell.setStatus(`Saved ${stem}_patches.zip with ${names.length} STL files.`);
    });
  }

  #exportFiles() {
    const shell = this.#shell;
    const stem = fileStem(shell.state.model.name);
    const ids = shell.state.segmentation.patches.map((p) => p.id);
    shell.enqueue('Writing patch files', async (progress, checkpoint) => {
      await shell.restoreEngine(progress, checkpoint);
      for (const [i, id] of ids.entries()) {
        progress('Writing patch files', i / ids.length);
        download(await shell.engine.request('segment.patchStl', { patchId: id }), `${stem}_patch${id}.stl`, 'model/stl');
        // Browsers drop downloads started in the same instant.
        await new Promise((resolve) => setTimeout(resolve, 150));
        checkpoint();
      }
      shell.setStatus(`Saved ${ids.length} STL files (the browser may ask once to allow several downloads).`);
    });
  }

  #wire() {
    const form = this.#form;
    form.addEventListener('input', () => this.#onInput());
    form.addEventListener('change', () => this.#onChange());
    form.addEventListener('submit', (event) => {
      event.preventDefault();
      const result = this.#validate();
      if (result.error) {
        form.querySelector('[aria-invalid="true"]')?.focus();
        return;
      }
      Object.assign(this.#s, result.settings);
      persistSettings(this.#s);
      this.requestSegmentation({ force: true });
    });
    form.querySelector('#defaults-button').addEventListener('click', () => {
      Object.assign(this.#s, DEFAULTS);
      this.#renderForm();
      persistSettings(this.#s);
      this.requestSegmentation();
    });
    const $ = (id) => document.getElementById(id);
    $('export-selected').addEventListener('click', () => this.#exportSelected());
    $('export-zip').addEventListener('click', () => this.#exportZip());
    $('export-files').addEventListener('click', () => this.#exportFiles());
    $('export-csv').addEventListener('click', () => {
      download(tableToCsv(this.#table()), `${fileStem(this.#shell.state.model.name)}_patches.csv`, 'text/csv');
    });
    $('export-json').addEventListener('click', () => {
      download(tableToJson(this.#table()), `${fileStem(this.#shell.state.model.name)}_patches.json`, 'application/json');
    });
  }
}

export const segmentTool = new SegmentTool();

/** Everything that describes one segmentation, as one plain object (the JSON export). */
function patchTable({ model, segmentation, params, units }) {
  return {
    generator: 'skinpath',
    created: new Date().toISOString(),
    model: {
      name: model.name,
      format: model.report.format,
      triangles: model.report.triangles,
      vertices: model.report.vertices,
      area: model.report.area,
      bboxMin: model.report.bboxMin,
      bboxMax: model.report.bboxMax,
    },
    // STL has no units: "length" is the unit the user said the file's numbers are in.
    units: { length: units.length, area: `${units.length}^2`, angle: 'rad', curvature: `1/${units.length}` },
    parameters: params,
    threshold: { kind: segmentation.thresholdKind, value: segmentation.threshold },
    patchCount: segmentation.patchCount,
    patches: segmentation.patches.map((p) => ({
      id: p.id,
      triangleCount: p.triangleCount,
      area: p.area,
      normal: p.normal,
      maxDeviation: p.maxDeviation,
      centroid: p.centroid,
    })),
  };
}

function tableToJson(table) {
  return JSON.stringify(table, null, 2) + '\n';
}

/** CSV with the parameters as leading '#' comment lines (pandas: comment='#'). */
function tableToCsv(table) {
  const u = table.units.length;
  const lines = [
    `# skinpath patch table for ${table.model.name}`,
    `# units: length ${u}, area ${u}^2, angles rad`,
    `# parameters: ${JSON.stringify(table.parameters)}`,
    `# growing threshold: ${table.threshold.kind} ${table.threshold.value}`,
    ['patch_id', 'triangles', `area_${u}2`, 'normal_x', 'normal_y', 'normal_z', 'max_deviation_rad',
      `centroid_x_${u}`, `centroid_y_${u}`, `centroid_z_${u}`].join(','),
  ];
  for (const p of table.patches) {
    lines.push([p.id, p.triangleCount, p.area, ...p.normal, p.maxDeviation, ...p.centroid].join(','));
  }
  return lines.join('\r\n') + '\r\n';
}

