// Settings: their defaults, how they travel (localStorage and the URL hash) and how they
// become the parameter object of the core. No DOM here; main.js renders and reads the form.
const STORAGE_KEY = 'skinpath.settings.v1';

/** Built-in models (www/samples/, see LICENSES.md there); their up axis and unit are known. */
export const SAMPLES = [
  { id: 'bwb', name: 'Blended-wing body', file: 'bwb_4464_pygeo_ascii.stl', up: 'y', unit: 'm',
    meta: '4,464 triangles, ASCII, pyGeo (Apache-2.0)' },
  { id: 'orion', name: 'Orion capsule', file: 'orion_51736_nasa.stl', up: 'y', unit: 'ft',
    meta: '51,736 triangles, binary, NASA 3D Resources' },
];

// The paper's defaults (α 0.35 rad, θmax 1 rad, ε 10 %); spray (µm) and grind (mm) values are examples.
export const DEFAULTS = Object.freeze({
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
  unit: 'mm',
  angleUnit: 'rad',
  up: 'z',
  sample: 'bwb',
});
export const CRITERION_FIELDS = {
  spray: ['meanThickness', 'allowedDeviation', 'minThickness'],
  grind: ['indentationDepth', 'minPressureRatio', 'contactWidth'],
  angle: ['angleThreshold'],
  curvature: ['curvatureThreshold'],
};
export const COMMON_FIELDS = ['thetaMax', 'minAreaRatio'];
export const SEED_RULES = ['flattest', 'largestArea', 'lowestIndex'];
export const ANGLE_FIELDS = new Set(['angleThreshold', 'thetaMax']);
export const DISPLAY_KEYS = ['unit', 'angleUnit', 'up'];
export const FIELD_LABELS = {
  meanThickness: 'mean thickness', allowedDeviation: 'allowed deviation', minThickness: 'minimum thickness',
  indentationDepth: 'indentation depth', minPressureRatio: 'minimum pressure ratio', contactWidth: 'contact width',
  angleThreshold: 'angle threshold', curvatureThreshold: 'curvature threshold',
  thetaMax: 'maximum angle to the patch normal θmax', minAreaRatio: 'minimum patch area',
};

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
  const out = {};
  const query = new URLSearchParams(hash.replace(/^#/, ''));
  for (const [key, value] of query) {
    if (!(key in DEFAULTS)) continue;
    if (typeof DEFAULTS[key] === 'number') {
      const n = Number(value);
      if (value.trim() !== '' && Number.isFinite(n)) out[key] = n;
    } else {
      out[key] = value;
    }
  }
  return sanitize(out);
}

/** Drops values the page cannot show (a hand-edited URL must not break the page). */
export function sanitize(s) {
  const allowed = { criterion: Object.keys(CRITERION_FIELDS), unit: ['mm', 'm', 'in', 'ft'],
    angleUnit: ['rad', 'deg'], up: ['y', 'z'], sample: [...SAMPLES.map((x) => x.id), ''], seedRule: SEED_RULES };
  const out = {};
  for (const [key, value] of Object.entries(s)) {
    if (!(key in DEFAULTS) || typeof value !== typeof DEFAULTS[key]) continue;
    if (allowed[key] && !allowed[key].includes(value)) continue;
    out[key] = value;
  }
  return out;
}

/** The URL hash of some settings: the criterion's own fields, the common ones, the display. */
export function settingsHash(s) {
  const query = new URLSearchParams();
  query.set('criterion', s.criterion);
  for (const key of [...CRITERION_FIELDS[s.criterion], ...COMMON_FIELDS, 'seedRule', ...DISPLAY_KEYS]) query.set(key, String(s[key]));
  if (s.sample) query.set('sample', s.sample);
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

/** Millimetres per file unit: grinding tool lengths are typed in mm, the core takes file units. */
export const MM_PER_UNIT = Object.freeze({ mm: 1, m: 1000, in: 25.4, ft: 304.8 });

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
export function inWords(message) {
  const text = message.replace(/\b(\w+)\b/g, (word) => FIELD_LABELS[word] ?? word);
  return text.charAt(0).toUpperCase() + text.slice(1);
}
