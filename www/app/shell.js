// The workbench shell: what every tool shares. It loads models (files, drops, samples), keeps
// the unit and view settings, the patch list and the selection, runs jobs one at a time on
// the engine (worker channel) with progress, Cancel and the alert area, and hosts the tools.
//
// Tool interface (tools/segment.js, tools/spray.js; later paths and drilling):
//   {
//     id, title,                      'spray', 'Spray'; settings keys are prefixed `${id}.`
//     settings: { order, defaults, allowed?, hashKeys(settings) }    registered with app/settings.js
//     mount(shell, { panel, results, overlay })   builds its DOM in its containers (left: inputs;
//                                         right under the patch list: results and exports;
//                                         overlay: a legend over the view, shown with its tab)
//     openParams?()                   params the worker runs for this tool right after parsing
//                                     (segmentation does, so a file opens segmented)
//     onModelLoaded?(model, result)   a new model is on screen; `result` = the tool's onOpen output
//     onSegmentation?(segmentation)   the patches changed (null = none)
//     onSelectionChanged?(patchId)    the selected patch (null = none)
//     onBeforeUnitsChange?()          about to change a unit: keep what is typed (in settings)
//     onUnitsChanged?({ unitChanged })  units may have changed: re-render numbers
//     onSettingsChanged?()            settings replaced from the URL hash
//     onActivate?() / onDeactivate?() its tab was opened / left (layers may stay or hide)
//     onEngineReady?()                the wasm engine has started (live checks may run now)
//     onEngineLost?()                 the worker was replaced (Cancel, failure): drop worker state
//   }
// Adding a tool: tools/<id>.js exporting such an object, `shell.addTool(…)` in main.js, and
// for engine work worker/<id>.js registered in worker/worker.js (TOOLS).
// Hooks run in registration order; a hook that throws is a bug and shows in the console.
// A tool talks to its worker module through shell.enqueue + shell.engine.request('<id>.<op>'),
// draws through shell.viewer.setLayer('<id>.<name>', …) and reads shell.state (read-only).
import { Engine, CancelledError } from './engine.js';
import { Viewer } from '../viewer/viewer.js';
import { bytesText, integer, metresText, num } from './format.js';
import {
  MM_PER_UNIT, SAMPLES, UNIT_NAMES, allDefaults, loadStoredSettings, persistSettings, registerSettings, sanitize,
  settingsFromHash,
} from './settings.js';
import { unitSuggestion } from './units.js';
import { PatchList } from './patches.js';

/**
 * Largest WebAssembly memory the page will ask for. wasm32 memory tops out at 4 GiB and
 * browsers often stop at 2 GiB, so files whose estimate exceeds this are refused up front.
 */
const MAX_WASM_BYTES = 2 * 1024 ** 3;
/** Core memory per triangle, beyond the file's own bytes (welded mesh, adjacency, results). */
const BYTES_PER_TRIANGLE = 200;
/** Typical size of one ASCII STL facet, used to guess the triangle count of ASCII files. */
const ASCII_BYTES_PER_TRIANGLE = 250;

const $ = (id) => document.getElementById(id);

/** A load abandoned because a later one was asked for: nothing to report. */
class SupersededError extends CancelledError {
  constructor() {
    super('superseded');
    this.name = 'SupersededError';
  }
}

export const DISPLAY_KEYS = ['unit', 'angleUnit', 'up'];

registerSettings({
  order: 1,
  defaults: { unit: 'mm', angleUnit: 'rad', up: 'z', sample: 'bwb', tool: 'segment' },
  allowed: { unit: Object.keys(MM_PER_UNIT), angleUnit: ['rad', 'deg'], up: ['y', 'z'], sample: [...SAMPLES.map((x) => x.id), ''] },
  hashKeys: (s) => [...DISPLAY_KEYS, ...(s.sample ? ['sample'] : []), ...(s.tool !== 'segment' ? ['tool'] : [])],
});

// The core's progress stages, in words (unknown ones are shown as they come).
const STAGE_NAMES = {
  parse: 'Reading the STL',
  adjacency: 'Finding neighbouring triangles',
  orient: 'Making the winding consistent',
  geometry: 'Computing normals and areas',
  regions: 'Growing regions',
  planarise: 'Splitting regions into near-planar patches',
  patches: 'Measuring the patches',
  display: 'Preparing the display',
};

class Shell {
  /** Shared, read-only for tools: settings, model, segmentation, selected, hidden, memoryBytes. */
  state = {
    settings: {},
    model: null, // { name, source, report, triangleCount, vertexCount }
    segmentation: null, // { patchCount, threshold, thresholdKind, patches }
    selected: null,
    hovered: null,
    hidden: new Set(), // patch ids not drawn; -1 stands for the dropped triangles
    memoryBytes: null,
  };
  tools = [];
  activeTool = null;
  engine = null;
  viewer = null;
  patches = null;

  #queue = Promise.resolve();
  #queuedJobs = 0;
  #epoch = 0; // bumped by Cancel: jobs queued before it are dropped
  #progressTimer = 0;
  #engineReady = null;
  #loadGeneration = 0; // bumped by every load request: only the latest one is applied
  #loadAbort = null; // AbortController of the load in flight

  // ---------------------------------------------------------------- units and formatting

  unitOf = {
    length: () => this.state.settings.unit,
    area: () => `${this.state.settings.unit}²`,
    curvature: () => `1/${this.state.settings.unit}`,
    angle: () => (this.state.settings.angleUnit === 'deg' ? '°' : 'rad'),
  };

  /** Millimetres per file unit. */
  get mmPerUnit() {
    return MM_PER_UNIT[this.state.settings.unit] ?? 1;
  }

  angleText(rad, digits = 4) {
    return this.state.settings.angleUnit === 'deg' ? `${num((rad * 180) / Math.PI, digits)}°` : `${num(rad, digits)} rad`;
  }

  // ---------------------------------------------------------------- tools

  /** Registers a tool (before start()). */
  addTool(tool) {
    if (tool.settings) registerSettings(tool.settings);
    this.tools.push(tool);
  }

  tool(id) {
    return this.tools.find((t) => t.id === id) ?? null;
  }

  #mountTools() {
    const tabs = $('tool-tabs');
    for (const tool of this.tools) {
      const tab = document.createElement('button');
      tab.type = 'button';
      tab.setAttribute('role', 'tab');
      tab.id = `tab-${tool.id}`;
      tab.dataset.tool = tool.id;
      tab.textContent = tool.title;
      tab.setAttribute('aria-controls', `panel-${tool.id}`);
      tab.addEventListener('click', () => this.activate(tool.id));
      tabs.append(tab);
      const panel = document.createElement('section');
      panel.id = `panel-${tool.id}`;
      panel.className = 'tool-panel';
      panel.setAttribute('role', 'tabpanel');
      panel.dataset.tool = tool.id;
      panel.setAttribute('aria-labelledby', tab.id);
      $('tool-panels').append(panel);
      const results = document.createElement('div');
      results.id = `results-${tool.id}`;
      results.className = 'tool-result';
      results.dataset.tool = tool.id;
      $('tool-results').append(results);
      const overlay = document.createElement('div');
      overlay.id = `overlay-${tool.id}`;
      overlay.className = 'tool-overlay';
      overlay.hidden = true;
      $('view-legend').append(overlay);
      tool.mount(this, { panel, results, overlay });
    }
    tabs.addEventListener('keydown', (event) => {
      const i = this.tools.indexOf(this.activeTool);
      const step = { ArrowRight: 1, ArrowLeft: -1 }[event.key];
      if (!step) return;
      event.preventDefault();
      const next = this.tools[(i + step + this.tools.length) % this.tools.length];
      this.activate(next.id);
      $(`tab-${next.id}`).focus();
    });
  }

  /** Opens a tool's tab: its panel and results show, the others hide. */
  activate(id) {
    const tool = this.tool(id) ?? this.tools[0];
    if (tool === this.activeTool) return;
    this.activeTool?.onDeactivate?.();
    this.activeTool = tool;
    for (const t of this.tools) {
      const on = t === tool;
      const tab = $(`tab-${t.id}`);
      tab.setAttribute('aria-selected', String(on));
      tab.tabIndex = on ? 0 : -1;
      $(`panel-${t.id}`).hidden = !on;
      $(`results-${t.id}`).hidden = !on;
      $(`overlay-${t.id}`).dataset.active = String(on);
    }
    document.body.dataset.tool = tool.id;
    if (this.state.settings.tool !== tool.id) this.updateSettings({ tool: tool.id });
    tool.onActivate?.();
  }

  #notify(method, ...args) {
    for (const tool of this.tools) tool[method]?.(...args);
  }

  // ---------------------------------------------------------------- settings

  /** Merges `partial` into the settings and saves them (localStorage + URL hash). */
  updateSettings(partial) {
    Object.assign(this.state.settings, partial);
    persistSettings(this.state.settings);
  }

  // ---------------------------------------------------------------- jobs, busy state, progress

  setBusy(busy) {
    document.body.dataset.state = busy ? 'busy' : 'ready';
    document.body.setAttribute('aria-busy', String(busy));
  }

  get busy() {
    return this.#queuedJobs > 0;
  }

  showProgress(rawStage, fraction) {
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
    this.setStatus(`${stage}…`);
  }

  /**
   * Runs jobs one after another; `fn(progress, checkpoint)` may throw, errors land in the
   * alert (or `onError(error)` when given). `checkpoint()` throws CancelledError once Cancel
   * was pressed: jobs call it after awaiting anything that is not the engine (reading a
   * file), since only the engine stops by itself. Resolves when the job has run.
   */
  enqueue(label, fn, { onError } = {}) {
    const myEpoch = this.#epoch;
    const checkpoint = () => {
      if (this.#epoch !== myEpoch) throw new CancelledError();
    };
    this.#queuedJobs++;
    this.setBusy(true);
    const run = async () => {
      if (myEpoch !== this.#epoch) return;
      try {
        await this.#engineReady;
      } catch {
        return; // the engine never started; the alert says so
      }
      // Small jobs finish before the overlay would flash; show it only if the work lasts.
      clearTimeout(this.#progressTimer);
      this.#progressTimer = setTimeout(() => { $('progress').hidden = false; }, 150);
      this.showProgress(label, null);
      try {
        await fn((stage, fraction) => {
          if (this.#epoch === myEpoch) this.showProgress(stage, fraction);
        }, checkpoint);
        // A job is done when the view shows its result: a large model reaches WebGL in
        // chunks over a few frames (viewer.js).
        await this.viewer?.drawn();
      } catch (error) {
        if (error instanceof SupersededError) {
          // a later load replaced this one: its own job reports
        } else if (error instanceof CancelledError) {
          this.setStatus('Cancelled. The model on screen is unchanged.');
        } else if (onError) {
          onError(error);
        } else {
          this.showAlert(error.message);
          this.setStatus(this.state.model ? `Still showing ${this.state.model.name}.` : 'No model loaded.');
        }
      } finally {
        clearTimeout(this.#progressTimer);
        $('progress').hidden = true;
      }
    };
    this.#queue = this.#queue.then(run).finally(() => {
      this.#queuedJobs--;
      if (this.#queuedJobs === 0) this.setBusy(false);
    });
    return this.#queue;
  }

  cancelWork() {
    this.#epoch++;
    this.#loadAbort = null;
    this.engine.cancel(); // the worker restarts without the mesh; it is reloaded when needed
    this.#notify('onEngineLost');
  }

  setStatus(text) {
    $('status').textContent = text;
  }

  showAlert(message) {
    $('alert-box').hidden = false;
    $('alert').textContent = message;
  }

  hideAlert() {
    $('alert-box').hidden = true;
    $('alert').textContent = '';
  }

  // ---------------------------------------------------------------- loading

  /** Reads the first bytes to estimate the wasm memory a file needs; returns a refusal or null. */
  async #refusalForSize(file) {
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

  async #readSource(source, progress, signal) {
    // A file goes to the worker as it is: the engine reads it as a stream, never whole.
    if (source.kind === 'file') return { file: source.file };
    const response = await fetch(source.url, { signal });
    if (!response.ok) throw new Error(`The sample ${source.url} could not be loaded (HTTP ${response.status}).`);
    // Content-Length is only a hint for the bar: a compressing server sends fewer bytes.
    const total = Number(response.headers.get('Content-Length')) || 0;
    if (!total || !response.body) return { buffer: await response.arrayBuffer() };
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
    return { buffer: await new Blob(chunks).arrayBuffer() };
  }

  /** Params of the tools that work right after parsing ({ segment: … }). */
  #openParams() {
    const out = {};
    for (const tool of this.tools) {
      const params = tool.openParams?.();
      if (params) out[tool.id] = params;
    }
    return out;
  }

  /**
   * Claims the next load generation: a load applies its result only while it is still the
   * latest request, and a newer request stops the older one's download or worker work.
   */
  #claimLoad() {
    const generation = ++this.#loadGeneration;
    this.#loadAbort?.abort(new SupersededError());
    const controller = new AbortController();
    this.#loadAbort = controller;
    return { generation, signal: controller.signal };
  }

  /** True when a user file or sample was asked for since the page opened. */
  get loadRequested() {
    return this.#loadGeneration > 0;
  }

  /** Opens a file or sample: parse (+ segment) in the worker; the old model stays on failure. */
  #openSource(source, name, { generation, signal }) {
    const stale = () => {
      if (generation !== this.#loadGeneration) throw new SupersededError();
    };
    return this.enqueue(`Opening ${name}`, async (progress, checkpoint) => {
      stale();
      this.hideAlert();
      let input;
      try {
        input = await this.#readSource(source, progress, signal);
      } catch (error) {
        stale();
        throw error;
      }
      stale();
      checkpoint();
      let result;
      try {
        result = await this.engine.open(input, name, this.#openParams(), progress, signal);
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        stale();
        throw new Error(`Could not open "${name}": ${error.message}`);
      }
      stale();
      this.#loadAbort = null;
      this.state.model = { name, source, report: result.report, triangleCount: result.triangleCount, vertexCount: result.vertexCount };
      this.state.settings.sample = source.kind === 'sample' ? source.id : '';
      let upNote = '';
      if (source.kind === 'file') {
        const up = guessUpAxis(result.report);
        if (up !== this.state.settings.up) this.setUpAxis(up);
        upNote = ` Shown ${up.toUpperCase()} up (its thinnest direction); U switches.`;
      }
      persistSettings(this.state.settings);
      this.#renderModel();
      progress('Drawing', null);
      this.state.memoryBytes = result.memoryBytes;
      this.viewer.setModel(result.display, { keepView: false });
      this.#notify('onModelLoaded', this.state.model, result);
      const seg = result.tools.segment;
      this.setSegmentation(seg?.segmentation ?? null, { redraw: false });
      const seconds = (ms) => `${num(ms / 1000, 2)} s`;
      this.setStatus(`Opened ${name} in ${seconds(result.timings.parseMs)}` +
        (seg?.segmentation ? `; ${seg.segmentation.patchCount} patches in ${seconds(seg.segmentMs)}.` : '.') + upNote);
    });
  }

  /** Opens a user's file; it wins over the sample and over any earlier file still loading. */
  async openFile(file) {
    if (!file) return;
    const claim = this.#claimLoad();
    this.setBusy(true); // at once, so that waiting on "ready" never sees a stale state
    const refusal = await this.#refusalForSize(file);
    if (claim.generation !== this.#loadGeneration) return;
    if (refusal) {
      this.showAlert(refusal);
      if (!this.busy) this.setBusy(false);
      return;
    }
    await this.#openSource({ kind: 'file', file }, file.name, claim);
  }

  /**
   * Opens a built-in sample. `initial` marks the page's own choice on start: it is skipped
   * when the user has already asked for a file.
   */
  openSample(id, { applyDisplay = true, initial = false } = {}) {
    if (initial && this.loadRequested) return Promise.resolve();
    const sample = SAMPLES.find((s) => s.id === id) ?? SAMPLES[0];
    const claim = this.#claimLoad();
    this.setBusy(true);
    if (applyDisplay) {
      // The samples' axes and units are known (see samples/LICENSES.md).
      this.state.settings.up = sample.up;
      this.state.settings.unit = sample.unit;
      this.#renderDisplaySettings();
      this.viewer.setUpAxis(sample.up);
      this.refreshUnits();
    }
    return this.#openSource({ kind: 'sample', id: sample.id, url: `./samples/${sample.file}` }, sample.file, claim);
  }

  /**
   * After Cancel or an engine failure the worker is new and empty: give it the model on
   * screen again, with the segmentation tool's params (same input, same patch ids).
   */
  async restoreEngine(progress, checkpoint) {
    if (this.engine.hasMesh || !this.state.model) return;
    const input = await this.#readSource(this.state.model.source, progress);
    checkpoint();
    const result = await this.engine.open(input, this.state.model.name, this.#openParams(), progress);
    const segmentError = result.tools.segment?.segmentError;
    if (segmentError) throw new Error(segmentError);
    return result;
  }

  // ---------------------------------------------------------------- model, units

  #renderModel() {
    const { report, name } = this.state.model;
    $('model-name').textContent = name;
    $('stat-triangles').textContent = integer.format(report.triangles);
    $('stat-vertices').textContent = integer.format(report.vertices);
    $('stat-format').textContent = report.format === 'ascii' ? 'ASCII STL' : 'binary STL';
    renderWarnings(report);
    this.refreshUnits();
    document.body.dataset.model = name;
  }

  #renderDisplaySettings() {
    const s = this.state.settings;
    $('unit-select').value = s.unit;
    $('angle-unit-select').value = s.angleUnit;
    $('up-select').value = s.up;
  }

  /** Everything on the page that shows a length, area or angle, in the current units. */
  refreshUnits({ unitChanged = false } = {}) {
    for (const el of document.querySelectorAll('[data-unit]')) {
      const f = this.unitOf[el.dataset.unit];
      if (f) el.textContent = f();
    }
    if (this.state.model) {
      const { bboxMin, bboxMax, area } = this.state.model.report;
      const u = this.state.settings.unit;
      $('stat-size').textContent = `${[0, 1, 2].map((i) => num(bboxMax[i] - bboxMin[i])).join(' × ')} ${u}`;
      $('stat-area').textContent = `${num(area)} ${u}²`;
      $('stat-memory').textContent = this.state.memoryBytes ? bytesText(this.state.memoryBytes) : '–';
    }
    this.#renderUnitNotice();
    this.patches?.render();
    this.#notify('onUnitsChanged', { unitChanged });
  }

  /** Suggests the likely unit when the model's size in the chosen one is implausible. */
  #renderUnitNotice() {
    const box = $('unit-notice');
    const hint = this.state.model ? unitSuggestion(this.state.model.report, this.state.settings.unit) : null;
    box.hidden = !hint;
    document.body.dataset.unitSuggestion = hint?.suggested ?? '';
    if (!hint) return;
    const u = hint.unit;
    const text = `This part would be ${metresText(hint.size)} long in ${UNIT_NAMES[u]}` +
      (hint.tooLarge ? ', larger than any aircraft part' : ', smaller than any aircraft part');
    const button = $('unit-suggest-button');
    if (hint.suggested) {
      $('unit-notice-text').textContent = `${text}. Is the file in ${UNIT_NAMES[hint.suggested]} ` +
        `(${metresText(hint.suggestedSize)} long)?`;
      button.hidden = false;
      button.textContent = `Use ${hint.suggested}`;
      button.dataset.unit = hint.suggested;
    } else {
      $('unit-notice-text').textContent = `${text}; check the file's unit.`;
      button.hidden = true;
    }
  }

  setUnit(unit) {
    this.#notify('onBeforeUnitsChange');
    this.state.settings.unit = unit;
    $('unit-select').value = unit;
    persistSettings(this.state.settings);
    this.refreshUnits({ unitChanged: true });
  }

  setUpAxis(axis) {
    this.state.settings.up = axis;
    $('up-select').value = axis;
    persistSettings(this.state.settings);
    this.viewer.setUpAxis(axis);
  }

  // ---------------------------------------------------------------- patches and selection

  /**
   * Shows a new segmentation (null = none). `display` (from the worker) redraws the model;
   * without it the caller has drawn already.
   */
  setSegmentation(segmentation, { display = null, keepView = true, memoryBytes = null, redraw = true } = {}) {
    this.state.segmentation = segmentation;
    this.state.selected = null;
    this.state.hovered = null;
    this.state.hidden = $('show-dropped').checked ? new Set() : new Set([-1]);
    if (memoryBytes) this.state.memoryBytes = memoryBytes;
    $('hover-tip').hidden = true;
    if (redraw && display) this.viewer.setModel(display, { keepView });
    this.syncViewer();
    $('stat-memory').textContent = this.state.memoryBytes ? bytesText(this.state.memoryBytes) : '–';
    this.patches.render();
    document.body.dataset.patches = String(segmentation?.patchCount ?? 0);
    document.body.dataset.segmentations = String(Number(document.body.dataset.segmentations ?? 0) + 1);
    this.#notify('onSegmentation', segmentation);
    this.#notify('onSelectionChanged', null);
  }

  /** Shows the engine's memory after a tool's request (result.memoryBytes). */
  showMemory(bytes) {
    if (!bytes) return;
    this.state.memoryBytes = bytes;
    $('stat-memory').textContent = bytesText(bytes);
  }

  patch(id) {
    return this.state.segmentation?.patches.find((p) => p.id === id) ?? null;
  }

  /** Applies selection, hover and visibility to the viewer without a rebuild. */
  syncViewer() {
    this.viewer.setPatchState({
      hidden: this.state.hidden,
      selected: this.state.selected,
      hovered: this.state.hovered,
      showBorders: $('show-borders').checked,
    });
  }

  /** Selects a patch (null clears); every tool hears of it. */
  select(id, options = {}) {
    if (id !== null && !this.patch(id)) id = null;
    this.state.selected = id;
    this.patches.markSelected(id, options);
    this.syncViewer();
    this.#notify('onSelectionChanged', id);
    if (id !== null) {
      const p = this.patch(id);
      this.setStatus(`Patch ${id}: ${integer.format(p.triangleCount)} triangles, ${num(p.area)} ${this.unitOf.area()}, ` +
        `max. deviation ${this.angleText(p.maxDeviation, 3)}.`);
    }
  }

  setHidden(hidden) {
    this.state.hidden = hidden;
    $('show-dropped').checked = !hidden.has(-1);
    this.patches.markHidden(hidden);
    this.syncViewer();
  }

  toggleHidden(id) {
    const hidden = new Set(this.state.hidden);
    if (hidden.has(id)) hidden.delete(id);
    else hidden.add(id);
    this.setHidden(hidden);
  }

  /** Shows only `id` (dropped triangles too are hidden); isolating it again shows everything. */
  isolate(id) {
    const all = this.state.segmentation.patches.map((p) => p.id);
    const alone = !this.state.hidden.has(id) && all.every((x) => x === id || this.state.hidden.has(x));
    this.setHidden(alone ? new Set() : new Set([-1, ...all.filter((x) => x !== id)]));
  }

  // ---------------------------------------------------------------- events

  /** File input, drop and samples work from the first moment, before the engine is up. */
  #wireLoading() {
    const fileInput = $('file-input');
    $('open-button').addEventListener('click', () => fileInput.click());
    fileInput.addEventListener('change', () => {
      const file = fileInput.files[0];
      this.openFile(file).finally(() => { fileInput.value = ''; });
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
      this.openFile(file);
      if (files.length > 1) this.setStatus(`Opening ${file.name}; one file at a time, the others were ignored.`);
    });

    const list = $('samples-list');
    for (const sample of SAMPLES) {
      const button = document.createElement('button');
      button.type = 'button';
      button.dataset.sample = sample.id;
      button.innerHTML = '<span></span><span class="sample-meta"></span>';
      button.firstChild.textContent = sample.name;
      button.lastChild.textContent = sample.meta;
      button.addEventListener('click', () => {
        $('samples-menu').open = false;
        $('samples-menu').querySelector('summary').focus(); // the clicked item is hidden now
        this.openSample(sample.id);
      });
      list.append(button);
    }
  }

  #wireEvents() {
    // Close menus on outside click or Escape, like native menus.
    document.addEventListener('click', (event) => {
      for (const menu of document.querySelectorAll('details.menu[open]')) {
        if (!menu.contains(event.target)) menu.open = false;
      }
    });
    $('unit-select').addEventListener('change', (event) => this.setUnit(event.target.value));
    $('unit-suggest-button').addEventListener('click', (event) => {
      const unit = event.currentTarget.dataset.unit;
      this.setUnit(unit);
      this.setStatus(`File unit set to ${UNIT_NAMES[unit]}.`);
    });
    $('angle-unit-select').addEventListener('change', (event) => {
      this.#notify('onBeforeUnitsChange');
      this.state.settings.angleUnit = event.target.value;
      persistSettings(this.state.settings);
      this.refreshUnits();
    });
    $('up-select').addEventListener('change', (event) => this.setUpAxis(event.target.value));

    for (const button of document.querySelectorAll('.view-toolbar [data-view]')) {
      button.addEventListener('click', () => this.viewer.setView(button.dataset.view));
    }
    this.viewer.setRayPicker((origin, direction, hidden, options) => this.#pick(origin, direction, hidden, options));
    this.viewer.addEventListener('modellost', () => this.#redraw());
    this.viewer.addEventListener('hover', (event) => this.#onHover(event.detail));
    this.viewer.addEventListener('pick', (event) => {
      const id = event.detail.patchId;
      this.select(id !== null && id >= 0 ? id : null);
    });

    $('cancel-button').addEventListener('click', () => this.cancelWork());
    $('alert-dismiss').addEventListener('click', () => this.hideAlert());
    document.addEventListener('keydown', (event) => this.#onShortcut(event));
    window.addEventListener('hashchange', () => this.#onHashChange());
  }

  /**
   * Asks the worker which patch a ray (model coordinates) hits first, passing through
   * `hidden` patches: { patchId, point } or null. The request queues behind running work (a
   * click waits for its answer). While the worker has no mesh (a file loading) it is a miss;
   * after Cancel, a click (not a hover) first gives the new worker the model on screen again.
   * A failure only costs the pick.
   */
  async #pick(origin, direction, hidden, { click }) {
    const ask = () => this.engine.request('pick', { origin, direction, hidden });
    try {
      if (this.engine?.hasMesh) return await ask();
      if (!click || !this.state.model || this.busy) return null;
      let hit = null;
      await this.enqueue('Preparing the model for picking', async (progress, checkpoint) => {
        await this.restoreEngine(progress, checkpoint);
        hit = await ask();
      });
      return hit;
    } catch {
      return null;
    }
  }

  /** The view lost its WebGL context and with it the model: the worker sends it again. */
  #redraw() {
    if (!this.state.model) return;
    this.enqueue('Drawing the model again', async (progress, checkpoint) => {
      await this.restoreEngine(progress, checkpoint);
      const display = await this.engine.request('display', {}, { onProgress: progress });
      checkpoint();
      this.viewer.setModel(display, { keepView: true });
      this.syncViewer();
    });
  }

  #onHover({ patchId, clientX, clientY }) {
    const tip = $('hover-tip');
    const id = patchId ?? null;
    if (id !== this.state.hovered) {
      this.state.hovered = id;
      this.syncViewer();
    }
    if (id === null || !this.state.segmentation) {
      tip.hidden = true;
      return;
    }
    const rect = $('viewport').getBoundingClientRect();
    tip.style.left = `${clientX - rect.left}px`;
    tip.style.top = `${clientY - rect.top}px`;
    if (id < 0) {
      tip.textContent = 'Dropped: region below the minimum patch area';
    } else {
      const p = this.patch(id);
      tip.textContent = `Patch ${id}: ${num(p.area)} ${this.unitOf.area()}, ${integer.format(p.triangleCount)} triangles`;
    }
    tip.hidden = false;
  }

  #onShortcut(event) {
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    const target = event.target;
    if (target.closest('input, select, textarea, [contenteditable="true"]')) return;
    if (event.key === 'Escape') {
      for (const menu of document.querySelectorAll('details.menu[open]')) menu.open = false;
      if (this.state.selected !== null) this.select(null);
      return;
    }
    // Buttons and rows keep Enter and Space; letters and digits are free everywhere else.
    const views = { f: 'fit', 1: 'top', 2: 'front', 3: 'side', 4: 'iso' };
    const key = event.key.toLowerCase();
    const selected = this.state.selected;
    if (views[key]) this.viewer.setView(views[key]);
    else if (key === 'o') $('file-input').click();
    else if (key === 'u') this.setUpAxis(this.state.settings.up === 'z' ? 'y' : 'z');
    else if (key === 'a' && this.state.segmentation) this.setHidden(new Set());
    else if (key === 'h' && selected !== null) this.toggleHidden(selected);
    else if (key === 'i' && selected !== null) this.isolate(selected);
    else return;
    event.preventDefault();
  }

  #onHashChange() {
    const fromHash = settingsFromHash(location.hash);
    const previous = { ...this.state.settings };
    Object.assign(this.state.settings, fromHash);
    this.#renderDisplaySettings();
    if (this.state.settings.up !== previous.up) this.viewer.setUpAxis(this.state.settings.up);
    this.refreshUnits();
    if (fromHash.tool) this.activate(fromHash.tool);
    if (fromHash.sample && fromHash.sample !== (this.state.model?.source.id ?? '')) {
      this.openSample(fromHash.sample, { applyDisplay: !('up' in fromHash) });
    } else {
      this.#notify('onSettingsChanged');
    }
  }

  // ---------------------------------------------------------------- start

  async start() {
    const fromHash = settingsFromHash(location.hash);
    const stored = sanitize(loadStoredSettings());
    this.state.settings = { ...allDefaults(), ...stored, ...fromHash };
    let engineStarted;
    this.#engineReady = new Promise((resolve, reject) => { engineStarted = { resolve, reject }; });
    this.#engineReady.catch(() => {});
    try {
      this.viewer = new Viewer($('viewer'));
    } catch {
      this.showAlert('This browser could not start WebGL, which the 3D view needs. Enable hardware acceleration or try another browser.');
      document.body.dataset.state = 'failed';
      return;
    }
    this.engine = new Engine();
    this.patches = new PatchList(this);
    this.viewer.setUpAxis(this.state.settings.up);
    this.#renderDisplaySettings();
    // A file chosen or dropped while the engine starts is queued, never lost.
    this.#wireLoading();
    this.#mountTools();
    this.activate(this.state.settings.tool);
    this.#wireEvents();
    this.refreshUnits();
    try {
      await this.engine.start();
      engineStarted.resolve();
    } catch (error) {
      engineStarted.reject(error);
      this.showAlert(`The processing engine could not start: ${error.message}`);
      document.body.dataset.state = 'failed';
      this.setStatus('Not ready.');
      return;
    }
    this.#notify('onEngineReady');
    if (!this.busy) this.setBusy(false);
    this.setStatus('Ready.');
    // First visit: open the default sample. A shared link or a later visit reopens its sample
    // with the settings it carries (the link's axis and unit win over the sample's own).
    const sample = this.state.settings.sample || allDefaults().sample;
    const linkSetsDisplay = 'up' in fromHash || 'unit' in fromHash;
    const storedForThisSample = stored.sample === sample; // keep what the user chose for it
    await this.openSample(sample, { applyDisplay: !linkSetsDisplay && !storedForThisSample, initial: true });
  }
}

/**
 * Files come Y-up or Z-up. An aircraft is flattest along its up axis, so the smaller of the
 * y and z extents of the bounding box is taken as up (no paper; right for all sample meshes).
 */
function guessUpAxis({ bboxMin, bboxMax }) {
  return bboxMax[2] - bboxMin[2] < bboxMax[1] - bboxMin[1] ? 'z' : 'y';
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

/** The one shell of the page. */
export const shell = new Shell();
