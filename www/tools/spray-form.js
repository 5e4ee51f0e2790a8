// Spray tool's form and result templates: the process fields in a painter's units, their
// defaults (the settings the shell keeps), and the HTML of the panel and the results area.
import { cellHtml } from '../app/cell.js';

export const P = 'spray.'; // settings key prefix

/** A painter's defaults: HVLP-like gun at 250 mm, 40° cone, 400 mm/s, 150 cm³/min, 60 % transfer. */
export const FIELDS = [
  // key, label, unit, default, min, max (exclusive bounds are checked by the core too), group
  { key: 'standoff', label: 'Standoff h', unit: 'mm', value: 250, min: 0, group: 'gun', title: 'Distance from the gun to the surface along the gun axis' },
  { key: 'coneAngle', label: 'Cone angle α', unit: '°', value: 40, min: 0, max: 180, group: 'gun', title: 'Full opening angle of the spray cone' },
  { key: 'speed', label: 'Nominal speed v', unit: 'mm/s', value: 400, min: 0, group: 'speed', title: 'The speed the passes are planned at; with optimisation, where it starts' },
  { key: 'minSpeed', label: 'Slowest gun speed', unit: 'mm/s', value: 200, min: 0, group: 'speed', title: 'No move is commanded slower (gun on)' },
  { key: 'maxSpeed', label: 'Fastest gun speed', unit: 'mm/s', value: 800, min: 0, group: 'speed', title: 'No move is commanded faster (gun on)' },
  { key: 'flowRate', label: 'Paint flow Q', unit: 'cm³/min', value: 150, min: 0, group: 'gun' },
  { key: 'efficiency', label: 'Transfer efficiency η', unit: '', value: 0.6, min: 0, max: 1, group: 'gun', title: 'Share of the paint that lands on the part (0–1)' },
  { key: 'spacing', label: 'Pass spacing b', unit: 'mm', value: 100, min: 0, group: 'path', title: 'Distance between neighbouring passes; with quality limits, where the search starts' },
  { key: 'transitionAngle', label: 'Arc above fold angle β_T', unit: '°', value: 20, min: 0, max: 180, group: 'path', title: 'Across a fold sharper than this the gun turns on an arc around the edge' },
  { key: 'rasterAngle', label: 'Turned by (typed)', unit: '°', value: 0, min: -180, max: 180, group: 'direction', title: 'Passes run along the longest extent of the patch; this turns them about its mean normal' },
  { key: 'maxError', label: 'Max. error δ_m', unit: '%', value: 15, min: 0, group: 'quality', title: 'Largest allowed |T − mean| / mean inside the patch' },
  { key: 'maxStdDev', label: 'Max. std. deviation E_m', unit: 'µm', value: 5, min: 0, group: 'quality' },
  { key: 'target', label: 'Target thickness', unit: 'µm', value: 40, min: 0, group: 'target' },
  { key: 'tolerance', label: 'Tolerance ±', unit: 'µm', value: 10, min: 0, group: 'target' },
];
export const FLAGS = [
  { key: 'optimiseSpeed', label: 'Optimise gun speed along the passes', value: true, group: 'speed', title: 'Vary the speed of each short piece of pass, within the limits, to flatten the coating' },
  { key: 'search', label: 'Search the widest spacing that meets the limits', value: true, group: 'quality' },
  { key: 'scaleSpeed', label: 'Set the gun speed so the mean reaches the target', value: true, group: 'target' },
  { key: 'showPath', label: 'Path', value: true, group: 'display' },
  { key: 'showAxis', label: 'Gun axis', value: false, group: 'display' },
  { key: 'showHeat', label: 'Thickness', value: true, group: 'display' },
  { key: 'showHotspots', label: 'Worst regions', value: true, group: 'display' },
];
/** Pass directions offered: a turn about the patch's mean normal (°), "best of", or typed. */
export const DIRECTIONS = [
  { value: 'principal', label: 'principal (0°)', degrees: 0 },
  { value: 'turn90', label: 'turned by +90°', degrees: 90 },
  { value: 'turn45', label: 'turned by +45°', degrees: 45 },
  { value: 'turnMinus45', label: 'turned by −45°', degrees: -45 },
  { value: 'best', label: 'best of these four', degrees: 0 },
  { value: 'typed', label: 'typed angle', degrees: null },
];
export const DEFAULTS = Object.freeze(Object.fromEntries([
  ...FIELDS.map((f) => [P + f.key, f.value]),
  ...FLAGS.map((f) => [P + f.key, f.value]),
  [`${P}colors`, 'thickness'],
  [`${P}scope`, 'patch'],
  [`${P}direction`, 'principal'],
]));

function fieldRow(f, prefix) {
  const title = f.title ? ` title="${f.title}"` : '';
  return `<label class="field"${title}><span>${f.label.replace(/_(\w)/, '<sub>$1</sub>')}</span>` +
    `<input type="number" name="${f.key}" id="${prefix}${f.key}" step="any" inputmode="decimal" aria-describedby="${f.group === 'speed' ? 'spray-speed-error' : 'spray-error'}">` +
    `<span class="unit">${f.unit}</span></label>`;
}
function flagRow(f, prefix) {
  const title = f.title ? ` title="${f.title}"` : '';
  return `<label class="check"${title}><input type="checkbox" name="${f.key}" id="${prefix}${f.key}"> ${f.label}</label>`;
}
const group = (g) => FIELDS.filter((f) => f.group === g).map((f) => fieldRow(f, 'spray-')).join('') +
  FLAGS.filter((f) => f.group === g).map((f) => flagRow(f, 'spray-')).join('');

export const PANEL = `
  <h2 id="spray-heading">Spray trajectory</h2>
  <form id="spray-form" novalidate>
    <fieldset class="spray-scope">
      <legend>Spray</legend>
      <label><input type="radio" name="scope" value="patch"> <span id="spray-patch-label">the selected patch</span></label>
      <label><input type="radio" name="scope" value="mesh"> the whole mesh</label>
      <p class="hint" id="spray-scope-hint">Click a patch in the view or the list to choose it.</p>
    </fieldset>
    <fieldset><legend>Gun and paint</legend>${group('gun')}</fieldset>
    <fieldset class="spray-speed"><legend>Gun speed</legend>${group('speed')}
      <p id="spray-speed-error" class="field-error" aria-live="polite"></p></fieldset>
    <fieldset><legend>Passes</legend>${group('path')}
      <label class="field choice" title="Passes run along the longest extent of the patch (principal); “best of” plans all four and keeps the better coating, ties to the shorter cycle time">
        <span>Pass direction</span><select id="spray-direction" name="direction">
        ${DIRECTIONS.map((d) => `<option value="${d.value}">${d.label}</option>`).join('')}</select></label>
      ${group('direction')}</fieldset>
    <fieldset><legend>Quality limits (inside the patch, away from its edge)</legend>${group('quality')}</fieldset>
    <fieldset><legend>Coating target</legend>${group('target')}</fieldset>
    <p id="spray-error" class="field-error" aria-live="polite"></p>
    <div class="form-actions">
      <button type="submit" id="spray-plan-button" class="primary">Plan spray</button>
      <button type="button" id="spray-defaults-button">Painter's defaults</button>
    </div>
  </form>`;

export const RESULTS = `
  <section aria-labelledby="spray-results-heading">
    <h2 id="spray-results-heading">Spray plan</h2>
    <p id="spray-summary" class="summary">No plan yet: choose a patch and press <strong>Plan spray</strong>.</p>
    <div id="spray-figures" hidden>
      <table class="quality-table" id="spray-quality">
        <thead><tr><th scope="col">Coating</th><th scope="col" title="Without a band of one spray radius along the edge, where specifications do not measure">Interior</th><th scope="col">Whole patch</th></tr></thead>
        <tbody></tbody>
      </table>
      <p id="spray-verdict" class="verdict"></p>
      <ul id="spray-notes" class="warnings" aria-label="Planner remarks"></ul>
      <div id="spray-hotspots-wrap" hidden>
        <p class="table-caption">Worst regions of the interior (ringed on the map; point at one to find it)</p>
        <ol id="spray-hotspots" class="hotspot-list"></ol>
      </div>
      <div id="spray-directions-wrap" hidden>
        <table class="quality-table" id="spray-directions">
          <caption>Pass directions tried at the chosen spacing (interior)</caption>
          <thead><tr><th scope="col">Direction</th><th scope="col">Error δ</th><th scope="col">Std. dev. E</th><th scope="col">Cycle time</th></tr></thead>
          <tbody></tbody>
        </table>
      </div>
      <div class="chart-wrap"><svg id="spray-chart" role="img" aria-label="Error and standard deviation against pass spacing"></svg>
        <p class="chart-key" id="spray-chart-key"></p></div>
      <fieldset class="display-options"><legend>Show</legend>${group('display')}
        <label class="check">Colours <select id="spray-colors" name="colors">
          <option value="thickness">thickness (µm)</option><option value="classes">under / in / over target</option></select></label>
        <label class="check">Path by <select id="spray-pathColors" name="pathColors">
          <option value="speed">gun speed</option><option value="kind">kind of move</option></select></label>
      </fieldset>
    </div>
  </section>
  <section aria-labelledby="spray-export-heading">
    <h2 id="spray-export-heading">Export the program</h2>
    <div class="export-buttons">
      <button type="button" data-format="rapid" disabled title="ABB RAPID module(s), positions in mm; several files come in one ZIP">ABB RAPID</button>
      <button type="button" data-format="krl" disabled title="KUKA KRL .src file(s), positions in mm; several files come in one ZIP">KUKA KRL</button>
      <button type="button" data-format="csv" disabled title="One row per trajectory point: position, gun axis, kind, pass">Trajectory · CSV</button>
      <button type="button" data-format="json" disabled title="The trajectory, parameters and quality figures">Trajectory · JSON</button>
    </div>
    ${cellHtml('spray')}
  </section>`;
