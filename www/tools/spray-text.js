// Spray tool's words and figures: pass directions, speed ranges, cycle times, the planner's
// remarks and the warning about a coarse evaluation, for the results area.
import { num } from '../app/format.js';

/** Diagonal of the bounding box of flat xyz positions (0 when empty). */
export function boxDiagonal(xyz) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < xyz.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      if (xyz[i + k] < lo[k]) lo[k] = xyz[i + k];
      if (xyz[i + k] > hi[k]) hi[k] = xyz[i + k];
    }
  }
  return xyz.length ? Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) : 0;
}

/** A turn of the pass direction (rad) in words. */
export function directionText(rad) {
  const deg = (rad * 180) / Math.PI;
  if (Math.abs(deg) < 1e-6) return 'along the principal direction';
  return `turned by ${deg > 0 ? '+' : '−'}${num(Math.abs(deg), 3)}°`;
}

/** A turn of the pass direction (rad) for a table cell. */
export function shortDirection(rad) {
  const deg = (rad * 180) / Math.PI;
  return Math.abs(deg) < 1e-6 ? 'principal (0°)' : `${deg > 0 ? '+' : '−'}${num(Math.abs(deg), 3)}°`;
}

/** A speed range in mm/s, as one figure when it is one. */
export function speedRangeText(lo, hi) {
  return Math.abs(hi - lo) <= 1e-6 * hi ? `${num(lo, 4)} mm/s` : `${num(lo, 4)}–${num(hi, 4)} mm/s`;
}

/**
 * The planner's remarks for the results area: the failing limits are said in the verdict;
 * a target out of reach is said in the painter's units with the flow rate that would reach
 * it; the worst regions and what would help are shown as they come, capitalised.
 */
export function plannerNotes(messages, asked, meanUm) {
  const out = [];
  for (const m of messages) {
    if (!m || /^(quality limits not met|speed scaled)/i.test(m)) continue;
    if (/^targetThickness .*not reached within the speed limits/.test(m) && meanUm > 0) {
      out.push(`The target ${num(asked.target, 3)} µm is not reached within the gun speed limits ` +
        `${num(asked.minSpeed, 4)}–${num(asked.maxSpeed, 4)} mm/s: the interior mean is ${num(meanUm, 3)} µm. ` +
        `A paint flow of ${num((asked.flowRate * asked.target) / meanUm, 3)} cm³/min (now ${num(asked.flowRate, 4)}) would reach it.`);
      continue;
    }
    out.push(m.charAt(0).toUpperCase() + m.slice(1) + (/[.)]$/.test(m) ? '' : '.'));
  }
  return out;
}

/** A duration in s, min or h. */
export function timeText(seconds) {
  if (!Number.isFinite(seconds)) return '–';
  if (seconds < 90) return `${Math.round(seconds)} s`;
  if (seconds < 5400) return `${Math.round(seconds / 60)} min`;
  return `${num(seconds / 3600, 2)} h`;
}

/** A warning when the figures rest on samples more than R/2 apart (R the spray radius): the
 *  ripple between passes, about R apart, then falls between samples. */
export function coarseWarning(resolution, params, mm) {
  const radius = params.standoff * Math.tan(params.coneAngle / 2);
  if (!(resolution > 0.5 * radius)) return '';
  return ` That is more than half the spray radius (R = ${num(radius * mm, 3)} mm): the ripple between ` +
    'passes can fall between samples, so δ and E may be understated; a smaller patch (θmax in Segment) is evaluated finer.';
}
