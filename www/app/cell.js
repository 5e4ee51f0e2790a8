// The robot cell the exported programs expect, shared by every tool that writes a robot
// program (spray, drill, paths): one settings group ('cell.' keys), a block each export panel
// shows before download (what the cell must set up, in the names the programs will use) with
// the options, and the options object the exporters take. No DOM outside `mountCell`.
import { persistSettings, registerSettings } from './settings.js';

const P = 'cell.';
/** Defaults: the core's (src/toolpath/export.rs). */
const DEFAULTS = Object.freeze({
  [`${P}rapidTool`]: 'tSkinpath',
  [`${P}rapidWorkObject`]: 'wSkinpath',
  [`${P}rapidSignal`]: 'doProcess',
  [`${P}rapidConfigCheck`]: false,
  [`${P}krlOutput`]: 1,
  [`${P}krlTool`]: 1,
  [`${P}krlBase`]: 1,
  [`${P}krlUnwrapAngles`]: false,
  [`${P}approachClearanceMm`]: 50,
});

registerSettings({
  order: 9,
  defaults: DEFAULTS,
  // Only what differs from the defaults goes into the URL.
  hashKeys: (s) => Object.keys(DEFAULTS).filter((k) => s[k] !== DEFAULTS[k]),
});

const TEXT = [
  ['rapidTool', 'RAPID tool', 'PERS tooldata the moves use'],
  ['rapidWorkObject', 'RAPID work object', 'PERS wobjdata the moves use'],
  ['rapidSignal', 'RAPID process signal', 'Digital output switched with SetDO'],
];
const NUMBERS = [
  ['approachClearanceMm', 'Approach / retract', 'mm', 'Distance back along the tool axis of the joint move that starts each program part and of the retract that ends it (at least 1 mm)', 1],
  ['krlOutput', 'KRL process output $OUT[n]', '', 'Output number switched by a TRIGGER', 1],
  ['krlTool', 'KRL tool TOOL_DATA[n]', '', 'Tool number (also LOAD_DATA[n])', 1],
  ['krlBase', 'KRL base BASE_DATA[n]', '', 'Base number: the part frame', 1],
];
const FLAGS = [
  ['rapidConfigCheck', 'RAPID: keep the configuration check (ConfJ\\On, ConfL\\On)',
    'Only for a cell that replaces the [0,0,0,0] confdata placeholders with real ones; otherwise the robot stops at the first target'],
  ['krlUnwrapAngles', 'KRL: unwrapped A and C (beyond ±180°)',
    'Only for a controller known to accept them; by default A and C stay in [−180°, 180°] and B in [−90°, 90°]'],
];

/** The cell block of an export section; `id` makes the element ids unique per tool. */
export function cellHtml(id) {
  const text = TEXT.map(([key, label, title]) => `<label class="field choice" title="${title}"><span>${label}</span>` +
    `<input type="text" spellcheck="false" autocomplete="off" id="${id}-cell-${key}" data-cell="${key}"></label>`).join('');
  const numbers = NUMBERS.map(([key, label, unit, title, min]) => `<label class="field" title="${title}"><span>${label}</span>` +
    `<input type="number" step="any" min="${min}" inputmode="decimal" id="${id}-cell-${key}" data-cell="${key}"><span class="unit">${unit}</span></label>`).join('');
  const flags = FLAGS.map(([key, label, title]) => `<label class="check" title="${title}">` +
    `<input type="checkbox" id="${id}-cell-${key}" data-cell="${key}"> ${label}</label>`).join('');
  return `<div class="cell-setup" id="${id}-cell">
      <p class="hint">Before running a robot program, the cell must provide:</p>
      <ul class="cell-notes" data-cell-notes></ul>
      <details><summary>Cell names and program options</summary>${numbers}${text}${flags}</details>
    </div>`;
}

/** What the cell must provide, in the names the programs will use. */
function notes(s) {
  const v = (k) => s[P + k];
  return [
    `Process signal: RAPID switches digital output <code>${esc(v('rapidSignal'))}</code> (SetDO), KRL <code>$OUT[${v('krlOutput')}]</code> (TRIGGER); it must exist in the cell's I/O configuration.`,
    `Tool: <code>${esc(v('rapidTool'))}</code> is declared as a placeholder with the TCP at the flange, and KRL uses <code>TOOL_DATA[${v('krlTool')}]</code> / <code>LOAD_DATA[${v('krlTool')}]</code>: set the real TCP and load in the cell.`,
    `Work object: <code>${esc(v('rapidWorkObject'))}</code> (placeholder at the world origin) and <code>BASE_DATA[${v('krlBase')}]</code> are the part's frame, the frame of the model's coordinates.`,
    `Each program part starts with a joint move, process off, to a pose ${v('approachClearanceMm')} mm back along the first tool axis, from wherever the robot stands: check that the way is clear.`,
    v('rapidConfigCheck')
      ? 'RAPID keeps the configuration check: replace the [0,0,0,0] confdata before running.'
      : 'RAPID robtargets carry placeholder confdata, so the program says ConfJ\\Off and ConfL\\Off.',
  ];
}

function esc(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
}

/** Fills every cell block under `root` (default: the page) from the settings. */
export function renderCell(settings, root = document) {
  for (const input of root.querySelectorAll('[data-cell]')) {
    const value = settings[P + input.dataset.cell];
    if (input.type === 'checkbox') input.checked = value;
    else if (document.activeElement !== input) input.value = String(value);
  }
  const items = notes(settings).map((n) => `<li>${n}</li>`).join('');
  for (const list of root.querySelectorAll('[data-cell-notes]')) list.innerHTML = items;
}

/**
 * Wires the cell block under `root`: edits update the shared settings (`getSettings()`, the
 * shell's current object) and every block.
 */
export function mountCell(root, getSettings) {
  root.addEventListener('change', (event) => {
    const key = event.target.dataset?.cell;
    if (!key) return;
    const settings = getSettings();
    const el = event.target;
    const k = P + key;
    if (el.type === 'checkbox') settings[k] = el.checked;
    else if (typeof DEFAULTS[k] === 'number') {
      const n = Number(el.value);
      // Out-of-range numbers stay as typed: the exporter refuses them, naming the option.
      settings[k] = el.value.trim() !== '' && Number.isFinite(n) ? n : DEFAULTS[k];
    } else settings[k] = el.value.trim() || DEFAULTS[k];
    persistSettings(settings);
    renderCell(settings);
  });
  renderCell(getSettings(), root);
}

/** The exporters' options from the settings (merged into `{ mmPerUnit, name }`). */
export function cellOptions(settings) {
  const out = {};
  for (const key of Object.keys(DEFAULTS)) out[key.slice(P.length)] = settings[key];
  return out;
}
