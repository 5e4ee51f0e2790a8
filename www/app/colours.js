// Colour scales shared by the tools: viridis for fields (thickness, distance), Turbo for the
// spray gun's speed; hex stops, turned into bytes once, interpolated without allocating.

/** Viridis, sampled at 9 stops (van der Walt & Smith, CC0): perceptually even, colour-blind safe. */
export const VIRIDIS = ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962', '#addc30', '#fde725'];
/**
 * Speed scale, sampled from Turbo (Mikhailov 2019, Apache-2.0) at 11 stops: a rainbow of even
 * lightness steps, distinct from the thickness map's viridis, slow = blue to fast = red.
 */
export const TURBO = ['#30123b', '#4454c4', '#4490fe', '#1fc8de', '#29efa2', '#7eff55', '#c1f334', '#f1ca3a', '#fe922a', '#ea4f0d', '#7a0403'];
export function hexRgb(hex) {
  const n = parseInt(hex.slice(1), 16);
  return [(n >> 16) & 255, (n >> 8) & 255, n & 255];
}

/** Colour of t in [0, 1] on a scale of hex stops, written to `out[at … at + 2]` (no allocation). */
function scaleInto(stops, t, out, at) {
  const x = Math.min(Math.max(Number.isFinite(t) ? t : 0, 0), 1) * (stops.length - 1);
  const i = Math.min(Math.floor(x), stops.length - 2);
  const f = x - i;
  const a = stops[i];
  const b = stops[i + 1];
  for (let k = 0; k < 3; k++) out[at + k] = Math.round(a[k] + (b[k] - a[k]) * f);
}

let turboRgb;

/** Turbo colour of t in [0, 1] (the speed scale) written to `out[at … at + 2]`. */
export function turboInto(t, out, at) {
  turboRgb ??= TURBO.map(hexRgb);
  scaleInto(turboRgb, t, out, at);
}

/** CSS gradient of a scale's stops, left to right. */
export const gradient = (stops) => `linear-gradient(to right, ${stops.map((c, i) => `${c} ${(100 * i) / (stops.length - 1)}%`).join(', ')})`;

/** Viridis colour of t in [0, 1] as [r, g, b] bytes. */
export function viridis(t) {
  const out = [0, 0, 0];
  viridisInto(t, out, 0);
  return out;
}

let viridisRgb;

/** `viridis(t)` written to `out[at … at + 2]`, allocating nothing (for per-vertex loops). */
export function viridisInto(t, out, at) {
  viridisRgb ??= VIRIDIS.map(hexRgb);
  scaleInto(viridisRgb, t, out, at);
}
