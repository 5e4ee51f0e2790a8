// Patch colours, shared by the view, the patch table and the worker that fills the colour
// buffer (so this module imports nothing: workers ignore the page's import map).

/**
 * Patch colours: Okabe & Ito's colour-blind-safe set (black and grey left out), then the
 * darker colours of Paul Tol's "muted" scheme. Grey is reserved for dropped triangles.
 * Colours repeat after twelve patches; the border lines keep neighbours apart.
 */
export const PATCH_COLORS = [
  '#0072B2', '#E69F00', '#009E73', '#CC79A7', '#56B4E9', '#D55E00',
  '#F0E442', '#882255', '#44AA99', '#332288', '#999933', '#AA4499',
];
export const DROPPED_COLOR = '#A0A4A8';

/** CSS colour of a patch id (-1 = dropped). */
export function patchColor(id) {
  return id < 0 ? DROPPED_COLOR : PATCH_COLORS[id % PATCH_COLORS.length];
}

/**
 * The vertex-colour bytes of a patch id: the sRGB palette colour in linear values (the
 * renderer reads vertex colours as linear and encodes back to sRGB), as three.js's
 * Color.set would convert it, times 255.
 */
export function patchColorBytes(id) {
  const hex = parseInt(patchColor(id).slice(1), 16);
  return [16, 8, 0].map((shift) => {
    const c = ((hex >> shift) & 255) / 255;
    const linear = c < 0.04045 ? c * 0.0773993808 : Math.pow(c * 0.9478672986 + 0.0521327014, 2.4);
    return Math.round(linear * 255);
  });
}
