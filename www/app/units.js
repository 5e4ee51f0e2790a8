// STL files carry no unit. The page keeps the unit the user chose, but when the model's size
// in that unit is implausible for an aircraft part it suggests the likely one (no paper: the
// bounds below are a judgement; the largest aircraft are under 120 m long, and no skin part
// is smaller than a millimetre).
import { MM_PER_UNIT } from './settings.js';

/** Largest plausible extent of an aircraft part, metres. */
export const MAX_PART_M = 200;
/** Smallest plausible extent of an aircraft part, metres. */
export const MIN_PART_M = 1e-3;

/** Largest bounding-box extent of a mesh report, in file units. */
export function largestExtent({ bboxMin, bboxMax }) {
  return Math.max(...[0, 1, 2].map((i) => bboxMax[i] - bboxMin[i]));
}

/**
 * null when the model's size is plausible in `unit`; otherwise { unit, size (m), suggested,
 * suggestedSize (m), tooLarge }: the plausible unit that gives the size nearest to 1 m
 * (in log scale), or suggested = null when no unit makes sense.
 */
export function unitSuggestion(report, unit) {
  const extent = largestExtent(report);
  if (!(extent > 0) || !Number.isFinite(extent)) return null;
  const metres = (u) => (extent * MM_PER_UNIT[u]) / 1000;
  const plausible = (m) => m >= MIN_PART_M && m <= MAX_PART_M;
  const size = metres(unit);
  if (plausible(size)) return null;
  let suggested = null;
  for (const u of Object.keys(MM_PER_UNIT)) {
    if (u === unit || !plausible(metres(u))) continue;
    if (suggested === null || Math.abs(Math.log10(metres(u))) < Math.abs(Math.log10(metres(suggested)))) suggested = u;
  }
  return { unit, size, suggested, suggestedSize: suggested ? metres(suggested) : null, tooLarge: size > MAX_PART_M };
}
