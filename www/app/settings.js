// Settings: one flat object shared by the shell and the tools, saved in localStorage and
// carried in the URL hash (a link reproduces a configuration). Each tool registers its group
// of keys with defaults; keys of tools other than segmentation carry the tool's prefix
// ('spray.standoff'), so tools never collide. No DOM here.
const STORAGE_KEY = 'skinpath.settings.v1';

/** Built-in models (www/samples/, see LICENSES.md there); their up axis and unit are known. */
export const SAMPLES = [
  { id: 'bwb', name: 'Blended-wing body', file: 'bwb_4464_pygeo_ascii.stl', up: 'y', unit: 'm',
    meta: '4,464 triangles, ASCII, pyGeo (Apache-2.0)' },
  { id: 'orion', name: 'Orion capsule', file: 'orion_51736_nasa.stl', up: 'y', unit: 'ft',
    meta: '51,736 triangles, binary, NASA 3D Resources' },
];

/** Millimetres per file unit: process lengths are typed in mm, the core takes file units. */
export const MM_PER_UNIT = Object.freeze({ mm: 1, m: 1000, in: 25.4, ft: 304.8 });
export const UNIT_NAMES = Object.freeze({ mm: 'millimetres', m: 'metres', in: 'inches', ft: 'feet' });

/**
 * Groups of settings: { order, defaults, allowed: { key: [values] }, hashKeys(settings) }.
 * `order` places the group's keys in the URL hash.
 */
const groups = [];

/** Adds a group (the shell's, or a tool's); returns its defaults. */
export function registerSettings(group) {
  groups.push(group);
  groups.sort((a, b) => a.order - b.order);
  return group.defaults;
}

/** Every registered default, one flat object. */
export function allDefaults() {
  return Object.assign({}, ...groups.map((g) => g.defaults));
}

function allowedValues() {
  return Object.assign({}, ...groups.map((g) => g.allowed ?? {}));
}

/** Settings of the last visit (checked by sanitize), or {}. */
export function loadStoredSettings() {
  try {
    return JSON.parse(localStorage.getItem(STORAGE_KEY) ?? '{}') ?? {};
  } catch {
    return {}; // storage disabled or corrupt: start from the defaults
  }
}

/** Settings from a URL hash like #criterion=angle&angleThreshold=0.35&… (unknown keys ignored). */
export function settingsFromHash(hash) {
  const defaults = allDefaults();
  const out = {};
  const query = new URLSearchParams(hash.replace(/^#/, ''));
  for (const [key, value] of query) {
    if (!(key in defaults)) continue;
    if (typeof defaults[key] === 'number') {
      const n = Number(value);
      if (value.trim() !== '' && Number.isFinite(n)) out[key] = n;
    } else if (typeof defaults[key] === 'boolean') {
      if (value === 'true' || value === 'false') out[key] = value === 'true';
    } else {
      out[key] = value;
    }
  }
  return sanitize(out);
}

/** Drops values the page cannot show (a hand-edited URL must not break the page). */
export function sanitize(s) {
  const defaults = allDefaults();
  const allowed = allowedValues();
  const out = {};
  for (const [key, value] of Object.entries(s ?? {})) {
    if (!(key in defaults) || typeof value !== typeof defaults[key]) continue;
    if (typeof value === 'number' && !Number.isFinite(value)) continue;
    if (allowed[key] && !allowed[key].includes(value)) continue;
    out[key] = value;
  }
  return out;
}

/** The URL hash of some settings: each group's keys, in group order. */
export function settingsHash(s) {
  const query = new URLSearchParams();
  for (const group of groups) {
    for (const key of group.hashKeys(s)) query.set(key, String(s[key]));
  }
  return `#${query}`;
}

/** Saves the settings for the next visit and puts them in the URL, ready to share. */
export function persistSettings(settings) {
  try {
    localStorage.setItem(STORAGE_KEY, JSON.stringify(settings));
  } catch {
    // private mode or quota: the URL hash still carries the settings
  }
  const hash = settingsHash(settings);
  if (location.hash !== hash) history.replaceState(null, '', hash);
}
