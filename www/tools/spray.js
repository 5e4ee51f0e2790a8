// Spray tool (seed 002): plans the gun trajectory over a patch (or the whole mesh), predicts
// the coating thickness, searches the widest pass spacing that meets the quality limits,
// optimises the gun speed along the passes, draws the path (by kind or by speed), the thickness
// heat map with its worst regions, and exports CSV, JSON, ABB RAPID and KUKA KRL.
// Process values are typed in a painter's units (mm, mm/s, cm³/min, °, µm) whatever the
// file's unit; they are converted here, and the worker (worker/spray.js) gets file units.
// The form and result templates are in spray-form.js, the words for figures in
// spray-text.js, the spacing chart in spray-chart.js.
import { CancelledError } from '../app/engine.js';
import { download, fileStem } from '../app/download.js';
import { fieldText, integer, num } from '../app/format.js';
import { persistSettings } from '../app/settings.js';
import { cellOptions, mountCell, renderCell } from '../app/cell.js';
import { TURBO, VIRIDIS, gradient, hexRgb, turboInto, viridisInto } from '../app/colours.js';
import { renderChart } from './spray-chart.js';
import { DEFAULTS, DIRECTIONS, FIELDS, FLAGS, P, PANEL, RESULTS } from './spray-form.js';
import {
  boxDiagonal, coarseWarning, directionText, plannerNotes, shortDirection, speedRangeText, timeText,
} from './spray-text.js';

/** Trajectory point kinds (SprayPlan.pointKinds) and their colours on the path. */
const KINDS = [
  { name: 'pass', label: 'Pass (gun on)', color: '#1d232a' },
  { name: 'straight', label: 'Straight transition', color: '#E69F00' },
  { name: 'arc', label: 'Arc over a fold', color: '#CC79A7' },
  { name: 'extension', label: 'Extension past the edge', color: '#56B4E9' },
  { name: 'link', label: 'Link (gun off)', color: '#6b7480', dashed: true },
];
const EXTENSION = 3; // kinds 0–3 have the gun on
const LINK = 4;
/** Thickness classes against target ± tolerance (Okabe & Ito colours). */
const CLASSES = [
  { name: 'under', label: 'Under', color: '#0072B2' },
  { name: 'in', label: 'In tolerance', color: '#009E73' },
  { name: 'over', label: 'Over', color: '#D55E00' },
];
/** Worst regions on the map: ring colour, and the one the pointer is on in the list. */
const HOTSPOT_COLOR = '#ff2d95';
const HOTSPOT_HIGHLIGHT = '#ffffff';
/** Segments per ring of a worst-region marker. */
const RING_SEGMENTS = 48;
/** Words for SprayHotspot.cause. */
const CAUSES = {
  edge: 'at the patch edge', fold: 'at a fold', curvature: 'on a tightly curved part', spacing: 'between passes',
};
/** About this many evaluation points at most: beyond, the worker coarsens the resolution. */
const MAX_SAMPLES = 100_000;
/** About this many deposition time steps at most (see #coreParams). */
const MAX_TIME_SAMPLES = 1_500_000;
/** Plans with more passes open with the path hidden (their lines would cover the heat map). */
const MAX_PASSES_SHOWN = 120;
/** At most this many gun-axis ticks are drawn. */
const MAX_TICKS = 1500;

const $ = (id) => document.getElementById(id);

class SprayTool {
  id = 'spray';
  title = 'Spray';
  settings = {
    order: 2,
    defaults: DEFAULTS,
    allowed: {
      [`${P}colors`]: ['thickness', 'classes'], [`${P}scope`]: ['patch', 'mesh'], [`${P}direction`]: DIRECTIONS.map((d) => d.value),
    },
    hashKeys: () => Object.keys(DEFAULTS),
  };

  #shell;
  #form;
  #results;
  #overlay;
  #plan = null; // { result, params, request, patchId, unit } of the plan on screen
  #target = null; // patch id the next plan sprays (selection, else the largest patch)

  mount(shell, { panel, results, overlay }) {
    this.#shell = shell;
    panel.innerHTML = PANEL;
    panel.setAttribute('aria-labelledby', 'spray-heading');
    results.innerHTML = RESULTS;
    mountCell(results, () => shell.state.settings);
    this.#results = results;
    this.#overlay = overlay;
    this.#form = panel.querySelector('#spray-form');
    this.#wire();
    this.#renderForm();
  }

  get #s() {
    return this.#shell.state.settings;
  }

  // ---------------------------------------------------------------- form

  #renderForm() {
    const s = this.#s;
    for (const f of FIELDS) {
      const el = $(`spray-${f.key}`);
      el.value = fieldText(s[P + f.key], 8);
    }
    for (const f of FLAGS) $(`spray-${f.key}`).checked = s[P + f.key];
    for (const radio of this.#form.elements.scope) radio.checked = radio.value === s[`${P}scope`];
    $('spray-colors').value = s[`${P}colors`];
    $('spray-direction').value = s[`${P}direction`];
    this.#validate();
  }

  /** Reads the form: { values } in the painter's units, or { error } with bad fields marked. */
  #read() {
    const values = {};
    let error = null;
    const direction = $('spray-direction').value || 'principal';
    // The typed angle counts only when chosen (it stays on screen, greyed, otherwise).
    $('spray-rasterAngle').disabled = direction !== 'typed';
    for (const f of FIELDS) {
      const el = $(`spray-${f.key}`);
      const v = el.value.trim() === '' ? NaN : Number(el.value);
      let problem = null;
      if (el.disabled) {
        el.setAttribute('aria-invalid', 'false');
        if (Number.isFinite(v) && v >= f.min && v <= f.max) values[f.key] = v;
        continue;
      }
      if (!Number.isFinite(v)) problem = `Enter a number for the ${f.label.toLowerCase()}.`;
      else if (f.key === 'rasterAngle' ? v < f.min || v > f.max : v <= f.min || (f.max !== undefined && v > f.max)) {
        problem = f.key === 'rasterAngle'
          ? `The pass direction turn must be between ${f.min}° and ${f.max}°.`
          : `The ${f.label.toLowerCase()} must be above ${f.min}${f.max !== undefined ? ` and at most ${f.max}` : ''} ${f.unit}.`;
      }
      if (f.key === 'coneAngle' && v >= 180) problem = 'The cone angle must be below 180°.';
      el.setAttribute('aria-invalid', String(Boolean(problem)));
      if (problem) error ??= problem.replace(/ +\./, '.');
      else values[f.key] = v;
    }
    // The gun speed limits against each other and the nominal speed (the core refuses the
    // same, naming minSpeed and maxSpeed; here it is said next to the fields).
    let speedError = null;
    const { speed, minSpeed, maxSpeed } = values;
    if (speed !== undefined && minSpeed !== undefined && maxSpeed !== undefined) {
      const mark = (...keys) => keys.forEach((k) => $(`spray-${k}`).setAttribute('aria-invalid', 'true'));
      if (minSpeed > maxSpeed) {
        speedError = `The slowest gun speed (${num(minSpeed, 4)} mm/s) must not exceed the fastest (${num(maxSpeed, 4)} mm/s).`;
        mark('minSpeed', 'maxSpeed');
      } else if (speed < minSpeed || speed > maxSpeed) {
        speedError = `The nominal gun speed v (${num(speed, 4)} mm/s) must lie between the slowest and the fastest, ` +
          `${num(minSpeed, 4)}–${num(maxSpeed, 4)} mm/s.`;
        mark('speed', speed < minSpeed ? 'minSpeed' : 'maxSpeed');
      }
    }
    for (const f of FLAGS) values[f.key] = $(`spray-${f.key}`).checked;
    values.scope = this.#form.elements.scope.value || 'patch';
    values.colors = $('spray-colors').value;
    values.direction = direction;
    const out = { values };
    if (error) out.error = error;
    if (speedError) out.speedError = speedError;
    return out;
  }

  #validate() {
    const result = this.#read();
    const noTarget = result.values.scope === 'patch' && this.#target === null;
    $('spray-error').textContent = result.error ?? '';
    $('spray-speed-error').textContent = result.speedError ?? '';
    $('spray-plan-button').disabled = Boolean(result.error || result.speedError) || !this.#shell.state.model || noTarget;
    return result;
  }

  #save() {
    const { values } = this.#read();
    for (const [k, v] of Object.entries(values)) {
      if (`${P}${k}` in DEFAULTS) this.#s[P + k] = v;
    }
    persistSettings(this.#s);
  }

  /**
   * The core's parameter object, in the file's units: lengths / mmPerUnit, flow cm³/min →
   * (file unit)³/s, angles in rad, thicknesses µm → file unit.
   */
  #coreParams(v, areaFileUnits) {
    const mm = this.#shell.mmPerUnit;
    const rad = (deg) => (deg * Math.PI) / 180;
    const turn = v.direction === 'typed' ? v.rasterAngle : DIRECTIONS.find((d) => d.value === v.direction)?.degrees ?? 0;
    const params = {
      spacing: v.spacing / mm,
      standoff: v.standoff / mm,
      speed: v.speed / mm,
      minSpeed: v.minSpeed / mm,
      maxSpeed: v.maxSpeed / mm,
      optimiseSpeed: v.optimiseSpeed,
      bestDirection: v.direction === 'best',
      flowRate: (v.flowRate * 1000) / 60 / mm ** 3,
      coneAngle: rad(v.coneAngle),
      transitionAngle: rad(v.transitionAngle),
      efficiency: v.efficiency,
      rasterAngle: rad(turn),
    };
    if (v.search) params.quality = { maxStdDev: v.maxStdDev / 1000 / mm, maxError: v.maxError / 100 };
    if (v.scaleSpeed) params.targetThickness = v.target / 1000 / mm;
    // The core's default time step moves the gun R/20 a step; on very large patches a longer
    // step keeps the deposition within MAX_TIME_SAMPLES at the narrowest spacing searched
    // (R/4, the core's default lower bound).
    const radius = params.standoff * Math.tan(params.coneAngle / 2);
    const narrowest = v.search ? Math.min(radius / 4, params.spacing) : params.spacing;
    const step = Math.max(radius / 20, areaFileUnits / narrowest / MAX_TIME_SAMPLES);
    if (step > radius / 20) params.timeStep = step / params.speed;
    return params;
  }

  // ---------------------------------------------------------------- target patch

  #chooseTarget() {
    const { segmentation, selected } = this.#shell.state;
    const patches = segmentation?.patches ?? [];
    if (selected !== null) this.#target = selected;
    else if (patches.length) this.#target = patches.reduce((a, b) => (b.area > a.area ? b : a)).id;
    else this.#target = null;
    this.#renderTarget();
  }

  #renderTarget() {
    const shell = this.#shell;
    const label = $('spray-patch-label');
    const hint = $('spray-scope-hint');
    if (this.#target === null) {
      label.textContent = 'a patch (none yet)';
      hint.textContent = shell.state.segmentation ? 'No patch was kept: plan on the whole mesh, or segment again.' : 'Segment the model, or plan on the whole mesh.';
    } else {
      const p = shell.patch(this.#target);
      const largest = shell.state.selected === null;
      label.textContent = `patch ${this.#target}${largest ? ' (the largest)' : ''} · ${num(p.area, 3)} ${shell.unitOf.area()}`;
      hint.textContent = 'Click a patch in the view or the list to choose another.';
    }
    this.#validate();
  }

  // ---------------------------------------------------------------- shell hooks

  onModelLoaded() {
    this.#clearPlan();
  }

  onSegmentation() {
    this.#clearPlan(); // patch ids may have changed
    this.#chooseTarget();
  }

  onSelectionChanged() {
    this.#chooseTarget();
  }

  onUnitsChanged({ unitChanged }) {
    if (unitChanged && this.#plan) this.#clearPlan('The file unit changed: plan again.');
    else if (this.#plan) this.#renderResults();
    if (this.#shell.state.model) this.#renderTarget();
  }

  onSettingsChanged() {
    renderCell(this.#s);
    this.#renderForm();
  }

  onActivate() {
    this.#showLayers(true);
    this.#validate();
  }

  onDeactivate() {
    this.#showLayers(false);
  }

  onEngineLost() {
    // The plan stays on screen; exports re-plan with the same input when the worker lost it.
  }

  // ---------------------------------------------------------------- planning

  #planRequest() {
    const read = this.#validate();
    if (read.error || read.speedError) return null;
    const shell = this.#shell;
    const v = read.values;
    const patchId = v.scope === 'patch' ? this.#target : null;
    if (v.scope === 'patch' && patchId === null) return null;
    const area = patchId === null ? shell.state.model.report.area : shell.patch(patchId).area;
    return { values: v, patchId, params: this.#coreParams(v, area) };
  }

  plan() {
    const shell = this.#shell;
    const request = this.#planRequest();
    if (!request) return;
    this.#save();
    const what = request.patchId === null ? 'the whole mesh' : `patch ${request.patchId}`;
    shell.enqueue(`Planning the spray on ${what}`, async (progress, checkpoint) => {
      shell.hideAlert();
      let result;
      try {
        await shell.restoreEngine(progress, checkpoint);
        result = await shell.engine.request('spray.plan',
          { params: request.params, patchId: request.patchId, sampleBudget: MAX_SAMPLES }, { onProgress: progress });
      } catch (error) {
        if (error instanceof CancelledError) throw error;
        throw new Error(`The spray plan failed: ${error.message.replace(/\.?$/, '.')} ${this.#plan ? 'The plan on screen is unchanged.' : ''}`.trim());
      }
      progress('Drawing', null);
      shell.showMemory(result.memoryBytes);
      // Hundreds of passes would hide the heat map under their lines: start with the path
      // off then (for this plan only; the saved setting is the user's).
      if (result.passCount > MAX_PASSES_SHOWN) $('spray-showPath').checked = false;
      // Optimised speeds are the news of the plan: the path opens coloured by them.
      $('spray-pathColors').value = result.speedOptimised ? 'speed' : 'kind';
      // Exports re-plan with exactly these parameters when the worker lost the plan.
      request.params = { ...request.params, resolution: result.resolution };
      this.#plan = { result, request, unit: shell.state.settings.unit, model: shell.state.model.name };
      this.#sprayedDiagonal = null;
      this.#drawLayers();
      this.#renderResults();
      // Look at the sprayed side: a patch under a wing is otherwise out of sight.
      if (request.patchId !== null && shell.patch(request.patchId)) shell.viewer.fitPatch(request.patchId, shell.patch(request.patchId).normal);
      document.body.dataset.sprayPlans = String(Number(document.body.dataset.sprayPlans ?? 0) + 1);
      shell.setStatus(`Spray on ${what}: ${result.passCount} passes at ${num(result.spacing * shell.mmPerUnit, 3)} mm, ` +
        `planned in ${num(result.timings.planMs / 1000, 2)} s.`);
    });
  }

  #clearPlan(message) {
    this.#plan = null;
    for (const layer of ['path', 'links', 'axis', 'heat', 'hotspots']) this.#shell.viewer?.removeLayer(`spray.${layer}`);
    if (this.#results) {
      $('spray-figures').hidden = true;
      $('spray-summary').textContent = message ?? 'No plan yet: choose a patch and press Plan spray.';
      for (const b of this.#results.querySelectorAll('[data-format]')) b.disabled = true;
      this.#overlay.replaceChildren();
      this.#overlay.hidden = true;
    }
    if (this.#shell.engine?.started) this.#shell.engine.request('spray.drop').catch(() => {});
  }

  // ---------------------------------------------------------------- drawing

  /** µm per file unit of thickness. */
  get #umPerUnit() {
    return this.#shell.mmPerUnit * 1000;
  }

  #drawLayers() {
    const viewer = this.#shell.viewer;
    const { result, request } = this.#plan;
    const { trajectory, kinds } = result;
    const n = kinds.length;
    this.#drawPath();
    // Gun axis: from the gun along the axis, one standoff long (ends on the surface).
    const every = Math.max(1, Math.ceil(n / MAX_TICKS));
    const ticks = [];
    const h = request.params.standoff;
    for (let i = 0; i < n; i += every) {
      if (kinds[i] === LINK) continue;
      const o = 6 * i;
      ticks.push(trajectory[o], trajectory[o + 1], trajectory[o + 2],
        trajectory[o] + h * trajectory[o + 3], trajectory[o + 1] + h * trajectory[o + 4], trajectory[o + 2] + h * trajectory[o + 5]);
    }
    viewer.setLayer('spray.axis', { kind: 'lines', positions: Float32Array.from(ticks), color: '#8a6d00' });
    this.#drawHeat();
    this.#drawHotspots(null);
    this.#showLayers(this.#shell.activeTool === this);
  }

  /** Speed range of the colour scale, file unit/s: the commanded one (a point when uniform). */
  #speedRange() {
    const { result } = this.#plan;
    return { lo: result.minSpeed, hi: result.maxSpeed };
  }

  /**
   * The path's gun-on moves coloured by kind or by speed, the links grey and dashed.
   * Segments between consecutive points take the kind and speed of the point they move to
   * (as a robot move does): moves to link points have the gun off.
   */
  #drawPath() {
    const viewer = this.#shell.viewer;
    const { result, request } = this.#plan;
    const { trajectory, kinds, speeds } = result;
    const n = kinds.length;
    const bySpeed = $('spray-pathColors').value === 'speed' && speeds.length === n;
    const { lo, hi } = this.#speedRange();
    const rgbSpeed = [0, 0, 0];
    let on = 0;
    let off = 0;
    const isOff = (i) => !(kinds[i + 1] <= EXTENSION);
    for (let i = 0; i + 1 < n; i++) (isOff(i) ? off++ : on++);
    const pathPos = new Float32Array(6 * on);
    const pathCol = new Uint8Array(6 * on);
    const linkPos = new Float32Array(6 * off);
    const rgb = KINDS.map((k) => hexRgb(k.color));
    for (let i = 0, a = 0, b = 0; i + 1 < n; i++) {
      const p = [trajectory[6 * i], trajectory[6 * i + 1], trajectory[6 * i + 2],
        trajectory[6 * i + 6], trajectory[6 * i + 7], trajectory[6 * i + 8]];
      if (isOff(i)) {
        linkPos.set(p, 6 * b++);
      } else {
        pathPos.set(p, 6 * a);
        let c = rgb[kinds[i + 1]] ?? rgb[0];
        if (bySpeed) {
          turboInto(hi > lo * (1 + 1e-9) ? (speeds[i + 1] - lo) / (hi - lo) : 0.5, rgbSpeed, 0);
          c = rgbSpeed;
        }
        pathCol.set(c, 6 * a);
        pathCol.set(c, 6 * a + 3);
        a++;
      }
    }
    viewer.setLayer('spray.path', { kind: 'lines', positions: pathPos, colors: pathCol });
    viewer.setLayer('spray.links', { kind: 'lines', positions: linkPos, color: KINDS[LINK].color, dashed: true,
      dashSize: request.params.spacing / 4 });
  }

  /**
   * Worst regions as wire balls (three great circles) around their positions, `highlight`
   * (an index, or null) in white: whichever way the surface faces, one ring shows. Radius R/2,
   * or 1/50 of the sprayed area's box diagonal when that is larger, so they show on a wing.
   */
  #drawHotspots(highlight) {
    const viewer = this.#shell.viewer;
    const { result, request } = this.#plan;
    const spots = result.hotspots ?? [];
    if (!viewer) return;
    if (spots.length === 0) {
      viewer.removeLayer('spray.hotspots');
      return;
    }
    this.#sprayedDiagonal ??= boxDiagonal(result.samplePositions);
    const r = Math.max((request.params.standoff * Math.tan(request.params.coneAngle / 2)) / 2, this.#sprayedDiagonal / 50);
    const positions = new Float32Array(spots.length * 3 * RING_SEGMENTS * 6);
    const colors = new Uint8Array(positions.length);
    const base = hexRgb(HOTSPOT_COLOR);
    const lit = hexRgb(HOTSPOT_HIGHLIGHT);
    let o = 0;
    spots.forEach((spot, k) => {
      const [x, y, z] = spot.position;
      const c = k === highlight ? lit : base;
      const scale = k === highlight ? 1.4 : 1;
      for (let axis = 0; axis < 3; axis++) {
        for (let j = 0; j < RING_SEGMENTS; j++) {
          for (const q of [j, j + 1]) {
            const t = (2 * Math.PI * q) / RING_SEGMENTS;
            const u = r * scale * Math.cos(t);
            const w = r * scale * Math.sin(t);
            const d = axis === 0 ? [0, u, w] : axis === 1 ? [u, 0, w] : [u, w, 0];
            positions.set([x + d[0], y + d[1], z + d[2]], o);
            colors.set(c, o);
            o += 3;
          }
        }
      }
    });
    viewer.setLayer('spray.hotspots', { kind: 'lines', positions, colors });
    this.#showLayers(this.#shell.activeTool === this);
  }

  #drawHeat() {
    const { result } = this.#plan;
    const v = this.#read().values;
    const um = this.#umPerUnit;
    const t = result.sampleThickness;
    const colors = new Uint8Array(3 * t.length);
    const { lo, hi } = this.#heatRange();
    const classRgb = CLASSES.map((c) => hexRgb(c.color));
    for (let i = 0; i < t.length; i++) {
      const x = t[i] * um;
      if (v.colors === 'classes') {
        colors.set(classRgb[x < v.target - v.tolerance ? 0 : x > v.target + v.tolerance ? 2 : 1], 3 * i);
      } else {
        viridisInto(hi > lo ? (x - lo) / (hi - lo) : 0.5, colors, 3 * i);
      }
    }
    this.#shell.viewer.setLayer('spray.heat', {
      kind: 'surface', positions: result.samplePositions, indices: result.sampleTriangles, colors,
    });
  }

  /** Colour scale range in µm: the whole patch's min to max. */
  #heatRange() {
    const q = this.#plan.result.quality.whole;
    return { lo: q.min * this.#umPerUnit, hi: q.max * this.#umPerUnit };
  }

  #showLayers(visible) {
    const v = this.#read().values;
    const viewer = this.#shell.viewer;
    if (!viewer) return;
    viewer.setLayerVisible('spray.path', visible && v.showPath);
    viewer.setLayerVisible('spray.links', visible && v.showPath);
    viewer.setLayerVisible('spray.axis', visible && v.showAxis);
    viewer.setLayerVisible('spray.heat', visible && v.showHeat);
    viewer.setLayerVisible('spray.hotspots', visible && v.showHotspots);
  }

  // ---------------------------------------------------------------- figures

  #renderResults() {
    const shell = this.#shell;
    const { result, request } = this.#plan;
    const v = this.#read().values;
    const mm = shell.mmPerUnit;
    const um = this.#umPerUnit;
    const what = request.patchId === null ? 'Whole mesh' : `Patch ${request.patchId}`;
    const asked = request.values;
    const speedText = result.speedOptimised
      ? `gun speed optimised along the passes, ${speedRangeText(result.minSpeed * mm, result.maxSpeed * mm)} commanded ` +
        `(limits ${num(asked.minSpeed, 4)}–${num(asked.maxSpeed, 4)} mm/s)`
      : `gun at ${speedRangeText(result.minSpeed * mm, result.maxSpeed * mm)}` +
        (asked.scaleSpeed && request.params.targetThickness ? ' (set for the target)' : '');
    const best = result.directions.length > 0;
    const direction = `passes ${directionText(result.rasterAngle)}` +
      (best ? ` (the best of ${result.directions.length} directions tried, see the table)` : '');
    $('spray-summary').textContent = `${what}: ${integer.format(result.passCount)} passes ${num(result.spacing * mm, 3)} mm apart, ` +
      `${direction}; ${speedText}. Cycle time ${timeText(result.cycleTime)}: spray path ${num((result.sprayLength * mm) / 1000, 3)} m, ` +
      `whole path ${num((result.pathLength * mm) / 1000, 3)} m with the links. ` +
      (result.passCount > MAX_PASSES_SHOWN && !v.showPath ? 'The path is hidden so the thickness shows: tick Path below. ' : '') +
      `Thickness evaluated every ${num(result.resolution * mm, 3)} mm` +
      (result.coarsened ? ' (coarsened on this large patch to keep planning quick).' : '.') +
      coarseWarning(result.resolution, request.params, mm);

    const q = result.quality;
    const rows = [
      ['Mean thickness', (x) => `${num(x.mean * um, 3)} µm`, 'Area-weighted mean of the predicted dry-film thickness'],
      ['Std. deviation E', (x) => `${num(x.stdDev * um, 3)} µm`, 'Area-weighted standard deviation of the thickness'],
      ['Error δ', (x) => `${num(x.error * 100, 3)} %`, 'Largest |thickness − mean| / mean'],
      ['Thinnest', (x) => `${num(x.min * um, 3)} µm`],
      ['Thickest', (x) => `${num(x.max * um, 3)} µm`],
      ['Area', (x) => `${num(x.area, 3)} ${shell.unitOf.area()}`],
    ];
    $('spray-quality').tBodies[0].replaceChildren(...rows.map(([label, f, title]) => {
      const row = document.createElement('tr');
      row.append(Object.assign(document.createElement('th'), { scope: 'row', textContent: label, title: title ?? '' }),
        Object.assign(document.createElement('td'), { textContent: f(q.interior) }),
        Object.assign(document.createElement('td'), { textContent: f(q.whole) }));
      return row;
    }));
    const verdict = $('spray-verdict');
    const messages = q.messages ?? [];
    if (request.params.quality) {
      const met = q.limitsMet;
      const limits = `δ ≤ ${num(asked.maxError, 3)} %, E ≤ ${num(asked.maxStdDev, 3)} µm`;
      verdict.className = `verdict ${met ? 'ok' : 'bad'}`;
      if (met) {
        verdict.textContent = `Meets the limits (${limits}) at the widest spacing found: δ ${num(q.interior.error * 100, 3)} %, ` +
          `E ${num(q.interior.stdDev * um, 3)} µm inside the patch.`;
      } else {
        // Which limit fails, in the painter's units (the core's message has file units).
        const failing = [];
        if (q.interior.error > request.params.quality.maxError) {
          failing.push(`error δ is ${num(q.interior.error * 100, 3)} % (limit ${num(asked.maxError, 3)} %)`);
        }
        if (q.interior.stdDev > request.params.quality.maxStdDev) {
          failing.push(`std. deviation E is ${num(q.interior.stdDev * um, 3)} µm (limit ${num(asked.maxStdDev, 3)} µm)`);
        }
        const margin = messages.map((m) => /within (\d+(?:\.\d+)?) % of the best/.exec(m)).find(Boolean);
        verdict.textContent = `Limits not met (${limits}): no spacing tried meets them. Here ${failing.join(' and ') || 'a limit fails'}. ` +
          `This plan uses ${num(result.spacing * mm, 3)} mm, the widest spacing` +
          (margin ? ` within ${margin[1]} % of the best figures seen.` : ' near the best figures seen.');
      }
    } else {
      verdict.className = 'verdict';
      verdict.textContent = 'Spacing as typed (no search).';
    }
    $('spray-notes').replaceChildren(...plannerNotes(messages, asked, q.interior.mean * um)
      .map((m) => Object.assign(document.createElement('li'), { textContent: m })));
    this.#renderHotspots();
    this.#renderDirections();
    // Classes against target ± tolerance, share of evaluation points.
    const t = result.sampleThickness;
    const counts = [0, 0, 0];
    for (let i = 0; i < t.length; i++) {
      const x = t[i] * um;
      counts[x < v.target - v.tolerance ? 0 : x > v.target + v.tolerance ? 2 : 1]++;
    }
    this.#classShares = counts.map((c) => (t.length ? (100 * c) / t.length : 0));
    renderChart($('spray-chart'), result.iterations, result.spacing, request.params.quality, mm, um);
    const coarse = result.iterations.some((it) => !it.full);
    $('spray-chart-key').textContent = (coarse ? 'Filled: full resolution (the choice rests on these); hollow: coarse screening. ' : '') +
      (request.params.quality ? '▲ under a spacing: it meets the limits; dashed: the limits.' : '');
    $('spray-figures').hidden = false;
    for (const b of this.#results.querySelectorAll('[data-format]')) b.disabled = false;
    this.#renderLegend();
  }

  #classShares = [0, 0, 0];
  #sprayedDiagonal = null; // of the plan on screen, measured once

  /** The worst regions, numbered as ringed on the map: deviation from the mean and cause. */
  #renderHotspots() {
    const spots = this.#plan.result.hotspots ?? [];
    $('spray-hotspots').replaceChildren(...spots.map((h, k) => {
      const li = document.createElement('li');
      li.dataset.index = String(k);
      li.tabIndex = 0;
      li.textContent = `${h.deviation >= 0 ? 'Thick' : 'Thin'} by ${num(Math.abs(h.deviation) * 100, 3)} % ${CAUSES[h.cause] ?? h.cause}`;
      li.title = `${h.cause}: ${h.deviation >= 0 ? '+' : '−'}${num(Math.abs(h.deviation) * 100, 3)} % from the interior mean`;
      return li;
    }));
    $('spray-hotspots-wrap').hidden = spots.length === 0;
  }

  /** With "best of": each direction tried at the chosen spacing, the one used marked. */
  #renderDirections() {
    const { result } = this.#plan;
    const um = this.#umPerUnit;
    const trials = result.directions ?? [];
    $('spray-directions').tBodies[0].replaceChildren(...trials.map((d) => {
      const row = document.createElement('tr');
      if (d.chosen) row.className = 'chosen';
      const fits = Number.isFinite(d.error);
      const cells = [
        shortDirection(d.rasterAngle) + (d.chosen ? ' ✓ used' : ''),
        fits ? `${num(d.error * 100, 3)} %` : 'does not fit',
        fits ? `${num(d.stdDev * um, 3)} µm` : '–',
        fits ? timeText(d.cycleTime) : '–',
      ];
      row.append(Object.assign(document.createElement('th'), { scope: 'row', textContent: cells[0] }),
        ...cells.slice(1).map((c) => Object.assign(document.createElement('td'), { textContent: c })));
      return row;
    }));
    $('spray-directions-wrap').hidden = trials.length === 0;
  }

  /** The legend over the view: the colour scale in µm (or the classes) and the path kinds. */
  #renderLegend() {
    const v = this.#read().values;
    const overlay = this.#overlay;
    // Built through the DOM: the page's CSP forbids inline style attributes.
    const el = (tag, className, text) => Object.assign(document.createElement(tag), { className: className ?? '', textContent: text ?? '' });
    const swatch = (color, className = 'legend-swatch') => {
      const span = el('span', className);
      if (className === 'legend-swatch') span.style.backgroundColor = color;
      else span.style.borderColor = color;
      return span;
    };
    const nodes = [];
    if (v.showHeat && this.#plan) {
      const lowEdge = v.target - v.tolerance;
      const highEdge = v.target + v.tolerance;
      if (v.colors === 'classes') {
        nodes.push(el('p', 'legend-title', 'Coating thickness, µm (share of evaluation points)'));
        const list = el('ul', 'legend-list');
        const ranges = [`below ${num(lowEdge, 3)}`, `${num(lowEdge, 3)}–${num(highEdge, 3)}`, `above ${num(highEdge, 3)}`];
        CLASSES.forEach((c, i) => {
          const li = el('li');
          li.append(swatch(c.color), `${c.label}: ${ranges[i]} (${num(this.#classShares[i], 3)} %)`);
          list.append(li);
        });
        nodes.push(list);
      } else {
        const { lo, hi } = this.#heatRange();
        nodes.push(el('p', 'legend-title', 'Coating thickness, µm'));
        const bar = el('div', 'legend-bar');
        bar.style.backgroundImage = gradient(VIRIDIS);
        // Where target ± tolerance falls on the scale.
        const pos = (x) => Math.min(100, Math.max(0, hi > lo ? (100 * (x - lo)) / (hi - lo) : 50));
        const band = el('span', 'legend-band');
        band.title = 'target ± tolerance';
        band.style.left = `${pos(lowEdge)}%`;
        band.style.width = `${Math.max(0, pos(highEdge) - pos(lowEdge))}%`;
        bar.append(band);
        const ticks = el('div', 'legend-ticks');
        ticks.append(el('span', '', num(lo, 3)), el('span', '', num((lo + hi) / 2, 3)), el('span', '', num(hi, 3)));
        const [under, inside, over] = this.#classShares;
        nodes.push(bar, ticks, el('p', 'legend-note', `Bracket: target ${num(v.target, 3)} ± ${num(v.tolerance, 3)} µm. ` +
          `Under ${num(under, 2)} %, in ${num(inside, 3)} %, over ${num(over, 2)} % of the points.`));
      }
    }
    const spots = this.#plan?.result.hotspots ?? [];
    if (v.showHotspots && spots.length) {
      const li = el('li');
      li.append(swatch(HOTSPOT_COLOR, 'legend-ring'), `Worst regions (${spots.length}, listed with the figures)`);
      const list = el('ul', 'legend-list');
      list.append(li);
      nodes.push(list);
    }
    const bySpeed = $('spray-pathColors').value === 'speed';
    if (v.showPath && this.#plan && bySpeed) {
      const mm = this.#shell.mmPerUnit;
      const { lo, hi } = this.#speedRange();
      const asked = this.#plan.request.values;
      const box = el('div', 'speed-legend');
      box.id = 'spray-speed-legend';
      box.append(el('p', 'legend-title', this.#plan.result.speedOptimised ? 'Gun speed, mm/s (optimised)' : 'Gun speed, mm/s'));
      const bar = el('div', 'legend-bar');
      bar.style.backgroundImage = hi > lo * (1 + 1e-9) ? gradient(TURBO) : 'none';
      if (!(hi > lo * (1 + 1e-9))) bar.style.backgroundColor = TURBO[(TURBO.length - 1) / 2];
      const ticks = el('div', 'legend-ticks');
      const lowTick = el('span', 'speed-min', num(lo * mm, 3));
      const highTick = el('span', 'speed-max', num(hi * mm, 3));
      lowTick.dataset.value = String(lo * mm);
      highTick.dataset.value = String(hi * mm);
      ticks.append(lowTick, el('span', '', num(((lo + hi) / 2) * mm, 3)), highTick);
      const link = el('li');
      link.append(swatch(KINDS[LINK].color, 'legend-line dashed'), KINDS[LINK].label);
      const list = el('ul', 'legend-list');
      list.append(link);
      box.append(bar, ticks, el('p', 'legend-note', `Commanded on the gun-on moves; limits ${num(asked.minSpeed, 4)}–${num(asked.maxSpeed, 4)} mm/s.`), list);
      nodes.push(box);
    } else if (v.showPath && this.#plan) {
      const list = el('ul', 'legend-list kinds');
      for (const k of KINDS) {
        const li = el('li');
        li.append(swatch(k.color, `legend-line${k.dashed ? ' dashed' : ''}`), k.label);
        list.append(li);
      }
      nodes.push(list);
    }
    overlay.replaceChildren(...nodes);
    overlay.hidden = nodes.length === 0;
  }

  // ---------------------------------------------------------------- exports

  #export(format) {
    const shell = this.#shell;
    const plan = this.#plan;
    if (!plan) return;
    const stem = fileStem(plan.model);
    // Robot programs are in mm; the program is named after the model (a RAPID/KRL identifier).
    // KRL allows 24 characters and the exporters append a part number (_12): keep 16.
    const name = `sp_${stem.replace(/[^A-Za-z0-9_]/g, '_')}`.slice(0, 16).replace(/_+$/, '');
    const options = { mmPerUnit: shell.mmPerUnit, name, ...cellOptions(this.#s) };
    const replan = (progress) => shell.engine.request('spray.plan', { params: plan.request.params, patchId: plan.request.patchId },
      { onProgress: progress });
    shell.enqueue(`Writing the ${format.toUpperCase()} program`, async (progress, checkpoint) => {
      // After Cancel or a failure the worker is new: give it the model and the plan again.
      if (!shell.engine.hasMesh) {
        await shell.restoreEngine(progress, checkpoint);
        await replan(progress);
      }
      let out;
      try {
        out = await shell.engine.request('spray.exportPlan', { format, options, stem }, { onProgress: progress });
      } catch (error) {
        if (error.message !== 'NO_PLAN') throw new Error(`The ${format.toUpperCase()} export failed: ${error.message}`);
        await replan(progress);
        out = await shell.engine.request('spray.exportPlan', { format, options, stem }, { onProgress: progress });
      }
      const type = out.fileName.endsWith('.zip') ? 'application/zip' : out.fileName.endsWith('.json') ? 'application/json' : 'text/plain';
      download(out.bytes, out.fileName, type);
      shell.setStatus(`Saved ${out.fileName}${out.fileCount > 1 ? ` with ${out.fileCount} files` : ''}.`);
    });
  }

  #wire() {
    const form = this.#form;
    form.addEventListener('submit', (event) => {
      event.preventDefault();
      this.plan();
    });
    form.addEventListener('input', () => {
      const r = this.#validate();
      if (!r.error) this.#save();
    });
    form.addEventListener('change', (event) => {
      if (event.target.name === 'scope') this.#renderTarget();
      if (this.#plan && ['target', 'tolerance'].includes(event.target.name)) {
        this.#drawHeat();
        this.#renderResults();
        this.#showLayers(true);
      }
    });
    $('spray-defaults-button').addEventListener('click', () => {
      for (const f of FIELDS) this.#s[P + f.key] = f.value;
      for (const f of FLAGS.filter((x) => x.group !== 'display')) this.#s[P + f.key] = f.value;
      this.#s[`${P}direction`] = DEFAULTS[`${P}direction`];
      persistSettings(this.#s);
      this.#renderForm();
    });
    const results = this.#results;
    // Pointing at (or tabbing to) a worst region in the list lights its ring on the map.
    const list = $('spray-hotspots');
    const light = (event) => {
      const li = event.target.closest?.('li[data-index]');
      if (this.#plan && li) this.#drawHotspots(Number(li.dataset.index));
    };
    const unlight = () => this.#plan && this.#drawHotspots(null);
    list.addEventListener('pointerover', light);
    list.addEventListener('focusin', light);
    list.addEventListener('pointerleave', unlight);
    list.addEventListener('focusout', unlight);
    results.addEventListener('change', (event) => {
      this.#save();
      if (!this.#plan) return;
      if (event.target.id === 'spray-colors') this.#drawHeat();
      if (event.target.id === 'spray-pathColors') this.#drawPath();
      this.#showLayers(true);
      this.#renderLegend();
    });
    for (const b of results.querySelectorAll('[data-format]')) b.addEventListener('click', () => this.#export(b.dataset.format));
  }
}

export const sprayTool = new SprayTool();
