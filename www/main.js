// The application: DOM events, settings and state. Geometry lives in the worker (engine.js)
// and drawing in the viewer (viewer.js); this module only moves data between them and the page.
import { Engine, CancelledError } from './engine.js';
import { Viewer, patchColor } from './viewer.js';
import { download, fileStem, patchTable, tableToCsv, tableToJson } from './exports.js';
import {
  ANGLE_FIELDS, COMMON_FIELDS, CRITERION_FIELDS, DEFAULTS, DISPLAY_KEYS, FIELD_LABELS, SAMPLES,
  coreParams, inWords, loadStoredSettings, persistSettings, sanitize, settingsFromHash,
} from './settings.js';

/**
 * Largest WebAssembly memory the page will ask for. wasm32 memory tops out at 4 GiB and
 * browsers often stop at 2 GiB, so files whose estimate exceeds this are refused up front.
 */
const MAX_WASM_BYTES = 2 * 1024 ** 3;
/** Core memory per triangle, beyond the file's own bytes (welded mesh, adjacency, results). */
const BYTES_PER_TRIANGLE = 200;
/** Typical size of one ASCII STL facet, used to guess the triangle count of ASCII files. */
const ASCII_BYTES_PER_TRIANGLE = 250;
/** Rows drawn in the patch table; the rest are summarised (the exports hold them all). */
const MAX_TABLE_ROWS = 2000;

const $ = (id) => document.getElementById(id);
const form = $('seg-form');

const state = {
  settings: { ...DEFAULTS },
  model: null, // { name, source, report, triangleCount, vertexCount }
  segmentation: null, // { patchCount, threshold, thresholdKind, patches }
  segmentedParams: null, // core params of the segmentation on screen
  selected: null,
  hovered: null,
  hidden: new Set(), // patch ids not drawn; -1 stands for the dropped triangles
  sort: { key: 'id', descending: false },
  memoryBytes: null,
};

let engine;
let viewer;

// ---------------------------------------------------------------- formatting

const integer = new Intl.NumberFormat('en-US');

/** A measured quantity with `digits` significant figures, thin grouping, no exponent for common sizes. */
function num(x, digits = 4) {
  if (!Number.isFinite(x)) return '–';
  if (x === 0) return '0';
  const magnitude = Math.abs(x);
  if (magnitude >= 1e-3 && magnitude < 1e7) {
    return new Intl.NumberFormat('en-US', { maximumSignificantDigits: digits }).format(x);
  }
  const [mantissa, exponent] = x.toExponential(digits - 1).split('e');
  return `${mantissa} × 10^${Number(exponent)}`;
}

const unitOf = {
  length: () => state.settings.unit,
  area: () => `${state.settings.unit}²`,
  curvature: () => `1/${state.settings.unit}`,
  angle: () => (state.settings.angleUnit === 'deg' ? '°' : 'rad'),
};

function angleText(rad, digits = 4) {
  return state.settings.angleUnit === 'deg' ? `${num((rad * 180) / Math.PI, digits)}°` : `${num(rad, digits)} rad`;
}

function bytesText(bytes) {
  if (bytes >= 1024 ** 3) return `${num(bytes / 1024 ** 3, 3)} GiB`;
  if (bytes >= 1024 ** 2) return `${num(bytes / 1024 ** 2, 3)} MiB`;
  return `${num(bytes / 1024, 3)} KiB`;
}

function thresholdText({ kind, value }) {
  if (kind === 'angle') {
    const deg = `${num((value * 180) / Math.PI)}°`;
    return `α = ${num(value)} rad (${deg})`;
  }
  return `κ = ${num(value)} ${unitOf.curvature()}`;
}

// ---------------------------------------------------------------- the form

function input(name) {
  return name === 'minAreaRatio' ? form.elements.minAreaPercent : form.elements[name];
}

/** Short text for a field: no 0.35000000000000003 (and 6 digits are plenty for degrees). */
function fieldText(x, digits = 10) {
  return String(Number(x.toPrecision(digits)));
}

function renderForm() {
  const s = state.settings;
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
    const el = input(name);
    el.value = fieldText(value, digits);
    // Unedited fields keep the exact stored value (degrees shown rounded are not re-read).
    el.dataset.shown = el.value;
    el.dataset.exact = String(s[name]);
  }
  form.elements.seedRule.value = s.seedRule;
  $('unit-select').value = s.unit;
  $('angle-unit-select').value = s.angleUnit;
  $('up-select').value = s.up;
  renderUnits();
  validateForm();
}

function renderUnits() {
  for (const el of document.querySelectorAll('[data-unit]')) el.textContent = unitOf[el.dataset.unit]();
  // Angle inputs: degrees allow larger numbers.
  input('thetaMax').max = state.settings.angleUnit === 'deg' ? '180' : String(Math.PI);
}

/**
 * Reads the form into candidate settings and checks them: per field (a number, in range),
 * then the core's own check through deriveThreshold. Marks bad fields inline.
 * Returns { settings, params, threshold } or { error }.
 */
function readForm() {
  const s = {
    ...state.settings,
    criterion: form.elements.criterion.value || state.settings.criterion,
    seedRule: form.elements.seedRule.value || state.settings.seedRule,
  };
  const names = [...CRITERION_FIELDS[s.criterion], ...COMMON_FIELDS];
  const problems = new Map();
  for (const name of names) {
    const el = input(name);
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
  if (problems.size === 0) {
    try {
      threshold = engine.deriveThreshold(params);
    } catch (error) {
      // The core names the problem; flag the criterion's fields (or the one it names).
      const named = names.filter((n) => error.message.includes(n) || error.message.toLowerCase().includes(FIELD_LABELS[n]));
      for (const n of named.length ? named : CRITERION_FIELDS[s.criterion]) problems.set(n, null);
      problems.set('_core', error.message);
    }
  }
  for (const name of [...Object.values(CRITERION_FIELDS).flat(), ...COMMON_FIELDS]) {
    input(name).setAttribute('aria-invalid', String(problems.has(name)));
  }
  if (problems.size) {
    const message = problems.get('_core') ?? [...problems.values()].find(Boolean);
    return { error: inWords(message) };
  }
  return { settings: s, params, threshold };
}


function validateForm() {
  const result = readForm();
  $('threshold-value').textContent = result.error ? '–' : thresholdText(result.threshold);
  $('params-error').textContent = result.error ?? '';
  $('segment-button').disabled = Boolean(result.error);
  return result;
}

function onFormInput() {
  const result = validateForm();
  for (const block of form.querySelectorAll('.criterion-fields')) {
    block.hidden = block.dataset.criterion !== form.elements.criterion.value;
  }
  if (result.error) return;
  state.settings = result.settings;
  persistSettings(state.settings);
}

let autoSegmentTimer = 0;
/** Committed edits (Enter, leaving a field, a new criterion) re-segment by themselves. */
function onFormChange() {
  const result = validateForm();
  if (result.error || !state.model) return;
  if (JSON.stringify(result.params) === JSON.stringify(state.segmentedParams)) return;
  clearTimeout(autoSegmentTimer);
  autoSegmentTimer = setTimeout(requestSegmentation, 150);
}

// ---------------------------------------------------------------- jobs, busy state, progress

let queue = Promise.resolve();
let queuedJobs = 0;
let epoch = 0; // bumped by Cancel: jobs queued before it are dropped
let segmentationQueued = false;
let progressTimer = 0;

function setBusy(busy) {
  document.body.dataset.state = busy ? 'busy' : 'ready';
  form.setAttribute('aria-busy', String(busy));
}

// The core's progress stages, in words (unknown ones are shown as they come).
const STAGE_NAMES = {
  parse: 'Reading the STL',
  adjacency: 'Finding neighbouring triangles',
  orient: 'Making the winding consistent',
  geometry: 'Computing normals and areas',
  regions: 'Growing regions',
  planarise: 'Splitting regions into near-planar patches',
  patches: 'Measuring the patches',
};

function showProgress(rawStage, fraction) {
  const stage = STAGE_NAMES[rawStage] ?? rawStage.charAt(0).toUpperCase() + rawStage.slice(1);
  $('progress-stage').textContent = stage;
  const bar = $('progress-bar');
  if (fraction === null || fraction === undefined) {
    bar.removeAttribute('value');
    $('progress-percent').textContent = '';
  } else {
    bar.value = fraction;
    $('progress-percent').textContent = `${Math.round(fraction * 100)} %`;
  }
  setStatus(`${stage}…`);
}

/**
 * Runs jobs one after another; `fn(progress, checkpoint)` may throw, errors land in the alert.
 * `checkpoint()` throws CancelledError once Cancel was pressed: jobs call it after awaiting
 * anything that is not the engine (reading a file), since only the engine stops by itself.
 */
function enqueue(label, fn) {
  const myEpoch = epoch;
  const checkpoint = () => {
    if (epoch !== myEpoch) throw new CancelledError();
  };
  queuedJobs++;
  setBusy(true);
  const run = async () => {
    if (myEpoch !== epoch) return;
    // Small jobs finish before the overlay would flash; show it only if the work lasts.
    clearTimeout(progressTimer);
    progressTimer = setTimeout(() => { $('progress').hidden = false; }, 150);
    showProgress(label, null);
    try {
      await fn((stage, fraction) => {
        if (epoch === myEpoch) showProgress(stage, fraction);
      }, checkpoint);
    } catch (error) {
      if (error instanceof CancelledError) {
        setStatus('Cancelled. The model on screen is unchanged.');
      } else {
        showAlert(error.message);
        setStatus(state.model ? `Still showing ${state.model.name}.` : 'No model loaded.');
      }
    } finally {
      clearTimeout(progressTimer);
      $('progress').hidden = true;
    }
  };
  queue = queue.then(run).finally(() => {
    queuedJobs--;
    if (queuedJobs === 0) setBusy(false);
  });
  return queue;
}

function cancelWork() {
  epoch++;
  segmentationQueued = false;
  engine.cancel(); // the worker restarts without the mesh; it is reloaded on the next segmentation
}

function setStatus(text) {
  $('status').textContent = text;
}

function showAlert(message) {
  $('alert-box').hidden = false;
  $('alert').textContent = message;
}

function hideAlert() {
  $('alert-box').hidden = true;
  $('alert').textContent = '';
}

// ---------------------------------------------------------------- loading

/** Reads the first bytes to estimate the wasm memory a file needs; returns a refusal or null. */
async function refusalForSize(file) {
  const head = new Uint8Array(await file.slice(0, 84).arrayBuffer());
  const startsWithSolid = new TextDecoder().decode(head.subarray(0, 5)).toLowerCase() === 'solid';
  const declared = head.length === 84 ? new DataView(head.buffer).getUint32(80, true) : -1;
  const ascii = startsWithSolid && 84 + 50 * declared !== file.size;
  const triangles = ascii ? file.size / ASCII_BYTES_PER_TRIANGLE : Math.max(0, file.size - 84) / 50;
  const needed = file.size + BYTES_PER_TRIANGLE * triangles;
  if (needed <= MAX_WASM_BYTES) return null;
  return `"${file.name}" is ${bytesText(file.size)} (about ${integer.format(Math.round(triangles))} triangles). ` +
    `Processing it would need about ${bytesText(needed)} of WebAssembly memory, more than the ${bytesText(MAX_WASM_BYTES)} ` +
    'a browser tab can rely on. Split or decimate the mesh and open the parts.';
}

async function readSource(source, progress) {
  if (source.kind === 'file') {
    try {
      return await source.file.arrayBuffer();
    } catch {
      throw new Error(`"${source.file.name}" can no longer be read (was it moved or deleted?). Open it again.`);
    }
  }
  const response = await fetch(source.url);
  if (!response.ok) throw new Error(`The sample ${source.url} could not be loaded (HTTP ${response.status}).`);
  // Content-Length is only a hint for the bar: a compressing server sends fewer bytes.
  const total = Number(response.headers.get('Content-Length')) || 0;
  if (!total || !response.body) return response.arrayBuffer();
  const chunks = [];
  let received = 0;
  const reader = response.body.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    chunks.push(value);
    received += value.length;
    progress('Downloading the sample', Math.min(received / total, 1));
  }
  return new Blob(chunks).arrayBuffer();
}

/** Opens a file or sample: parse + segment in the worker; the old model stays on failure. */
function openSource(source, name) {
  return enqueue(`Opening ${name}`, async (progress, checkpoint) => {
    hideAlert();
    const buffer = await readSource(source, progress);
    checkpoint();
    const validated = validateForm();
    const params = validated.error ? null : validated.params;
    let result;
    try {
      result = await engine.open(buffer, name, params, progress);
    } catch (error) {
      if (error instanceof CancelledError) throw error;
      throw new Error(`Could not open "${name}": ${error.message}`);
    }
    state.model = { name, source, report: result.report, triangleCount: result.triangleCount, vertexCount: result.vertexCount };
    state.settings.sample = source.kind === 'sample' ? source.id : '';
    let upNote = '';
    if (source.kind === 'file') {
      const up = guessUpAxis(result.report);
      if (up !== state.settings.up) setUpAxis(up);
      upNote = ` Shown ${up.toUpperCase()} up (its thinnest direction); U switches.`;
    }
    persistSettings(state.settings);
    renderModel();
    progress('Drawing', null);
    showSegmentation(result, params, { keepView: false });
    if (result.segmentError) $('params-error').textContent = inWords(result.segmentError);
    const seconds = (ms) => `${num(ms / 1000, 2)} s`;
    setStatus(`Opened ${name} in ${seconds(result.timings.parseMs)}` +
      (result.segmentation ? `; ${result.segmentation.patchCount} patches in ${seconds(result.timings.segmentMs)}.` : '.') + upNote);
  });
}

/**
 * Files come Y-up or Z-up. An aircraft is flattest along its up axis, so the smaller of the
 * y and z extents of the bounding box is taken as up (no paper; right for all sample meshes).
 */
function guessUpAxis({ bboxMin, bboxMax }) {
  return bboxMax[2] - bboxMin[2] < bboxMax[1] - bboxMin[1] ? 'z' : 'y';
}

async function openFile(file) {
  if (!file) return;
  hideAlert();
  const refusal = await refusalForSize(file);
  if (refusal) {
    showAlert(refusal);
    if (queuedJobs === 0) setBusy(false);
    return;
  }
  await openSource({ kind: 'file', file }, file.name);
}

function openSample(id, { applyDisplay = true } = {}) {
  const sample = SAMPLES.find((s) => s.id === id) ?? SAMPLES[0];
  if (applyDisplay) {
    // The samples' axes and units are known (see samples/LICENSES.md).
    state.settings.up = sample.up;
    state.settings.unit = sample.unit;
    renderForm();
    viewer.setUpAxis(sample.up);
    refreshUnits();
  }
  return openSource({ kind: 'sample', id: sample.id, url: `./samples/${sample.file}` }, sample.file);
}

/**
 * Queues one re-segmentation with the settings current when it starts; without `force` it
 * is skipped when they are those of the segmentation on screen.
 */
function requestSegmentation({ force = false } = {}) {
  if (!state.model || segmentationQueued) return;
  segmentationQueued = true;
  enqueue('Segmenting', async (progress, checkpoint) => {
    segmentationQueued = false;
    const validated = validateForm();
    if (validated.error || !state.model) return;
    const same = JSON.stringify(validated.params) === JSON.stringify(state.segmentedParams);
    if (same && !force && engine.hasMesh) return;
    hideAlert();
    let result;
    if (!engine.hasMesh) {
      // After Cancel or an engine failure the worker is new: give it the model again.
      const buffer = await readSource(state.model.source, progress);
      checkpoint();
      result = await engine.open(buffer, state.model.name, validated.params, progress);
      if (result.segmentError) throw new Error(`The segmentation failed: ${inWords(result.segmentError)}`);
    } else {
      try {
        result = await engine.segment(validated.params, progress);
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        throw new Error(`The segmentation failed: ${inWords(error.message).replace(/\.?$/, '.')} The patches on screen are unchanged.`);
      }
    }
    progress('Drawing', null);
    showSegmentation(result, validated.params, { keepView: true });
    setStatus(`${result.segmentation.patchCount} patches in ${num(result.timings.segmentMs / 1000, 2)} s ` +
      `(${thresholdText({ kind: result.segmentation.thresholdKind, value: result.segmentation.threshold })}).`);
  });
}

// ---------------------------------------------------------------- results

function renderModel() {
  const { report, name } = state.model;
  $('model-name').textContent = name;
  $('stat-triangles').textContent = integer.format(report.triangles);
  $('stat-vertices').textContent = integer.format(report.vertices);
  $('stat-format').textContent = report.format === 'ascii' ? 'ASCII STL' : 'binary STL';
  renderWarnings(report);
  refreshUnits();
  document.body.dataset.model = name;
}

function renderWarnings(r) {
  const items = [];
  const n = (count, one, many) => `${integer.format(count)} ${count === 1 ? one : many}`;
  if (r.skippedTriangles) items.push(`${n(r.skippedTriangles, 'triangle was', 'triangles were')} unreadable (for example NaN or infinite coordinates) and skipped.`);
  if (r.degenerateTriangles) items.push(`${n(r.degenerateTriangles, 'triangle has', 'triangles have')} no area (collapsed to a line or point); they do not count towards patches.`);
  if (r.boundaryEdges) items.push(`${n(r.boundaryEdges, 'open edge', 'open edges')}: the surface has holes or gaps, so it is not watertight. Patches stop at the gaps.`);
  if (r.nonManifoldEdges) items.push(`${n(r.nonManifoldEdges, 'edge is', 'edges are')} shared by more than two triangles (non-manifold), as where separate parts touch.`);
  if (r.components > 1) items.push(`The model has ${integer.format(r.components)} separate shells that do not share edges; each is segmented on its own.`);
  if (r.flippedTriangles) items.push(`${n(r.flippedTriangles, 'triangle was', 'triangles were')} wound the other way round than their neighbours and ${r.flippedTriangles === 1 ? 'has' : 'have'} been re-wound.`);
  if (r.inconsistentEdges) items.push(`${n(r.inconsistentEdges, 'edge joins', 'edges join')} triangles whose winding could not be made consistent (the surface is not orientable there).`);
  if (r.trailingBytes) items.push(`${n(r.trailingBytes, 'byte', 'bytes')} after the last triangle were ignored.`);
  const list = $('warnings');
  list.replaceChildren(...items.map((text) => Object.assign(document.createElement('li'), { textContent: text })));
  if (!items.length) {
    const ok = Object.assign(document.createElement('li'), { textContent: 'No defects found: one closed, consistently wound shell.', className: 'ok' });
    list.append(ok);
  }
}

/** Everything on the page that shows a length, area or angle, in the current units. */
function refreshUnits() {
  renderUnits();
  if (state.model) {
    const { bboxMin, bboxMax, area } = state.model.report;
    const u = state.settings.unit;
    $('stat-size').textContent = `${[0, 1, 2].map((i) => num(bboxMax[i] - bboxMin[i])).join(' × ')} ${u}`;
    $('stat-area').textContent = `${num(area)} ${u}²`;
  }
  validateForm();
  renderPatchTable();
  renderSummary();
}

function showSegmentation(result, params, { keepView }) {
  state.segmentation = result.segmentation;
  state.segmentedParams = result.segmentation ? params : null;
  state.memoryBytes = result.memoryBytes;
  state.selected = null;
  state.hovered = null;
  state.hidden = $('show-dropped').checked ? new Set() : new Set([-1]);
  $('hover-tip').hidden = true;
  viewer.setModel(result.display, { keepView });
  syncViewer();
  $('stat-memory').textContent = bytesText(result.memoryBytes);
  renderPatchTable();
  renderSummary();
  updateExportButtons();
  document.body.dataset.patches = String(result.segmentation?.patchCount ?? 0);
  document.body.dataset.segmentations = String(Number(document.body.dataset.segmentations ?? 0) + 1);
}

function renderSummary() {
  const seg = state.segmentation;
  const summary = $('patch-summary');
  if (!state.model) return;
  if (!seg) {
    summary.textContent = 'Not segmented: check the settings on the left.';
    return;
  }
  const covered = seg.patches.reduce((sum, p) => sum + p.area, 0);
  const keptTriangles = seg.patches.reduce((sum, p) => sum + p.triangleCount, 0);
  const dropped = state.model.report.triangles - keptTriangles;
  const share = state.model.report.area > 0 ? (100 * covered) / state.model.report.area : 100;
  if (seg.patchCount === 0) {
    summary.textContent = `No patch reaches the minimum area (${num(100 * (state.segmentedParams?.minAreaRatio ?? state.settings.minAreaRatio), 3)} % of the surface): ` +
      'lower the minimum patch area, or loosen the growing threshold so regions can grow.';
    return;
  }
  summary.textContent = `${seg.patchCount} ${seg.patchCount === 1 ? 'patch covers' : 'patches cover'} ${num(share, 3)} % of the surface` +
    (dropped > 0 ? `; ${integer.format(dropped)} triangles in small regions are dropped (grey).` : '.');
}

function sortedPatches() {
  const { key, descending } = state.sort;
  const patches = [...(state.segmentation?.patches ?? [])];
  patches.sort((a, b) => (a[key] - b[key]) * (descending ? -1 : 1) || a.id - b.id);
  return patches;
}

const EYE = '<svg aria-hidden="true" viewBox="0 0 16 16" width="14" height="14"><path d="M1 8s2.5-4.5 7-4.5S15 8 15 8s-2.5 4.5-7 4.5S1 8 1 8z" fill="none" stroke="currentColor" stroke-width="1.3"/><circle cx="8" cy="8" r="2" fill="currentColor"/></svg>';
const TARGET = '<svg aria-hidden="true" viewBox="0 0 16 16" width="14" height="14"><circle cx="8" cy="8" r="5.5" fill="none" stroke="currentColor" stroke-width="1.3"/><circle cx="8" cy="8" r="1.8" fill="currentColor"/></svg>';

function renderPatchTable() {
  const body = $('patch-rows');
  const patches = sortedPatches();
  const shown = patches.slice(0, MAX_TABLE_ROWS);
  const rows = shown.map((p) => {
    const tr = document.createElement('tr');
    tr.dataset.patchId = String(p.id);
    tr.tabIndex = -1;
    tr.setAttribute('aria-selected', String(p.id === state.selected));
    tr.classList.toggle('is-hidden', state.hidden.has(p.id));
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.backgroundColor = patchColor(p.id);
    const idCell = document.createElement('td');
    idCell.append(swatch, `${p.id}`);
    const cell = (text, className) => Object.assign(document.createElement('td'), { textContent: text, className: className ?? '' });
    const actions = document.createElement('td');
    const hidden = state.hidden.has(p.id);
    actions.innerHTML = `<span class="row-actions">` +
      `<button type="button" data-action="toggle" aria-pressed="${!hidden}" aria-label="${hidden ? 'Show' : 'Hide'} patch ${p.id}" title="${hidden ? 'Show' : 'Hide'} (H)">${EYE}</button>` +
      `<button type="button" data-action="isolate" aria-label="Show only patch ${p.id}" title="Isolate (I)">${TARGET}</button></span>`;
    tr.append(
      idCell,
      cell(integer.format(p.triangleCount)),
      cell(num(p.area)),
      cell(p.normal.map((c) => (Math.abs(c) < 0.005 ? 0 : c).toFixed(2)).join(',\u2009'), 'normal'),
      cell(state.settings.angleUnit === 'deg' ? ((p.maxDeviation * 180) / Math.PI).toFixed(1) : p.maxDeviation.toFixed(3)),
      actions,
    );
    return tr;
  });
  body.replaceChildren(...rows);
  const focusRow = body.querySelector('tr[aria-selected="true"]') ?? body.firstElementChild;
  if (focusRow) focusRow.tabIndex = 0;
  const note = $('patch-table-note');
  note.hidden = patches.length <= MAX_TABLE_ROWS;
  note.textContent = `Showing the first ${integer.format(MAX_TABLE_ROWS)} of ${integer.format(patches.length)} patches in this order; the exports contain all of them.`;
  for (const th of document.querySelectorAll('#patch-table th')) {
    const key = th.querySelector('button[data-sort]')?.dataset.sort;
    if (!key) continue;
    if (key === state.sort.key) th.setAttribute('aria-sort', state.sort.descending ? 'descending' : 'ascending');
    else th.removeAttribute('aria-sort');
  }
}

function rowOf(id) {
  return $('patch-rows').querySelector(`tr[data-patch-id="${id}"]`);
}

/** Applies selection, hover and visibility to the viewer and the table without a rebuild. */
function syncViewer() {
  viewer.setPatchState({
    hidden: state.hidden,
    selected: state.selected,
    hovered: state.hovered,
    showBorders: $('show-borders').checked,
  });
}

function select(id, { scroll = true, focus = false } = {}) {
  state.selected = id;
  for (const tr of $('patch-rows').querySelectorAll('tr[aria-selected="true"]')) {
    tr.setAttribute('aria-selected', 'false');
    tr.tabIndex = -1;
  }
  const row = id === null ? null : rowOf(id);
  if (row) {
    row.setAttribute('aria-selected', 'true');
    row.tabIndex = 0;
    if (scroll) row.scrollIntoView({ block: 'nearest' });
    if (focus) row.focus();
  } else {
    const first = $('patch-rows').firstElementChild;
    if (first) first.tabIndex = 0;
  }
  syncViewer();
  updateExportButtons();
  if (id !== null) {
    const p = state.segmentation.patches.find((x) => x.id === id);
    setStatus(`Patch ${id}: ${integer.format(p.triangleCount)} triangles, ${num(p.area)} ${unitOf.area()}, ` +
      `max. deviation ${angleText(p.maxDeviation, 3)}.`);
  }
}

function setHidden(hidden) {
  state.hidden = hidden;
  $('show-dropped').checked = !hidden.has(-1);
  for (const tr of $('patch-rows').children) {
    const id = Number(tr.dataset.patchId);
    const isHidden = hidden.has(id);
    tr.classList.toggle('is-hidden', isHidden);
    const button = tr.querySelector('[data-action="toggle"]');
    button.setAttribute('aria-pressed', String(!isHidden));
    button.setAttribute('aria-label', `${isHidden ? 'Show' : 'Hide'} patch ${id}`);
    button.title = `${isHidden ? 'Show' : 'Hide'} (H)`;
  }
  syncViewer();
}

function toggleHidden(id) {
  const hidden = new Set(state.hidden);
  if (hidden.has(id)) hidden.delete(id);
  else hidden.add(id);
  setHidden(hidden);
}

/** Shows only `id` (dropped triangles too are hidden); isolating it again shows everything. */
function isolate(id) {
  const all = state.segmentation.patches.map((p) => p.id);
  const alone = !state.hidden.has(id) && all.every((x) => x === id || state.hidden.has(x));
  setHidden(alone ? new Set() : new Set([-1, ...all.filter((x) => x !== id)]));
}

function updateExportButtons() {
  const hasPatches = Boolean(state.segmentation?.patchCount);
  $('export-selected').disabled = !hasPatches || state.selected === null;
  $('export-zip').disabled = !hasPatches;
  $('export-files').disabled = !hasPatches;
  $('export-csv').disabled = !state.segmentation;
  $('export-json').disabled = !state.segmentation;
}

// ---------------------------------------------------------------- exports

/**
 * After Cancel or an engine failure the worker is new and empty: give it the model and the
 * segmentation on screen again (same input, same parameters, so the same patch ids).
 */
async function restoreEngine(progress, checkpoint) {
  if (engine.hasMesh) return;
  const buffer = await readSource(state.model.source, progress);
  checkpoint();
  const result = await engine.open(buffer, state.model.name, state.segmentedParams, progress);
  if (result.segmentError) throw new Error(result.segmentError);
}

function currentTable() {
  return patchTable({
    model: state.model,
    segmentation: state.segmentation,
    params: state.segmentedParams,
    units: { length: state.settings.unit },
  });
}

function exportSelected() {
  const id = state.selected;
  const stem = fileStem(state.model.name);
  enqueue(`Writing patch ${id}`, async (progress, checkpoint) => {
    await restoreEngine(progress, checkpoint);
    const bytes = await engine.patchStl(id);
    download(bytes, `${stem}_patch${id}.stl`, 'model/stl');
    setStatus(`Saved ${stem}_patch${id}.stl.`);
  });
}

function exportZip() {
  const stem = fileStem(state.model.name);
  const names = state.segmentation.patches.map((p) => ({ patchId: p.id, fileName: `${stem}_patch${p.id}.stl` }));
  enqueue('Writing the archive', async (progress, checkpoint) => {
    await restoreEngine(progress, checkpoint);
    const bytes = await engine.zipPatches(names, progress);
    download(bytes, `${stem}_patches.zip`, 'application/zip');
    setStatus(`Saved ${stem}_patches.zip with ${names.length} STL files.`);
  });
}

function exportFiles() {
  const stem = fileStem(state.model.name);
  const ids = state.segmentation.patches.map((p) => p.id);
  enqueue('Writing patch files', async (progress, checkpoint) => {
    await restoreEngine(progress, checkpoint);
    for (const [i, id] of ids.entries()) {
      progress('Writing patch files', i / ids.length);
      download(await engine.patchStl(id), `${stem}_patch${id}.stl`, 'model/stl');
      // Browsers drop downloads started in the same instant.
      await new Promise((resolve) => setTimeout(resolve, 150));
      checkpoint();
    }
    setStatus(`Saved ${ids.length} STL files (the browser may ask once to allow several downloads).`);
  });
}

// ---------------------------------------------------------------- events

function wireEvents() {
  const fileInput = $('file-input');
  $('open-button').addEventListener('click', () => fileInput.click());
  fileInput.addEventListener('change', () => {
    const file = fileInput.files[0];
    if (file) setBusy(true); // at once, so that waiting on "ready" never sees a stale state
    openFile(file).finally(() => { fileInput.value = ''; });
  });

  // Drop anywhere on the page (the viewport shows where): the browser must not navigate away.
  const overlay = $('drop-overlay');
  let dragDepth = 0;
  const hasFiles = (event) => [...(event.dataTransfer?.types ?? [])].includes('Files');
  window.addEventListener('dragenter', (event) => {
    if (!hasFiles(event)) return;
    event.preventDefault();
    dragDepth++;
    overlay.hidden = false;
  });
  window.addEventListener('dragover', (event) => {
    if (!hasFiles(event)) return;
    event.preventDefault();
    event.dataTransfer.dropEffect = 'copy';
  });
  window.addEventListener('dragleave', () => {
    dragDepth = Math.max(0, dragDepth - 1);
    if (dragDepth === 0) overlay.hidden = true;
  });
  window.addEventListener('drop', (event) => {
    if (!hasFiles(event)) return;
    event.preventDefault();
    dragDepth = 0;
    overlay.hidden = true;
    const files = [...event.dataTransfer.files];
    const file = files.find((f) => /\.stl$/i.test(f.name)) ?? files[0];
    if (!file) return;
    setBusy(true);
    openFile(file);
    if (files.length > 1) setStatus(`Opening ${file.name}; one file at a time, the others were ignored.`);
  });

  // Samples menu
  const list = $('samples-list');
  for (const sample of SAMPLES) {
    const button = document.createElement('button');
    button.type = 'button';
    button.dataset.sample = sample.id;
    button.innerHTML = `<span></span><span class="sample-meta"></span>`;
    button.firstChild.textContent = sample.name;
    button.lastChild.textContent = sample.meta;
    button.addEventListener('click', () => {
      $('samples-menu').open = false;
      $('samples-menu').querySelector('summary').focus(); // the clicked item is hidden now
      setBusy(true);
      openSample(sample.id);
    });
    list.append(button);
  }
  // Close menus on outside click or Escape, like native menus.
  document.addEventListener('click', (event) => {
    for (const menu of document.querySelectorAll('details.menu[open]')) {
      if (!menu.contains(event.target)) menu.open = false;
    }
  });

  // Settings form
  form.addEventListener('input', onFormInput);
  form.addEventListener('change', onFormChange);
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    const result = validateForm();
    if (result.error) {
      form.querySelector('[aria-invalid="true"]')?.focus();
      return;
    }
    state.settings = result.settings;
    persistSettings(state.settings);
    requestSegmentation({ force: true });
  });
  $('defaults-button').addEventListener('click', () => {
    const keep = Object.fromEntries([...DISPLAY_KEYS, 'sample'].map((k) => [k, state.settings[k]]));
    state.settings = { ...DEFAULTS, ...keep };
    renderForm();
    persistSettings(state.settings);
    requestSegmentation();
  });

  $('unit-select').addEventListener('change', (event) => {
    state.settings.unit = event.target.value;
    persistSettings(state.settings);
    refreshUnits();
    // Grinding tool lengths are in mm: in another file unit they give another κ.
    if (state.settings.criterion === 'grind') requestSegmentation();
  });
  $('angle-unit-select').addEventListener('change', (event) => {
    // Keep what is typed valid: convert the angle fields in place.
    const current = readForm();
    if (!current.error) state.settings = current.settings;
    state.settings.angleUnit = event.target.value;
    persistSettings(state.settings);
    renderForm();
    refreshUnits();
  });
  $('up-select').addEventListener('change', (event) => setUpAxis(event.target.value));

  // View
  for (const button of document.querySelectorAll('.view-toolbar [data-view]')) {
    button.addEventListener('click', () => viewer.setView(button.dataset.view));
  }
  viewer.addEventListener('hover', (event) => onHover(event.detail));
  viewer.addEventListener('pick', (event) => {
    const id = event.detail.patchId;
    select(id !== null && id >= 0 ? id : null);
  });

  // Patch table
  for (const button of document.querySelectorAll('#patch-table th button[data-sort]')) {
    button.addEventListener('click', () => {
      const key = button.dataset.sort;
      state.sort = { key, descending: state.sort.key === key ? !state.sort.descending : key !== 'id' };
      renderPatchTable();
    });
  }
  const rows = $('patch-rows');
  rows.addEventListener('click', (event) => {
    const tr = event.target.closest('tr[data-patch-id]');
    if (!tr) return;
    const id = Number(tr.dataset.patchId);
    const action = event.target.closest('button[data-action]')?.dataset.action;
    if (action === 'toggle') toggleHidden(id);
    else if (action === 'isolate') isolate(id);
    else select(id, { scroll: false, focus: true });
  });
  rows.addEventListener('dblclick', (event) => {
    const tr = event.target.closest('tr[data-patch-id]');
    if (tr && !event.target.closest('button')) viewer.fitPatch(Number(tr.dataset.patchId));
  });
  rows.addEventListener('keydown', (event) => {
    const tr = event.target.closest('tr[data-patch-id]');
    if (!tr || event.target !== tr) return;
    let next = null;
    if (event.key === 'ArrowDown') next = tr.nextElementSibling;
    else if (event.key === 'ArrowUp') next = tr.previousElementSibling;
    else if (event.key === 'Home') next = rows.firstElementChild;
    else if (event.key === 'End') next = rows.lastElementChild;
    else if (event.key === 'Enter' || event.key === ' ') next = tr;
    if (!next) return;
    event.preventDefault();
    select(Number(next.dataset.patchId), { focus: true });
  });
  $('show-all-button').addEventListener('click', () => setHidden(new Set()));
  $('show-borders').addEventListener('change', syncViewer);
  $('show-dropped').addEventListener('change', (event) => {
    const hidden = new Set(state.hidden);
    if (event.target.checked) hidden.delete(-1);
    else hidden.add(-1);
    setHidden(hidden);
  });

  // Exports
  $('export-selected').addEventListener('click', exportSelected);
  $('export-zip').addEventListener('click', exportZip);
  $('export-files').addEventListener('click', exportFiles);
  $('export-csv').addEventListener('click', () => {
    download(tableToCsv(currentTable()), `${fileStem(state.model.name)}_patches.csv`, 'text/csv');
  });
  $('export-json').addEventListener('click', () => {
    download(tableToJson(currentTable()), `${fileStem(state.model.name)}_patches.json`, 'application/json');
  });

  $('cancel-button').addEventListener('click', cancelWork);
  $('alert-dismiss').addEventListener('click', hideAlert);
  document.addEventListener('keydown', onShortcut);
  window.addEventListener('hashchange', onHashChange);
}

function setUpAxis(axis) {
  state.settings.up = axis;
  $('up-select').value = axis;
  persistSettings(state.settings);
  viewer.setUpAxis(axis);
}

function onHover({ patchId, clientX, clientY }) {
  const tip = $('hover-tip');
  const id = patchId ?? null;
  if (id !== state.hovered) {
    state.hovered = id;
    syncViewer();
  }
  if (id === null || !state.segmentation) {
    tip.hidden = true;
    return;
  }
  const rect = $('viewport').getBoundingClientRect();
  tip.style.left = `${clientX - rect.left}px`;
  tip.style.top = `${clientY - rect.top}px`;
  if (id < 0) {
    tip.textContent = 'Dropped: region below the minimum patch area';
  } else {
    const p = state.segmentation.patches.find((x) => x.id === id);
    tip.textContent = `Patch ${id}: ${num(p.area)} ${unitOf.area()}, ${integer.format(p.triangleCount)} triangles`;
  }
  tip.hidden = false;
}

function onShortcut(event) {
  if (event.ctrlKey || event.metaKey || event.altKey) return;
  const target = event.target;
  if (target.closest('input, select, textarea, [contenteditable="true"]')) return;
  if (event.key === 'Escape') {
    for (const menu of document.querySelectorAll('details.menu[open]')) menu.open = false;
    if (state.selected !== null) select(null);
    return;
  }
  // Buttons and rows keep Enter and Space; letters and digits are free everywhere else.
  const views = { f: 'fit', 1: 'top', 2: 'front', 3: 'side', 4: 'iso' };
  const key = event.key.toLowerCase();
  if (views[key]) viewer.setView(views[key]);
  else if (key === 'o') $('file-input').click();
  else if (key === 'u') setUpAxis(state.settings.up === 'z' ? 'y' : 'z');
  else if (key === 'a' && state.segmentation) setHidden(new Set());
  else if (key === 'h' && state.selected !== null) toggleHidden(state.selected);
  else if (key === 'i' && state.selected !== null) isolate(state.selected);
  else return;
  event.preventDefault();
}

function onHashChange() {
  const fromHash = settingsFromHash(location.hash);
  const previous = state.settings;
  state.settings = { ...previous, ...fromHash };
  renderForm();
  refreshUnits();
  if (state.settings.up !== previous.up) viewer.setUpAxis(state.settings.up);
  if (fromHash.sample && fromHash.sample !== (state.model?.source.id ?? '')) {
    setBusy(true);
    openSample(fromHash.sample, { applyDisplay: !('up' in fromHash) });
  } else {
    requestSegmentation();
  }
}

// ---------------------------------------------------------------- start

async function main() {
  const fromHash = settingsFromHash(location.hash);
  const stored = sanitize(loadStoredSettings());
  state.settings = { ...DEFAULTS, ...stored, ...fromHash };
  try {
    viewer = new Viewer($('viewer'));
  } catch {
    showAlert('This browser could not start WebGL, which the 3D view needs. Enable hardware acceleration or try another browser.');
    document.body.dataset.state = 'failed';
    return;
  }
  engine = new Engine();
  try {
    await engine.start();
  } catch (error) {
    showAlert(`The processing engine could not start: ${error.message}`);
    document.body.dataset.state = 'failed';
    setStatus('Not ready.');
    return;
  }
  viewer.setUpAxis(state.settings.up);
  renderForm();
  wireEvents();
  setStatus('Ready.');
  // First visit: open the default sample. A shared link or a later visit reopens its sample
  // with the settings it carries (the link's axis and unit win over the sample's own).
  const sample = state.settings.sample || DEFAULTS.sample;
  const linkSetsDisplay = 'up' in fromHash || 'unit' in fromHash;
  const storedForThisSample = stored.sample === sample; // keep what the user chose for it
  await openSample(sample, { applyDisplay: !linkSetsDisplay && !storedForThisSample });
}

main();
